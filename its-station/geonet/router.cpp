#include "its-station/geonet/router.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/geodesy/local_frame.hpp"

namespace tb::its::geonet {

std::string to_string(DataConfirm c) {
  switch (c) {
    case DataConfirm::kAccepted:
      return "accepted";
    case DataConfirm::kMaxSduSizeExceeded:
      return "payload exceeds itsGnMaxSduSize";
    case DataConfirm::kMaxLifetimeExceeded:
      return "lifetime exceeds itsGnMaxPacketLifetime";
    case DataConfirm::kMissingArea:
      return "GeoBroadcast request without a destination area";
    case DataConfirm::kNoPosition:
      return "no ego position yet";
    case DataConfirm::kNoNeighbourTowardsArea:
      return "outside the area and no neighbour closer to it";
    case DataConfirm::kLinkError:
      return "link layer refused the frame";
  }
  return "unknown";
}

std::string to_string(DropReason r) {
  switch (r) {
    case DropReason::kWrongEtherType:
      return "not a GeoNetworking ethertype";
    case DropReason::kParseError:
      return "malformed packet";
    case DropReason::kOwnPacket:
      return "own packet";
    case DropReason::kDuplicate:
      return "duplicate packet";
    case DropReason::kLifetimeExpired:
      return "packet lifetime expired";
    case DropReason::kHopLimitZero:
      return "remaining hop limit is 0";
    case DropReason::kHopLimitExceedsMaximum:
      return "remaining hop limit exceeds maximum hop limit";
    case DropReason::kOutsideArea:
      return "outside the destination area";
    case DropReason::kNotForwardedHopLimit:
      return "not forwarded: hop limit reached";
    case DropReason::kNoForwardingNeighbour:
      return "not forwarded: no neighbour towards the area";
    case DropReason::kForwardLinkError:
      return "not forwarded: link error";
    case DropReason::kContentionLost:
      return "not forwarded: another router rebroadcast it first";
    case DropReason::kLocationTableFull:
      return "location table full";
    case DropReason::kSecurity:
      return "refused by security";
    case DropReason::kUnsecured:
      return "unsecured packet at a signing station";
    case DropReason::kCount:
      break;
  }
  return "unknown";
}

namespace {

std::uint32_t seed_from(const link::MacAddress& mac) {
  std::uint32_t seed = 0x9e3779b9u;
  for (const auto b : mac)
    seed = (seed ^ b) * 0x01000193u;
  return seed == 0 ? 1 : seed;
}

PacketType gbc_type(AreaShape shape) {
  switch (shape) {
    case AreaShape::kRectangle:
      return PacketType::kGeoBroadcastRectangle;
    case AreaShape::kEllipse:
      return PacketType::kGeoBroadcastEllipse;
    case AreaShape::kCircle:
      break;
  }
  return PacketType::kGeoBroadcastCircle;
}

}  // namespace

Router::Router(clock::Runtime& runtime, link::LinkLayer& link, const PositionProvider& position,
               RouterConfig config)
    : runtime_(runtime),
      link_(link),
      position_(position),
      config_(config),
      address_{config.manually_configured_address, config.station_type, link.address()},
      table_(config.location_entry_lifetime),
      rng_(config.random_seed != 0 ? config.random_seed : seed_from(link.address())) {
  // A program's configuration mistake, caught where the router is made (the program's edge).
  if (config_.beacon_interval <= clock::Duration::zero())
    throw std::invalid_argument("GN router: beacon interval must be positive");
  if (config_.beacon_max_jitter < clock::Duration::zero())
    throw std::invalid_argument("GN router: beacon jitter must not be negative");
  if (config_.location_entry_lifetime <= clock::Duration::zero())
    throw std::invalid_argument("GN router: location table entry lifetime must be positive");
  if (config_.cbf_min_time <= clock::Duration::zero() ||
      config_.cbf_max_time < config_.cbf_min_time || config_.max_communication_range_m <= 0.0)
    throw std::invalid_argument("GN router: need 0 < CBF min time <= CBF max time, range > 0");
  if (config_.max_location_entries == 0)
    throw std::invalid_argument("GN router: the location table must hold at least one entry");
  if (config_.default_hop_limit == 0)
    throw std::invalid_argument("GN router: default hop limit must be at least 1");
  if (config_.default_lifetime <= clock::Duration::zero() ||
      config_.default_lifetime > config_.max_lifetime)
    throw std::invalid_argument("GN router: default packet lifetime must be in (0, max lifetime]");
  link_.set_receive_handler([this](const link::ReceivedFrame& f) { on_frame(f); });
  // Clause 10.3.6.2: the first beacon goes out after a random jitter, so that stations started
  // together do not beacon in step.
  schedule_beacon(jitter());
}

Router::~Router() {
  runtime_.cancel(beacon_timer_);
  for (const auto& [key, entry] : cbf_buffer_)
    runtime_.cancel(entry.timer);
  link_.set_receive_handler({});
}

std::optional<LongPositionVector> Router::ego_position_vector() const {
  const auto pos = position_.current_position();
  if (!pos || !std::isfinite(pos->latitude_deg) || !std::isfinite(pos->longitude_deg))
    return std::nullopt;
  LongPositionVector pv;
  pv.address = address_;
  pv.timestamp = to_timestamp(pos->time);
  pv.latitude = to_tenth_micro_degree(std::clamp(pos->latitude_deg, -90.0, 90.0));
  pv.longitude = to_tenth_micro_degree(std::clamp(pos->longitude_deg, -180.0, 180.0));
  pv.position_accurate = pos->accurate;
  // S is 15-bit signed in 0.01 m/s (clause 9.5.2).
  const double speed = std::isfinite(pos->speed_mps) ? pos->speed_mps * 100.0 : 0.0;
  pv.speed = static_cast<std::int16_t>(std::lround(std::clamp(speed, -16384.0, 16383.0)));
  const double heading = std::isfinite(pos->heading_deg) ? geodesy::wrap_360(pos->heading_deg) : 0;
  pv.heading = static_cast<std::uint16_t>(std::lround(heading * 10.0) % 3600);
  return pv;
}

clock::Duration Router::jitter() {
  const auto max_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(config_.beacon_max_jitter).count();
  if (max_ms <= 0)
    return clock::Duration::zero();
  std::uniform_int_distribution<std::int64_t> dist(0, max_ms);
  return std::chrono::milliseconds{dist(rng_)};
}

void Router::schedule_beacon(clock::Duration delay) {
  runtime_.cancel(beacon_timer_);
  beacon_timer_ = runtime_.schedule_in(delay, [this] { on_beacon_timer(); });
}

void Router::on_beacon_timer() {
  beacon_timer_ = 0;
  if (auto epv = ego_position_vector()) {
    BasicHeader basic{kGnProtocolVersion, BasicNextHeader::kCommonHeader,
                      Lifetime::from_duration(config_.default_lifetime), 1};
    CommonHeader common{UpperProtocol::kAny, PacketType::kBeacon, {}, config_.is_mobile, 0, 1};
    std::size_t n = serialize(basic, common, BeaconHeader{*epv}, {}, tx_);
    // Clause 10.3.6.2 with security enabled: the beacon is a secured packet too, signed for
    // GN-MGMT (TS 102 965 ITS-AID 141) under the generic profile of TS 103 097 7.1.3. An AT of
    // an older test PKI lacks that permission: its beacons go unsigned (strict peers drop them).
    if (n > 0 && security_on()) {
      if (security_->can_sign(security::kPsidGnMgmt)) {
        n = secure(security::kPsidGnMgmt, n, *epv);
      } else {
        ++stats_.beacons_unsigned;
      }
    }
    if (n > 0 && send_frame(link::kBroadcastMac, std::span(tx_).first(n))) {
      ++stats_.sent;
      ++stats_.beacons_sent;
    }
  }
  // Clause 10.3.6.2: retransmit after itsGnBeaconServiceRetransmitTimer plus a random jitter.
  schedule_beacon(config_.beacon_interval + jitter());
}

bool Router::send_frame(const link::MacAddress& to, std::span<const std::uint8_t> bytes) {
  return !link_.send(to, link::kEtherTypeGeoNetworking, bytes);
}

DataConfirm Router::request(const DataRequest& req, std::span<const std::uint8_t> payload) {
  if (payload.size() > config_.max_sdu_size)
    return DataConfirm::kMaxSduSizeExceeded;
  const clock::Duration lifetime =
      req.lifetime > clock::Duration::zero() ? req.lifetime : config_.default_lifetime;
  if (lifetime > config_.max_lifetime)
    return DataConfirm::kMaxLifetimeExceeded;
  if (req.transport == TransportType::kGeoBroadcast && !req.area)
    return DataConfirm::kMissingArea;
  const auto epv = ego_position_vector();
  if (!epv)
    return DataConfirm::kNoPosition;

  const std::uint8_t hop_limit =
      req.transport == TransportType::kSingleHopBroadcast
          ? 1
          : (req.max_hop_limit != 0 ? req.max_hop_limit : config_.default_hop_limit);
  BasicHeader basic{kGnProtocolVersion, BasicNextHeader::kCommonHeader,
                    Lifetime::from_duration(lifetime), hop_limit};
  CommonHeader common{req.upper_protocol,
                      PacketType::kSingleHopBroadcast,
                      req.traffic_class,
                      config_.is_mobile,
                      static_cast<std::uint16_t>(payload.size()),
                      hop_limit};
  ExtendedHeader ext;
  link::MacAddress destination = link::kBroadcastMac;
  switch (req.transport) {
    case TransportType::kSingleHopBroadcast:
      ext = ShbHeader{*epv, 0};
      break;
    case TransportType::kTopologicallyScopedBroadcast:
      common.type = PacketType::kTopologicallyScopedBroadcast;
      ext = TsbHeader{sequence_number_++, *epv};
      break;
    case TransportType::kGeoBroadcast: {
      common.type = gbc_type(req.area->shape);
      ext = GbcHeader{sequence_number_++, *epv, *req.area};
      // Clause 10.3.11.2 with Annex F: broadcast inside the area, greedy towards it otherwise.
      const GeoPoint ego = position_of(*epv);
      if (!is_inside_or_at_border(*req.area, ego)) {
        const auto next = greedy_next_hop(*req.area, ego, req.traffic_class);
        if (!next)
          return DataConfirm::kNoNeighbourTowardsArea;
        destination = *next;
      }
      break;
    }
  }
  std::size_t n = serialize(basic, common, ext, payload, tx_);
  if (n == 0)
    return DataConfirm::kMaxSduSizeExceeded;
  if (security_on()) {
    n = secure(req.its_aid, n, *epv);
    if (n == 0)
      return DataConfirm::kMaxSduSizeExceeded;
  }
  if (!send_frame(destination, std::span(tx_).first(n)))
    return DataConfirm::kLinkError;
  ++stats_.sent;
  // Clause 10.3.10.2: an SHB tells the neighbours where we are, so the next beacon can wait.
  if (req.transport == TransportType::kSingleHopBroadcast)
    schedule_beacon(config_.beacon_interval + jitter());
  return DataConfirm::kAccepted;
}

std::size_t Router::secure(std::uint64_t its_aid, std::size_t n, const LongPositionVector& epv) {
  // Clause 9.3 / TS 103 097: the basic header stays in clear, the rest goes signed.
  std::optional<security::ThreeDLocation> where;
  if (its_aid == security::kPsidDenm)
    where = security::ThreeDLocation{epv.latitude, epv.longitude, 4096};  // 0 m: unknown
  const security::Bytes secured = security_->encapsulate(
      its_aid, std::span(tx_).subspan(4, n - 4), security::to_time64(runtime_.wall_now()), where);
  if (4 + secured.size() > tx_.size())
    return 0;
  tx_[0] = static_cast<std::uint8_t>((tx_[0] & 0xf0) |
                                     static_cast<unsigned>(BasicNextHeader::kSecuredPacket));
  std::copy(secured.begin(), secured.end(), tx_.begin() + 4);
  return 4 + secured.size();
}

void Router::drop(DropReason reason, std::optional<ParseError> pe) {
  ++stats_.drops[static_cast<std::size_t>(reason)];
  if (drop_hook_)
    drop_hook_(DropEvent{reason, pe});
}

std::optional<link::MacAddress> Router::greedy_next_hop(const GeoArea& area, const GeoPoint& ego,
                                                        TrafficClass tc) const {
  // Annex E.2, most forward within radius: the neighbour nearest to the destination, if it is
  // nearer than we are.
  const GeoPoint centre{to_degrees(area.latitude), to_degrees(area.longitude)};
  double best = distance_m(ego, centre);
  std::optional<link::MacAddress> next;
  table_.for_each_neighbour(runtime_.steady_now(), [&](const LocationTableEntry& e) {
    const double d = distance_m(position_of(e.position), centre);
    if (d < best) {
      best = d;
      next = e.link_address;
    }
  });
  // Annex E.2 at a local optimum (no neighbour makes progress): with store-carry-forward the
  // packet waits in the forwarding buffer, which this router does not implement (so: none);
  // without, it is broadcast for whoever hears it.
  if (!next && !tc.store_carry_forward)
    next = link::kBroadcastMac;
  return next;
}

void Router::deliver(const Packet& packet, const link::ReceivedFrame& frame,
                     clock::Duration remaining_lifetime) {
  ++stats_.delivered;
  if (!indication_)
    return;
  DataIndication ind;
  ind.upper_protocol = packet.common.next_header;
  ind.packet_type = packet.common.type;
  ind.source_position = source_position(packet.extended);
  ind.source = ind.source_position.address;
  if (const auto* gbc = std::get_if<GbcHeader>(&packet.extended))
    ind.destination_area = gbc->area;
  ind.traffic_class = packet.common.traffic_class;
  ind.remaining_lifetime = remaining_lifetime;
  ind.remaining_hop_limit = packet.basic.remaining_hop_limit;
  ind.sender = frame.source;
  ind.rx_time = frame.rx_time;
  if (unwrapped_ != nullptr) {
    ind.security_report = unwrapped_->reason;
    ind.its_aid = unwrapped_->psid;
    ind.permissions = unwrapped_->ssp;
  }
  indication_(ind, packet.payload);
}

std::span<const std::uint8_t> Router::as_received(const Packet& packet,
                                                  std::span<const std::uint8_t> bytes) const {
  if (unwrapped_ != nullptr)
    return secured_frame_;  // the secured packet ends the frame: its decoder insists on that
  return bytes.first(static_cast<std::size_t>(packet.payload.data() - bytes.data()) +
                     packet.payload.size());
}

void Router::forward(const Packet& packet, std::span<const std::uint8_t> bytes,
                     const std::optional<GeoArea>& area, bool inside) {
  // Clause 10.3.9.3 / 10.3.11.3: decrement RHL; at 0 the packet goes no further.
  const std::uint8_t rhl = packet.basic.remaining_hop_limit - 1;
  if (rhl == 0) {
    drop(DropReason::kNotForwardedHopLimit);
    return;
  }
  link::MacAddress destination = link::kBroadcastMac;
  if (area && !inside) {
    const auto epv = ego_position_vector();
    const auto next =
        epv ? greedy_next_hop(*area, position_of(*epv), packet.common.traffic_class) : std::nullopt;
    if (!next) {
      drop(DropReason::kNoForwardingNeighbour);
      return;
    }
    destination = *next;
  }
  // Forward the packet as received, headers and payload (or the signed part) unchanged but for
  // the RHL (byte 3 of the basic header); link padding after the payload is not copied.
  const auto out = as_received(packet, bytes);
  std::copy(out.begin(), out.end(), tx_.begin());
  tx_[3] = rhl;
  if (!send_frame(destination, std::span(tx_).first(out.size()))) {
    drop(DropReason::kForwardLinkError);
    return;
  }
  ++stats_.forwarded;
}

void Router::contend(const Packet& packet, std::span<const std::uint8_t> bytes,
                     const link::MacAddress& sender, std::uint64_t key) {
  const std::uint8_t rhl = packet.basic.remaining_hop_limit - 1;
  if (rhl == 0) {
    drop(DropReason::kNotForwardedHopLimit);
    return;
  }
  // TO_CBF = max − (max − min) × DIST / DIST_MAX for a sender whose accurate position we know,
  // min beyond DIST_MAX, max when we know nothing of the sender (Annex F.3).
  clock::Duration timeout = config_.cbf_max_time;
  const auto epv = ego_position_vector();
  const LocationTableEntry* se =
      table_.find(GnAddress{false, StationType::kUnknown, sender}.mid_key(), runtime_.steady_now());
  if (epv && se != nullptr && se->has_position && se->position.position_accurate) {
    const double dist = distance_m(position_of(se->position), position_of(*epv));
    const double share = std::min(dist / config_.max_communication_range_m, 1.0);
    timeout = config_.cbf_max_time - std::chrono::duration_cast<clock::Duration>(
                                         (config_.cbf_max_time - config_.cbf_min_time) * share);
  }
  const auto out = as_received(packet, bytes);
  std::vector<std::uint8_t> copy(out.begin(), out.end());
  copy[3] = rhl;
  const auto id = std::make_pair(key, std::get<GbcHeader>(packet.extended).sequence_number);
  const clock::TimerId timer = runtime_.schedule_in(timeout, [this, id] {
    auto it = cbf_buffer_.find(id);
    if (it == cbf_buffer_.end())
      return;
    const std::vector<std::uint8_t> out = std::move(it->second.packet);
    cbf_buffer_.erase(it);
    if (send_frame(link::kBroadcastMac, out))
      ++stats_.forwarded;
    else
      drop(DropReason::kForwardLinkError);
  });
  cbf_buffer_[id] = CbfEntry{timer, std::move(copy)};
  ++stats_.cbf_buffered;
}

void Router::on_secured_frame(const link::ReceivedFrame& frame) {
  // The secured packet (clause 9.3): basic header, then the Ieee1609Dot2Data whose payload is
  // common header onwards. What passes verification (or a permissive station passes up) goes
  // through the ordinary receive path as basic header + that payload.
  const std::uint64_t ticket = ++next_ticket_;
  const auto outcomes = security_->decapsulate(frame.payload.subspan(4),
                                               security::to_time64(runtime_.wall_now()), ticket);
  if (std::none_of(outcomes.begin(), outcomes.end(),
                   [&](const auto& o) { return o.ticket == ticket; })) {
    // Held until its signer's certificate comes: keep the frame it came in.
    HeldFrame& h = held_frames_[ticket];
    h.payload.assign(frame.payload.begin(), frame.payload.end());
    h.frame = frame;
    h.frame.payload = h.payload;
  }
  for (const auto& o : outcomes) {
    if (o.ticket == ticket) {
      on_unwrapped(o, frame);
      continue;
    }
    auto it = held_frames_.find(o.ticket);
    if (it == held_frames_.end())
      continue;
    const HeldFrame held = std::move(it->second);
    held_frames_.erase(it);
    link::ReceivedFrame f = held.frame;
    f.payload = held.payload;
    on_unwrapped(o, f);
  }
}

void Router::on_unwrapped(const security::SecuredIndication& o,
                          const link::ReceivedFrame& secured) {
  if (!o.pass_up) {
    ++stats_.received;
    drop(DropReason::kSecurity);
    return;
  }
  std::vector<std::uint8_t> plain(secured.payload.begin(), secured.payload.begin() + 4);
  plain[0] = static_cast<std::uint8_t>((plain[0] & 0xf0) |
                                       static_cast<unsigned>(BasicNextHeader::kCommonHeader));
  plain.insert(plain.end(), o.payload.begin(), o.payload.end());
  link::ReceivedFrame inner = secured;
  inner.payload = plain;
  unwrapped_ = &o;
  secured_frame_ = secured.payload;
  on_frame(inner);
  unwrapped_ = nullptr;
  secured_frame_ = {};
}

void Router::on_frame(const link::ReceivedFrame& frame) {
  if (security_on() && unwrapped_ == nullptr && frame.ethertype == link::kEtherTypeGeoNetworking &&
      frame.payload.size() > 4 &&
      (frame.payload[0] & 0x0f) == static_cast<unsigned>(BasicNextHeader::kSecuredPacket)) {
    on_secured_frame(frame);
    return;
  }
  ++stats_.received;
  if (frame.ethertype != link::kEtherTypeGeoNetworking) {
    drop(DropReason::kWrongEtherType);
    return;
  }
  const clock::SteadyTime now = runtime_.steady_now();
  if (now >= next_purge_) {
    table_.purge(now);
    next_purge_ = now + 1s;
  }

  // A shared parser's packet is held there (valid while this frame is handled), else our own.
  std::optional<Expected<Packet, ParseError>> own;
  const Expected<Packet, ParseError>& parsed = shared_parser_
                                                   ? shared_parser_->parse(frame.payload)
                                                   : own.emplace(parse_packet(frame.payload));
  if (!parsed) {
    drop(DropReason::kParseError, parsed.error());
    return;
  }
  const Packet& p = *parsed;
  // A strict station (itsGnSnDecapResultHandling STRICT) takes only secured packets, beacons
  // included (they are signed for GN-MGMT).
  if (security_on() && unwrapped_ == nullptr &&
      security_->mode() == security::SecurityMode::kSigned) {
    drop(DropReason::kUnsecured);
    return;
  }
  const LongPositionVector& so = source_position(p.extended);
  if (so.address.mid == address_.mid || frame.source == address_.mid) {
    drop(DropReason::kOwnPacket);
    return;
  }
  // Clause 10.3.3: basic and common header processing.
  if (p.basic.remaining_hop_limit == 0) {
    drop(DropReason::kHopLimitZero);
    return;
  }
  if (p.basic.remaining_hop_limit > p.common.maximum_hop_limit) {
    drop(DropReason::kHopLimitExceedsMaximum);
    return;
  }
  // Clause 10.3.10.3 / 10.3.11.3: the lifetime governs buffering and forwarding; nothing is
  // dropped for the age (own time − source TST) it would suggest, since peers stamp TSTs in
  // TAI or UTC (5 s apart) from clocks we cannot check, with lifetimes as short as 1 s. Only
  // a packet that arrives with no lifetime at all is stale by its own word.
  const clock::Duration remaining_lifetime = p.basic.lifetime.duration();
  if (p.common.type != PacketType::kBeacon && remaining_lifetime <= clock::Duration::zero()) {
    drop(DropReason::kLifetimeExpired);
    return;
  }

  if (table_.size() >= config_.max_location_entries &&
      table_.find(so.address.mid_key(), now) == nullptr) {
    table_.purge(now);
    if (table_.size() >= config_.max_location_entries) {
      drop(DropReason::kLocationTableFull);
      return;
    }
  }
  bool created = false;
  LocationTableEntry& entry =
      table_.find_or_create(so.address, now, created,
                            shared_parser_ ? shared_parser_->sender_row() : SenderIndex::kNoRow);
  switch (p.common.type) {
    case PacketType::kBeacon:
    case PacketType::kSingleHopBroadcast: {
      // Clause 10.3.10.3 (V1.3.1 on): no duplicate packet detection for single-hop packets.
      // A newer TST updates the entry (Annex C.2), an older or equal one does not; the packet
      // goes up either way, and hearing the source directly keeps its entry alive.
      if (!table_.update_position(entry, so, now))
        table_.refresh(entry, now);
      entry.is_neighbour = true;
      entry.link_address = frame.source;
      if (p.common.type == PacketType::kSingleHopBroadcast)
        deliver(p, frame, remaining_lifetime);
      return;
    }
    case PacketType::kTopologicallyScopedBroadcast: {
      const auto& tsb = std::get<TsbHeader>(p.extended);
      if (LocationTable::is_duplicate_sequence_number(entry, tsb.sequence_number)) {
        drop(DropReason::kDuplicate);
        return;
      }
      table_.update_position(entry, so, now);
      deliver(p, frame, remaining_lifetime);
      forward(p, frame.payload, std::nullopt, true);
      return;
    }
    case PacketType::kGeoBroadcastCircle:
    case PacketType::kGeoBroadcastRectangle:
    case PacketType::kGeoBroadcastEllipse: {
      const auto& gbc = std::get<GbcHeader>(p.extended);
      const auto cbf_key = std::make_pair(so.address.mid_key(), gbc.sequence_number);
      if (LocationTable::is_duplicate_sequence_number(entry, gbc.sequence_number)) {
        // Annex F.3: hearing the packet again while contending means a router farther on has
        // rebroadcast it; ours would add nothing.
        if (auto it = cbf_buffer_.find(cbf_key); it != cbf_buffer_.end()) {
          runtime_.cancel(it->second.timer);
          cbf_buffer_.erase(it);
          drop(DropReason::kContentionLost);
          return;
        }
        drop(DropReason::kDuplicate);
        return;
      }
      table_.update_position(entry, so, now);
      const auto epv = ego_position_vector();
      const bool inside = epv && is_inside_or_at_border(gbc.area, position_of(*epv));
      if (inside) {
        deliver(p, frame, remaining_lifetime);
        if (config_.area_forwarding == RouterConfig::AreaForwarding::kContentionBased)
          contend(p, frame.payload, frame.source, cbf_key.first);
        else
          forward(p, frame.payload, gbc.area, true);
        return;
      }
      drop(DropReason::kOutsideArea);
      // Annex F.2: a packet that a sender inside the area broadcast has done its job; carrying
      // it back towards the area would only loop.
      const std::uint64_t sender_key =
          GnAddress{false, StationType::kUnknown, frame.source}.mid_key();
      const LocationTableEntry* sender = table_.find(sender_key, now);
      if (sender != nullptr && sender->has_position &&
          is_inside_or_at_border(gbc.area, position_of(sender->position)))
        return;
      forward(p, frame.payload, gbc.area, false);
      return;
    }
  }
}

}  // namespace tb::its::geonet
