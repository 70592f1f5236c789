#pragma once
/// @file The GeoAdhoc router (EN 302 636-4-1 V1.4.1 clause 10): SHB, TSB and GBC source and
/// receive operations, GBC forwarding, beacons, the location table and duplicate detection.
///
/// Time comes from a clock::Runtime and frames from a link::LinkLayer, so tests drive it with a
/// ManualRuntime and a TestLink. Everything runs on the caller's thread; no locking.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "common/clock/runtime.hpp"
#include "its-station/geonet/area.hpp"
#include "its-station/geonet/location_table.hpp"
#include "its-station/geonet/packet.hpp"
#include "its-station/geonet/position_provider.hpp"
#include "its-station/geonet/shared_packet_parser.hpp"
#include "its-station/link/link_layer.hpp"
#include "its-station/security/security_entity.hpp"

namespace tb::its::geonet {

using namespace std::chrono_literals;

/// The router's MIB (Annex H), with the standard's defaults.
struct RouterConfig {
  StationType station_type = StationType::kPassengerCar;
  bool manually_configured_address = false;       ///< the GN_ADDR's M bit
  bool is_mobile = true;                          ///< itsGnIsMobile
  clock::Duration beacon_interval = 3000ms;       ///< itsGnBeaconServiceRetransmitTimer
  clock::Duration beacon_max_jitter = 750ms;      ///< itsGnBeaconServiceMaxJitter
  clock::Duration location_entry_lifetime = 20s;  ///< itsGnLifetimeLocTE
  clock::Duration default_lifetime = 60s;         ///< itsGnDefaultPacketLifetime
  clock::Duration max_lifetime = 600s;            ///< itsGnMaxPacketLifetime
  std::uint8_t default_hop_limit = 10;            ///< itsGnDefaultHopLimit
  std::size_t max_sdu_size = 1398;                ///< itsGnMaxSduSize
  /// Bound on location table entries, so that a flood of made-up sources cannot exhaust
  /// memory (the standard sets none); packets from new sources beyond it are dropped.
  std::size_t max_location_entries = 10'000;
  /// Seeds the beacon jitter; 0 derives a seed from the MAC so that stations differ.
  std::uint32_t random_seed = 0;

  /// itsGnAreaForwardingAlgorithm: how a router inside a GBC's area rebroadcasts it.
  enum class AreaForwarding {
    kSimple,           ///< Annex F.2: at once
    kContentionBased,  ///< Annex F.3: after a timeout shorter the farther the sender; a copy
                       ///< heard meanwhile means someone farther on forwarded it already
  };
  /// Annex H: itsGnAreaForwardingAlgorithm defaults to CBF.
  AreaForwarding area_forwarding = AreaForwarding::kContentionBased;
  clock::Duration cbf_min_time = 1ms;         ///< itsGnCbfMinTime
  clock::Duration cbf_max_time = 100ms;       ///< itsGnCbfMaxTime
  double max_communication_range_m = 1000.0;  ///< itsGnDefaultMaxCommunicationRange
};

enum class TransportType { kSingleHopBroadcast, kTopologicallyScopedBroadcast, kGeoBroadcast };

/// GN-DATA.request (clause 7.2 / Annex J).
struct DataRequest {
  TransportType transport = TransportType::kSingleHopBroadcast;
  UpperProtocol upper_protocol = UpperProtocol::kBtpB;
  TrafficClass traffic_class;
  /// Zero means itsGnDefaultPacketLifetime.
  clock::Duration lifetime{0};
  /// TSB and GBC; zero means itsGnDefaultHopLimit. SHB always uses 1.
  std::uint8_t max_hop_limit = 0;
  /// GBC only.
  std::optional<GeoArea> area;
  /// ITS-AID (psid) of the payload's service, which the security entity signs it for (Annex J
  /// "security profile"); 0 when the service has none.
  std::uint64_t its_aid = 0;

  static DataRequest single_hop(TrafficClass tc = {}, clock::Duration lifetime = {}) {
    DataRequest r;
    r.traffic_class = tc;
    r.lifetime = lifetime;
    return r;
  }
  static DataRequest topologically_scoped(std::uint8_t max_hop_limit = 0) {
    DataRequest r;
    r.transport = TransportType::kTopologicallyScopedBroadcast;
    r.max_hop_limit = max_hop_limit;
    return r;
  }
  static DataRequest geo_broadcast(const GeoArea& area, std::uint8_t max_hop_limit = 0) {
    DataRequest r;
    r.transport = TransportType::kGeoBroadcast;
    r.area = area;
    r.max_hop_limit = max_hop_limit;
    return r;
  }
};

/// GN-DATA.confirm result codes.
enum class DataConfirm {
  kAccepted,
  kMaxSduSizeExceeded,
  kMaxLifetimeExceeded,
  kMissingArea,             ///< GBC request without a destination area
  kNoPosition,              ///< the positioning service has no fix yet
  kNoNeighbourTowardsArea,  ///< GBC from outside the area, no neighbour towards it, and
                            ///< store-carry-forward asked for (its buffer is not implemented)
  kLinkError,
};
std::string to_string(DataConfirm c);

/// GN-DATA.indication (clause 7.2 / Annex J): what the upper protocol learns with a payload.
struct DataIndication {
  UpperProtocol upper_protocol = UpperProtocol::kAny;
  PacketType packet_type = PacketType::kSingleHopBroadcast;
  GnAddress source;
  LongPositionVector source_position;
  std::optional<GeoArea> destination_area;
  TrafficClass traffic_class;
  clock::Duration remaining_lifetime{0};
  std::uint8_t remaining_hop_limit = 0;
  link::MacAddress sender{};  ///< link-layer source of the frame (the last forwarder)
  clock::WallTime rx_time{};  ///< kernel receive time of the frame
  /// A secured packet's verification outcome (kOk, or the failure a permissive station passed
  /// it up with); empty for an unsecured packet.
  std::optional<security::VerifyResult> security_report;
  std::uint64_t its_aid = 0;  ///< the psid a secured packet was signed for
  /// The signer's SSP for its_aid (Annex J "permissions"), for the service to check the
  /// content against; empty for an unsecured packet or a permission without SSP.
  std::vector<std::uint8_t> permissions;
};

using IndicationHandler =
    std::function<void(const DataIndication&, std::span<const std::uint8_t> payload)>;

/// Why a received packet was not delivered or not forwarded.
enum class DropReason {
  kWrongEtherType,
  kParseError,              ///< see the ParseError passed along
  kOwnPacket,               ///< our own packet, rebroadcast by a neighbour
  kDuplicate,               ///< Annex A: seen before (sequence number; multi-hop packets only)
  kLifetimeExpired,         ///< LT zero on reception
  kHopLimitZero,            ///< RHL 0 on reception
  kHopLimitExceedsMaximum,  ///< RHL > MHL: inconsistent, so not trusted
  kOutsideArea,             ///< GBC for an area we are not in: forwarded, not delivered
  kNotForwardedHopLimit,    ///< delivered, but RHL reached 0 so not forwarded
  kNoForwardingNeighbour,   ///< local optimum with store-carry-forward (no buffer for it)
  kForwardLinkError,
  kContentionLost,     ///< CBF: another router rebroadcast it first, so we do not
  kLocationTableFull,  ///< a new source while max_location_entries live entries exist
  kSecurity,           ///< the security entity refused it (its verifier counts the reason)
  kUnsecured,          ///< a station in mode signed: an unsecured packet (beacons too)
  kCount
};
std::string to_string(DropReason r);

struct DropEvent {
  DropReason reason;
  std::optional<ParseError> parse_error;
};
using DropHook = std::function<void(const DropEvent&)>;

struct RouterStats {
  std::uint64_t received = 0;
  std::uint64_t delivered = 0;
  std::uint64_t sent = 0;  ///< originated packets, beacons included
  std::uint64_t beacons_sent = 0;
  /// Beacons sent unsigned by a securing router whose AT lacks GN-MGMT (an older test PKI).
  std::uint64_t beacons_unsigned = 0;
  std::uint64_t forwarded = 0;
  std::uint64_t cbf_buffered = 0;  ///< GBCs that entered contention
  std::array<std::uint64_t, static_cast<std::size_t>(DropReason::kCount)> drops{};
  std::uint64_t dropped(DropReason r) const { return drops[static_cast<std::size_t>(r)]; }
};

class Router {
 public:
  /// @throws std::invalid_argument for a configuration that cannot work (non-positive beacon
  /// interval or entry lifetime, hop limit 0, default lifetime outside (0, max lifetime]).
  Router(clock::Runtime& runtime, link::LinkLayer& link, const PositionProvider& position,
         RouterConfig config = {});
  ~Router();
  Router(const Router&) = delete;
  Router& operator=(const Router&) = delete;

  /// GN-DATA.request: originates a packet carrying @p payload (the BTP header and data).
  DataConfirm request(const DataRequest& request, std::span<const std::uint8_t> payload);

  void set_indication_handler(IndicationHandler h) { indication_ = std::move(h); }
  void set_drop_hook(DropHook h) { drop_hook_ = std::move(h); }
  /// Signs what the station sends, beacons included, and verifies what it receives (EN 302
  /// 636-4-1 10.3.x "if security is enabled"); null or mode none: unsecured packets only, as
  /// without security. A secured packet that is forwarded goes on as it was received: only the
  /// basic header (remaining hop limit) changes, the signed part does not (clause 9.3).
  void set_security(security::SecurityEntity* entity) { security_ = entity; }
  /// Parse received frames through @p parser, shared with the other routers of this thread that
  /// hear the same frames (station-host): one parse per frame for all of them.
  /// Its location table then caches its entries in the parser's SenderIndex. Before the first
  /// frame.
  void set_shared_parser(SharedPacketParser* parser) {
    shared_parser_ = parser;
    if (parser != nullptr)
      table_.share_sender_index(parser->senders());
  }

  /// The receive path; the constructor binds it to the link. Public so that a caller holding
  /// frames from elsewhere (a pcap, a fuzzer) can feed them.
  void on_frame(const link::ReceivedFrame& frame);

  const GnAddress& address() const { return address_; }
  const LocationTable& location_table() const { return table_; }
  const RouterStats& stats() const { return stats_; }
  /// The long position vector the router would send now, if it has a position.
  std::optional<LongPositionVector> ego_position_vector() const;

 private:
  void drop(DropReason reason, std::optional<ParseError> pe = std::nullopt);
  clock::Duration jitter();
  void schedule_beacon(clock::Duration delay);
  void on_beacon_timer();
  bool send_frame(const link::MacAddress& to, std::span<const std::uint8_t> bytes);
  /// Annex E.2: the neighbour to unicast to, broadcast at a local optimum, or nullopt where
  /// the standard would buffer the packet (store-carry-forward, not implemented).
  std::optional<link::MacAddress> greedy_next_hop(const GeoArea& area, const GeoPoint& ego,
                                                  TrafficClass tc) const;
  /// Annex F.3: buffers the packet for a timeout that shrinks with the sender's distance.
  void contend(const Packet& packet, std::span<const std::uint8_t> bytes,
               const link::MacAddress& sender, std::uint64_t key);
  void forward(const Packet& packet, std::span<const std::uint8_t> bytes,
               const std::optional<GeoArea>& area, bool inside);
  /// The octets to forward of a received packet: the secured packet as received when it came
  /// secured, else the packet without link padding.
  std::span<const std::uint8_t> as_received(const Packet& packet,
                                            std::span<const std::uint8_t> bytes) const;
  /// Wraps the packet of @p n octets in tx_ into a secured packet signed for @p its_aid;
  /// returns its new length, or 0 when it no longer fits a frame.
  std::size_t secure(std::uint64_t its_aid, std::size_t n, const LongPositionVector& epv);
  void deliver(const Packet& packet, const link::ReceivedFrame& frame,
               clock::Duration remaining_lifetime);

  clock::Runtime& runtime_;
  link::LinkLayer& link_;
  const PositionProvider& position_;
  RouterConfig config_;
  GnAddress address_;
  LocationTable table_;
  std::uint16_t sequence_number_ = 0;
  std::minstd_rand rng_;
  clock::TimerId beacon_timer_ = 0;
  clock::SteadyTime next_purge_{};
  struct CbfEntry {
    clock::TimerId timer;
    std::vector<std::uint8_t> packet;  ///< as it will be sent, RHL already decremented
  };
  /// Packets contending for rebroadcast, by source MID key and sequence number.
  std::map<std::pair<std::uint64_t, std::uint16_t>, CbfEntry> cbf_buffer_;
  IndicationHandler indication_;
  DropHook drop_hook_;
  RouterStats stats_;
  std::array<std::uint8_t, link::kMaxPayload> tx_{};
  /// Secured packets: the entity; while a packet unwrapped from one goes through on_frame(),
  /// its outcome and the secured packet as received (basic header onwards), which forwarding
  /// re-sends.
  void on_secured_frame(const link::ReceivedFrame& frame);
  void on_unwrapped(const security::SecuredIndication& o, const link::ReceivedFrame& secured);
  bool security_on() const {
    return security_ != nullptr && security_->mode() != security::SecurityMode::kNone;
  }
  security::SecurityEntity* security_ = nullptr;
  SharedPacketParser* shared_parser_ = nullptr;
  const security::SecuredIndication* unwrapped_ = nullptr;
  std::span<const std::uint8_t> secured_frame_;
  /// Frames whose secured packet the entity holds (signer not known yet), by the ticket they
  /// were given with: when the entity releases one, it goes on with its own basic header,
  /// sender and receive time. Bounded by the entity's hold (it answers every ticket).
  struct HeldFrame {
    link::ReceivedFrame frame;
    std::vector<std::uint8_t> payload;
  };
  std::map<std::uint64_t, HeldFrame> held_frames_;
  std::uint64_t next_ticket_ = 0;
};

}  // namespace tb::its::geonet
