#pragma once
/// @file The BTP entity (EN 302 636-5-1 clause 6/8): sends BTP-A/B over the GN router and hands
/// received payloads to the handler registered for their destination port.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>

#include "its-station/btp/header.hpp"
#include "its-station/geonet/router.hpp"

namespace tb::its::btp {

/// BTP-Data.indication: the ports and the GN indication data.
struct Indication {
  geonet::UpperProtocol type = geonet::UpperProtocol::kBtpB;
  std::uint16_t destination_port = 0;
  std::optional<std::uint16_t> source_port;            ///< BTP-A only
  std::optional<std::uint16_t> destination_port_info;  ///< BTP-B only
  const geonet::DataIndication* gn = nullptr;          ///< valid during the handler call
};

using PortHandler = std::function<void(const Indication&, std::span<const std::uint8_t> payload)>;

enum class DropReason {
  kNotBtp,           ///< GN next header is neither BTP-A nor BTP-B
  kTruncatedHeader,  ///< fewer than 4 bytes
  kNoPortHandler,    ///< nobody listens on the destination port
  kItsAidMismatch,   ///< a secured packet signed for another ITS-AID than the port's service
  kCount
};
std::string to_string(DropReason r);

/// The ITS-AID (TS 102 965) of the service on a well-known port (TS 103 248), 0 for others.
std::uint64_t its_aid_of(std::uint16_t port);

struct DispatcherStats {
  std::uint64_t delivered = 0;
  std::array<std::uint64_t, static_cast<std::size_t>(DropReason::kCount)> drops{};
  std::uint64_t dropped(DropReason r) const { return drops[static_cast<std::size_t>(r)]; }
};

class Dispatcher {
 public:
  /// Installs itself as @p router's indication handler; destroy it before the router.
  explicit Dispatcher(geonet::Router& router);
  ~Dispatcher();
  Dispatcher(const Dispatcher&) = delete;
  Dispatcher& operator=(const Dispatcher&) = delete;

  /// Returns false if @p port already has a handler.
  bool register_port(std::uint16_t port, PortHandler handler);
  void unregister_port(std::uint16_t port);

  /// BTP-B: non-interactive, e.g. CAM (SHB, port 2001) and DENM (GBC, port 2002).
  geonet::DataConfirm send_b(geonet::DataRequest gn, std::uint16_t destination_port,
                             std::uint16_t destination_port_info,
                             std::span<const std::uint8_t> payload);
  /// BTP-A: interactive, with the sender's port for replies.
  geonet::DataConfirm send_a(geonet::DataRequest gn, std::uint16_t destination_port,
                             std::uint16_t source_port, std::span<const std::uint8_t> payload);

  /// The GN-DATA.indication entry point (bound to the router by the constructor).
  void on_indication(const geonet::DataIndication& gn, std::span<const std::uint8_t> bytes);

  void set_drop_hook(std::function<void(DropReason)> hook) { drop_hook_ = std::move(hook); }
  const DispatcherStats& stats() const { return stats_; }

 private:
  void drop(DropReason r);

  geonet::Router& router_;
  std::unordered_map<std::uint16_t, PortHandler> handlers_;
  std::function<void(DropReason)> drop_hook_;
  DispatcherStats stats_;
  std::array<std::uint8_t, link::kMaxPayload> tx_{};
};

}  // namespace tb::its::btp
