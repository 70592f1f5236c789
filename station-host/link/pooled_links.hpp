#pragma once
/// @file The pooled stations' links: one interface of the host shared by all its stations.
///
/// Each station gets a link::LinkLayer with its own MAC address (02:00 + its StationID, as the
/// medium attributes frames by source MAC). What the host reads from its interface is handed
/// out by the contract's rule (shared DESIGN.md, "station-host on its wlan0"):
///  * a plain GeoNetworking frame (0x8947) goes to every own station except its sender (the
///    kernel bridge delivers every frame to every port), or to the one station a unicast
///    destination names;
///  * a pooled delivery (0x88B5, TBPD) hands its inner frame to exactly the listed own stations;
///  * when the medium forwards in the kernel, the bridge never hands a port's frame back to it,
///    so the host loops its stations' transmissions back to its other stations itself.
/// No sockets here: the host's packet socket (host_socket.hpp) feeds on_frame() and takes the
/// frames send() builds; tests inject both.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "common/clock/clock.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::host {

/// The MAC address a station sends with: locally administered, unicast, 02:00 then the
/// StationID big-endian (radio-medium's station_mac(), the contract's rule).
its::link::MacAddress pooled_station_mac(std::uint32_t station_id);

/// Where the links' outgoing frames go: the host's packet socket in the program.
class FrameOutput {
 public:
  virtual ~FrameOutput() = default;
  /// Sends one whole Ethernet frame; an empty error_code means the kernel took it.
  virtual std::error_code send_frame(std::span<const std::uint8_t> frame) = 0;
};

struct DemuxCounters {
  std::uint64_t frames = 0;             ///< frames read from the interface
  std::uint64_t plain = 0;              ///< plain GN frames handed out
  std::uint64_t pooled = 0;             ///< TBPD frames handed out
  std::uint64_t malformed_pooled = 0;   ///< TBPD frames dropped: bad head or inner frame
  std::uint64_t foreign_receivers = 0;  ///< TBPD receiver ids that are not this host's
  std::uint64_t not_for_us = 0;         ///< unicast to no own station, or another ethertype
  std::uint64_t deliveries = 0;         ///< frames handed to a station (one per receiver)
  std::uint64_t looped_back = 0;        ///< own transmissions handed to the other own stations
  std::uint64_t sent = 0;
  std::uint64_t send_errors = 0;
};

class PooledLinks {
 public:
  /// @p loop_back: the medium forwards in the kernel (see above). @p output must outlive this.
  /// @p request_flush is called (once until flush() runs) when looped-back frames wait: the
  /// program posts flush() to its event loop, so a station's send() never re-enters another
  /// station's stack from inside it.
  PooledLinks(FrameOutput& output, const clock::Clock& clock, bool loop_back,
              std::function<void()> request_flush);
  ~PooledLinks();
  PooledLinks(const PooledLinks&) = delete;
  PooledLinks& operator=(const PooledLinks&) = delete;

  /// The link of station @p station_id, made on first call. It lives as long as this object.
  its::link::LinkLayer& link(std::uint32_t station_id);

  /// One whole Ethernet frame read from the interface at @p rx_time (the kernel's stamp).
  void on_frame(std::span<const std::uint8_t> frame, clock::WallTime rx_time);
  /// Hands the waiting looped-back frames to their receivers.
  void flush();

  const DemuxCounters& counters() const { return counters_; }
  std::size_t size() const { return stations_.size(); }

 private:
  class StationLink;

  std::error_code send(StationLink& from, const its::link::MacAddress& destination,
                       std::uint16_t ethertype, std::span<const std::uint8_t> payload);
  /// Hands a GN frame to the own stations it is for, @p except excluded.
  void deliver_plain(const its::link::ReceivedFrame& frame, const StationLink* except);
  StationLink* find(const its::link::MacAddress& mac) const;
  StationLink* find(std::uint32_t station_id) const;

  FrameOutput& output_;
  const clock::Clock& clock_;
  bool loop_back_;
  std::function<void()> request_flush_;
  std::unordered_map<std::uint32_t, std::unique_ptr<StationLink>> stations_;
  std::vector<StationLink*> order_;  ///< in the order they were added: delivery order
  std::vector<std::uint8_t> tx_buffer_;
  struct Pending {
    std::uint32_t sender = 0;
    std::vector<std::uint8_t> frame;
    clock::WallTime time;
  };
  std::vector<Pending> pending_;
  std::vector<Pending> flushing_;
  bool flush_requested_ = false;
  DemuxCounters counters_;
};

}  // namespace tb::host
