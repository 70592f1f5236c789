#include "common/wire/sim_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <utility>

#include "common/util/bytes.hpp"

namespace tb::wire::sim {
namespace {

constexpr std::uint8_t kReverseBit = 1u << 0;
constexpr std::uint8_t kHandbrakeBit = 1u << 1;

// Fixed payload sizes of the client's messages.
constexpr std::size_t kAttachSize = 1 + 2;
constexpr std::size_t kControlsSize = kControlsEntrySize;
constexpr std::size_t kDetachSize = 2;
constexpr std::size_t kStateHeadSize = 8 + 8 + 8 + 2;
constexpr std::size_t kSignalStatesHeadSize = 8 + 2;

bool is_client_type(MessageType t) {
  return static_cast<std::uint8_t>(t) < 0x80;
}

bool known_type(std::uint8_t t) {
  switch (static_cast<MessageType>(t)) {
    case MessageType::kHello:
    case MessageType::kAttach:
    case MessageType::kControls:
    case MessageType::kDetach:
    case MessageType::kControlsBatch:
    case MessageType::kWelcome:
    case MessageType::kAttachResult:
    case MessageType::kState:
    case MessageType::kDriverChanged:
    case MessageType::kClosing:
    case MessageType::kSignalStates:
      return true;
  }
  return false;
}

/// Builds a frame: header first, the payload size patched in by finish().
class FrameWriter {
 public:
  FrameWriter(MessageType type, std::size_t payload_size)
      : buf_(kHeaderSize + payload_size), w_(buf_) {
    w_.le<std::uint8_t>(kMagic0);
    w_.le<std::uint8_t>(kMagic1);
    w_.le<std::uint8_t>(kProtocolVersion);
    w_.le<std::uint8_t>(static_cast<std::uint8_t>(type));
    w_.le<std::uint32_t>(static_cast<std::uint32_t>(payload_size));
  }
  ByteWriter& w() { return w_; }
  /// Strings longer than the wire allows are cut: the encoder's callers own the limits, and a
  /// cut name is better than a frame the peer rejects.
  void text(std::string_view s, std::size_t max) {
    const auto n = std::min(s.size(), max);
    w_.le<std::uint8_t>(static_cast<std::uint8_t>(n));
    w_.write({reinterpret_cast<const std::uint8_t*>(s.data()), n});
  }
  std::vector<std::uint8_t> finish() {
    // A size mismatch is a bug in this file, not bad input.
    if (!w_.ok() || w_.position() != buf_.size())
      std::abort();
    return std::move(buf_);
  }

 private:
  std::vector<std::uint8_t> buf_;
  ByteWriter w_;
};

std::size_t text_size(std::string_view s, std::size_t max) {
  return 1 + std::min(s.size(), max);
}

/// Reads a u8-length string; printable ASCII and UTF-8 continuation bytes only, so that names
/// are safe to put in logs.
bool read_text(ByteReader& r, std::size_t max, std::string& out) {
  const std::size_t n = r.le<std::uint8_t>();
  if (!r.ok() || n > max)
    return false;
  out.resize(n);
  if (!r.read({reinterpret_cast<std::uint8_t*>(out.data()), n}))
    return false;
  return std::all_of(out.begin(), out.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 0x20 && u != 0x7f;
  });
}

/// One Controls payload (also a ControlsBatch entry); the reader's ok() says if it was all there.
std::optional<ProtocolError> read_controls(ByteReader& r, ControlsMsg& m) {
  m.vehicle = r.le<std::uint16_t>();
  m.controls.throttle = r.le<float>();
  m.controls.brake = r.le<float>();
  m.controls.steer = r.le<float>();
  const auto flags = r.le<std::uint8_t>();
  m.lights = r.le<std::uint16_t>();
  m.input_ns = r.le<std::int64_t>();
  if (!r.ok())
    return ProtocolError::kBadLength;
  if (!std::isfinite(m.controls.throttle) || !std::isfinite(m.controls.brake) ||
      !std::isfinite(m.controls.steer)) {
    return ProtocolError::kNotFinite;
  }
  if ((flags & ~(kReverseBit | kHandbrakeBit)) != 0)
    return ProtocolError::kBadValue;
  m.controls.reverse = (flags & kReverseBit) != 0;
  m.controls.handbrake = (flags & kHandbrakeBit) != 0;
  return std::nullopt;
}

void write_controls(ByteWriter& w, const ControlsMsg& m) {
  w.le(m.vehicle);
  w.le(m.controls.throttle);
  w.le(m.controls.brake);
  w.le(m.controls.steer);
  w.le<std::uint8_t>((m.controls.reverse ? kReverseBit : 0) |
                     (m.controls.handbrake ? kHandbrakeBit : 0));
  w.le(m.lights);
  w.le(m.input_ns);
}

template <typename T>
Expected<T, ProtocolError> fail(ProtocolError e) {
  return Unexpected{e};
}

/// Checks that the reader consumed the payload exactly.
std::optional<ProtocolError> finished(const ByteReader& r) {
  if (!r.ok() || r.remaining() != 0)
    return ProtocolError::kBadLength;
  return std::nullopt;
}

}  // namespace

std::string_view to_string(MessageType t) {
  switch (t) {
    case MessageType::kHello:
      return "Hello";
    case MessageType::kAttach:
      return "Attach";
    case MessageType::kControls:
      return "Controls";
    case MessageType::kDetach:
      return "Detach";
    case MessageType::kControlsBatch:
      return "ControlsBatch";
    case MessageType::kWelcome:
      return "Welcome";
    case MessageType::kAttachResult:
      return "AttachResult";
    case MessageType::kState:
      return "State";
    case MessageType::kDriverChanged:
      return "DriverChanged";
    case MessageType::kClosing:
      return "Closing";
    case MessageType::kSignalStates:
      return "SignalStates";
  }
  return "unknown";
}

std::string_view to_string(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::kUnavailable:
      return "unavailable";
    case MovementPhaseState::kDark:
      return "dark";
    case MovementPhaseState::kStopThenProceed:
      return "stop-Then-Proceed";
    case MovementPhaseState::kStopAndRemain:
      return "stop-And-Remain";
    case MovementPhaseState::kPreMovement:
      return "pre-Movement";
    case MovementPhaseState::kPermissiveMovementAllowed:
      return "permissive-Movement-Allowed";
    case MovementPhaseState::kProtectedMovementAllowed:
      return "protected-Movement-Allowed";
    case MovementPhaseState::kPermissiveClearance:
      return "permissive-clearance";
    case MovementPhaseState::kProtectedClearance:
      return "protected-clearance";
    case MovementPhaseState::kCautionConflictingTraffic:
      return "caution-Conflicting-Traffic";
  }
  return "unknown";
}

std::string_view to_string(ProtocolError e) {
  switch (e) {
    case ProtocolError::kBadMagic:
      return "bad magic (not a sim-protocol frame)";
    case ProtocolError::kUnsupportedVersion:
      return "unsupported protocol version";
    case ProtocolError::kUnknownType:
      return "unknown message type";
    case ProtocolError::kOversized:
      return "message larger than its bound";
    case ProtocolError::kBadLength:
      return "payload length does not match its fields";
    case ProtocolError::kBadText:
      return "string too long or not printable";
    case ProtocolError::kNotFinite:
      return "non-finite number";
    case ProtocolError::kBadValue:
      return "value out of range";
    case ProtocolError::kBadState:
      return "malformed vehicle state record";
    case ProtocolError::kOutOfOrder:
      return "message out of order";
    case ProtocolError::kParserFailed:
      return "stream already failed";
  }
  return "unknown error";
}

std::string_view to_string(AttachStatus s) {
  switch (s) {
    case AttachStatus::kOk:
      return "ok";
    case AttachStatus::kUnknownVehicle:
      return "unknown vehicle";
    case AttachStatus::kAlreadyDriven:
      return "already driven";
    case AttachStatus::kRefused:
      return "refused";
  }
  return "unknown";
}

std::string_view to_string(CloseReason r) {
  switch (r) {
    case CloseReason::kProtocolError:
      return "protocol error";
    case CloseReason::kTooSlow:
      return "too slow";
    case CloseReason::kShutdown:
      return "shutdown";
    case CloseReason::kScenarioFinished:
      return "scenario finished";
  }
  return "unknown";
}

std::size_t max_payload(Sender from, MessageType type) {
  if ((from == Sender::kClient) != is_client_type(type))
    return 0;
  switch (type) {
    case MessageType::kHello:
      return 1 + kMaxNameLength;
    case MessageType::kAttach:
      return kAttachSize;
    case MessageType::kControls:
      return kControlsSize;
    case MessageType::kDetach:
      return kDetachSize;
    case MessageType::kControlsBatch:
      return kMaxControlsBatchPayload;
    case MessageType::kWelcome:
      return kMaxWelcomePayload;
    case MessageType::kState:
      return kMaxServerPayload;
    case MessageType::kAttachResult:
      return 1 + 2 + 1 + 1 + kMaxTextLength;
    case MessageType::kDriverChanged:
      return 2 + 1 + kMaxNameLength;
    case MessageType::kClosing:
      return 1 + 1 + kMaxTextLength;
    case MessageType::kSignalStates:
      return kSignalStatesHeadSize + kMaxSignalGroupStates * kSignalGroupStateSize;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// FrameParser

Expected<FrameParser::Status, ProtocolError> FrameParser::check_header() {
  ByteReader r(header_);
  const auto m0 = r.le<std::uint8_t>();
  const auto m1 = r.le<std::uint8_t>();
  const auto version = r.le<std::uint8_t>();
  const auto type = r.le<std::uint8_t>();
  const auto size = r.le<std::uint32_t>();
  if (m0 != kMagic0 || m1 != kMagic1)
    return Unexpected{ProtocolError::kBadMagic};
  if (version != kProtocolVersion)
    return Unexpected{ProtocolError::kUnsupportedVersion};
  if (!known_type(type))
    return Unexpected{ProtocolError::kUnknownType};
  const auto t = static_cast<MessageType>(type);
  const std::size_t bound = max_payload(from_, t);
  if (bound == 0)
    return Unexpected{ProtocolError::kUnknownType};
  if (size > bound)
    return Unexpected{ProtocolError::kOversized};
  frame_.type = t;
  frame_.payload.clear();
  payload_size_ = size;
  return Status::kNeedMore;
}

Expected<FrameParser::Status, ProtocolError> FrameParser::parse(
    std::span<const std::uint8_t>& data) {
  while (true) {
    switch (step_) {
      case Step::kFailed:
        return Unexpected{ProtocolError::kParserFailed};
      case Step::kHeader: {
        if (data.empty())
          return Status::kNeedMore;
        const std::size_t n = std::min(kHeaderSize - header_fill_, data.size());
        std::memcpy(header_.data() + header_fill_, data.data(), n);
        header_fill_ += n;
        data = data.subspan(n);
        if (header_fill_ < kHeaderSize)
          return Status::kNeedMore;
        header_fill_ = 0;
        if (auto h = check_header(); !h) {
          step_ = Step::kFailed;
          return Unexpected{h.error()};
        }
        step_ = Step::kPayload;
        frame_.payload.reserve(payload_size_);
        break;
      }
      case Step::kPayload: {
        const std::size_t n = std::min(payload_size_ - frame_.payload.size(), data.size());
        frame_.payload.insert(frame_.payload.end(), data.begin(), data.begin() + n);
        data = data.subspan(n);
        if (frame_.payload.size() < payload_size_)
          return Status::kNeedMore;
        step_ = Step::kHeader;
        return Status::kFrame;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Decoding

Expected<ClientMessage, ProtocolError> decode_client(const Frame& f) {
  if (f.payload.size() > max_payload(Sender::kClient, f.type))
    return Unexpected{ProtocolError::kOversized};
  ByteReader r(f.payload);
  ClientMessage out;
  switch (f.type) {
    case MessageType::kHello: {
      Hello m;
      if (!read_text(r, kMaxNameLength, m.client_name))
        return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
      out = std::move(m);
      break;
    }
    case MessageType::kAttach: {
      Attach m;
      const auto role = r.le<std::uint8_t>();
      m.vehicle = r.le<std::uint16_t>();
      if (auto e = finished(r))
        return Unexpected{*e};
      if (role > static_cast<std::uint8_t>(Role::kDriver))
        return Unexpected{ProtocolError::kBadValue};
      m.role = static_cast<Role>(role);
      out = m;
      break;
    }
    case MessageType::kControls: {
      ControlsMsg m;
      const auto bad = read_controls(r, m);
      if (auto e = finished(r))
        return Unexpected{*e};
      if (bad)
        return Unexpected{*bad};
      out = m;
      break;
    }
    case MessageType::kControlsBatch: {
      // The count must match the payload exactly before any entry is read.
      const std::size_t count = r.le<std::uint16_t>();
      if (!r.ok() || r.remaining() != count * kControlsEntrySize)
        return Unexpected{ProtocolError::kBadLength};
      if (count == 0 || count > kMaxVehicles)
        return Unexpected{ProtocolError::kBadValue};
      ControlsBatch m;
      m.entries.resize(count);
      for (ControlsMsg& e : m.entries) {
        if (const auto bad = read_controls(r, e))
          return Unexpected{*bad};
      }
      out = std::move(m);
      break;
    }
    case MessageType::kDetach: {
      Detach m;
      m.vehicle = r.le<std::uint16_t>();
      if (auto e = finished(r))
        return Unexpected{*e};
      out = m;
      break;
    }
    default:
      return Unexpected{ProtocolError::kUnknownType};
  }
  if (auto e = finished(r))
    return Unexpected{*e};
  return out;
}

namespace {

Expected<ServerMessage, ProtocolError> decode_welcome(ByteReader& r) {
  Welcome m;
  if (!read_text(r, kMaxNameLength, m.server_name))
    return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
  m.step_ns = r.le<std::int64_t>();
  m.world_start_ns = r.le<std::int64_t>();
  const std::size_t count = r.le<std::uint16_t>();
  if (!r.ok())
    return Unexpected{ProtocolError::kBadLength};
  if (m.step_ns <= 0 || m.world_start_ns <= 0 || count > kMaxVehicles)
    return Unexpected{ProtocolError::kBadValue};
  m.vehicles.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    VehicleInfo v;
    v.index = r.le<std::uint16_t>();
    if (!read_text(r, kMaxTextLength, v.id))
      return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
    v.station_id = r.le<std::uint32_t>();
    v.station_type = r.le<std::uint8_t>();
    if (!read_text(r, kMaxTextLength, v.color))
      return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
    const auto kind = r.le<std::uint8_t>();
    float* dims[] = {&v.length_m, &v.width_m,        &v.height_m,     &v.wheelbase_m,
                     &v.track_m,  &v.wheel_radius_m, &v.max_steer_rad};
    for (float* d : dims)
      *d = r.le<float>();
    if (!read_text(r, kMaxNameLength, v.driver))
      return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
    if (!r.ok())
      return Unexpected{ProtocolError::kBadLength};
    if (kind > static_cast<std::uint8_t>(DriverKind::kLaneFollow) || v.index != i)
      return Unexpected{ProtocolError::kBadValue};
    v.driver_kind = static_cast<DriverKind>(kind);
    for (float* d : dims) {
      if (!std::isfinite(*d))
        return Unexpected{ProtocolError::kNotFinite};
    }
    m.vehicles.push_back(std::move(v));
  }
  const std::size_t json_size = r.le<std::uint32_t>();
  if (!r.ok() || json_size > kMaxScenarioText || json_size > r.remaining())
    return Unexpected{ProtocolError::kBadLength};
  m.scenario_json.resize(json_size);
  r.read({reinterpret_cast<std::uint8_t*>(m.scenario_json.data()), json_size});
  const std::size_t map_size = r.le<std::uint32_t>();
  if (!r.ok() || map_size > kMaxMapText || map_size != r.remaining())
    return Unexpected{ProtocolError::kBadLength};
  m.map_text.resize(map_size);
  r.read({reinterpret_cast<std::uint8_t*>(m.map_text.data()), map_size});
  return ServerMessage{std::move(m)};
}

Expected<ServerMessage, ProtocolError> decode_state(ByteReader& r) {
  StateFrame m;
  m.tick = r.le<std::uint64_t>();
  m.sim_time_ns = r.le<std::int64_t>();
  m.step_wall_ns = r.le<std::int64_t>();
  const std::size_t count = r.le<std::uint16_t>();
  if (!r.ok() || r.remaining() != count * kVehicleStateSize)
    return Unexpected{ProtocolError::kBadLength};
  if (count > kMaxVehicles || m.sim_time_ns < kMinSimTimeNs)
    return Unexpected{ProtocolError::kBadValue};
  m.vehicles.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    auto s = decode(r.rest().first(kVehicleStateSize));
    if (!s)
      return Unexpected{ProtocolError::kBadState};
    r.skip(kVehicleStateSize);
    m.vehicles.push_back(*s);
  }
  return ServerMessage{std::move(m)};
}

Expected<ServerMessage, ProtocolError> decode_signal_states(ByteReader& r) {
  SignalStates m;
  m.world_time_ms = r.le<std::int64_t>();
  const std::size_t count = r.le<std::uint16_t>();
  if (!r.ok() || r.remaining() != count * kSignalGroupStateSize)
    return Unexpected{ProtocolError::kBadLength};
  if (count > kMaxSignalGroupStates || m.world_time_ms < 0)
    return Unexpected{ProtocolError::kBadValue};
  m.groups.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    SignalGroupState g;
    g.intersection_id = r.le<std::uint16_t>();
    g.signal_group = r.le<std::uint8_t>();
    const auto state = r.le<std::uint8_t>();
    g.next_change_ms = r.le<std::int64_t>();
    g.likely_change_ms = r.le<std::int64_t>();
    // SignalGroupID 0 and 255 are reserved (ISO TS 19091 DSRC); ascending entries make a
    // repeated group an error found in one pass.
    if (g.signal_group == 0 || g.signal_group == 255 ||
        state > static_cast<std::uint8_t>(MovementPhaseState::kCautionConflictingTraffic) ||
        g.next_change_ms < 0 || g.likely_change_ms < 0) {
      return Unexpected{ProtocolError::kBadValue};
    }
    if (!m.groups.empty() &&
        std::pair(g.intersection_id, g.signal_group) <=
            std::pair(m.groups.back().intersection_id, m.groups.back().signal_group)) {
      return Unexpected{ProtocolError::kBadValue};
    }
    g.state = static_cast<MovementPhaseState>(state);
    m.groups.push_back(g);
  }
  if (auto e = finished(r))
    return Unexpected{*e};
  return ServerMessage{std::move(m)};
}

}  // namespace

Expected<ServerMessage, ProtocolError> decode_server(const Frame& f) {
  if (f.payload.size() > max_payload(Sender::kServer, f.type))
    return Unexpected{ProtocolError::kOversized};
  ByteReader r(f.payload);
  switch (f.type) {
    case MessageType::kWelcome:
      return decode_welcome(r);
    case MessageType::kState:
      return decode_state(r);
    case MessageType::kAttachResult: {
      AttachResult m;
      const auto role = r.le<std::uint8_t>();
      m.vehicle = r.le<std::uint16_t>();
      const auto status = r.le<std::uint8_t>();
      if (!read_text(r, kMaxTextLength, m.reason))
        return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
      if (auto e = finished(r))
        return Unexpected{*e};
      if (role > static_cast<std::uint8_t>(Role::kDriver) ||
          status > static_cast<std::uint8_t>(AttachStatus::kRefused)) {
        return Unexpected{ProtocolError::kBadValue};
      }
      m.role = static_cast<Role>(role);
      m.status = static_cast<AttachStatus>(status);
      return ServerMessage{std::move(m)};
    }
    case MessageType::kDriverChanged: {
      DriverChanged m;
      m.vehicle = r.le<std::uint16_t>();
      if (!read_text(r, kMaxNameLength, m.driver))
        return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
      if (auto e = finished(r))
        return Unexpected{*e};
      return ServerMessage{std::move(m)};
    }
    case MessageType::kSignalStates:
      return decode_signal_states(r);
    case MessageType::kClosing: {
      Closing m;
      const auto reason = r.le<std::uint8_t>();
      if (!read_text(r, kMaxTextLength, m.text))
        return Unexpected{r.ok() ? ProtocolError::kBadText : ProtocolError::kBadLength};
      if (auto e = finished(r))
        return Unexpected{*e};
      if (reason < static_cast<std::uint8_t>(CloseReason::kProtocolError) ||
          reason > static_cast<std::uint8_t>(CloseReason::kScenarioFinished)) {
        return Unexpected{ProtocolError::kBadValue};
      }
      m.reason = static_cast<CloseReason>(reason);
      return ServerMessage{std::move(m)};
    }
    default:
      return Unexpected{ProtocolError::kUnknownType};
  }
}

// ---------------------------------------------------------------------------------------------
// Encoding

std::vector<std::uint8_t> encode(const Hello& m) {
  FrameWriter f(MessageType::kHello, text_size(m.client_name, kMaxNameLength));
  f.text(m.client_name, kMaxNameLength);
  return f.finish();
}

std::vector<std::uint8_t> encode(const Attach& m) {
  FrameWriter f(MessageType::kAttach, kAttachSize);
  f.w().le(static_cast<std::uint8_t>(m.role));
  f.w().le(m.vehicle);
  return f.finish();
}

std::vector<std::uint8_t> encode(const ControlsMsg& m) {
  FrameWriter f(MessageType::kControls, kControlsSize);
  write_controls(f.w(), m);
  return f.finish();
}

std::vector<std::uint8_t> encode(const ControlsBatch& m) {
  const std::size_t count = std::min(m.entries.size(), kMaxVehicles);
  FrameWriter f(MessageType::kControlsBatch, 2 + count * kControlsEntrySize);
  f.w().le(static_cast<std::uint16_t>(count));
  for (std::size_t i = 0; i < count; ++i)
    write_controls(f.w(), m.entries[i]);
  return f.finish();
}

std::vector<std::uint8_t> encode(const Detach& m) {
  FrameWriter f(MessageType::kDetach, kDetachSize);
  f.w().le(m.vehicle);
  return f.finish();
}

std::vector<std::uint8_t> encode(const Welcome& m) {
  const std::size_t count = std::min(m.vehicles.size(), kMaxVehicles);
  std::size_t size = text_size(m.server_name, kMaxNameLength) + 8 + 8 + 2;
  for (std::size_t i = 0; i < count; ++i) {
    const auto& v = m.vehicles[i];
    size += 2 + text_size(v.id, kMaxTextLength) + 4 + 1 + text_size(v.color, kMaxTextLength) + 1 +
            7 * 4 + text_size(v.driver, kMaxNameLength);
  }
  const std::size_t json = std::min(m.scenario_json.size(), kMaxScenarioText);
  const std::size_t map = std::min(m.map_text.size(), kMaxMapText);
  size += 4 + json + 4 + map;
  FrameWriter f(MessageType::kWelcome, size);
  f.text(m.server_name, kMaxNameLength);
  f.w().le(m.step_ns);
  f.w().le(m.world_start_ns);
  f.w().le(static_cast<std::uint16_t>(count));
  for (std::size_t i = 0; i < count; ++i) {
    const auto& v = m.vehicles[i];
    f.w().le(static_cast<std::uint16_t>(i));
    f.text(v.id, kMaxTextLength);
    f.w().le(v.station_id);
    f.w().le(v.station_type);
    f.text(v.color, kMaxTextLength);
    f.w().le(static_cast<std::uint8_t>(v.driver_kind));
    for (float d : {v.length_m, v.width_m, v.height_m, v.wheelbase_m, v.track_m, v.wheel_radius_m,
                    v.max_steer_rad})
      f.w().le(d);
    f.text(v.driver, kMaxNameLength);
  }
  f.w().le(static_cast<std::uint32_t>(json));
  f.w().write({reinterpret_cast<const std::uint8_t*>(m.scenario_json.data()), json});
  f.w().le(static_cast<std::uint32_t>(map));
  f.w().write({reinterpret_cast<const std::uint8_t*>(m.map_text.data()), map});
  return f.finish();
}

std::vector<std::uint8_t> encode(const AttachResult& m) {
  FrameWriter f(MessageType::kAttachResult, 1 + 2 + 1 + text_size(m.reason, kMaxTextLength));
  f.w().le(static_cast<std::uint8_t>(m.role));
  f.w().le(m.vehicle);
  f.w().le(static_cast<std::uint8_t>(m.status));
  f.text(m.reason, kMaxTextLength);
  return f.finish();
}

std::vector<std::uint8_t> encode_state(std::uint64_t tick, std::int64_t sim_time_ns,
                                       std::int64_t step_wall_ns,
                                       std::span<const VehicleState> vehicles,
                                       std::int64_t send_wall_ns) {
  const std::size_t count = std::min(vehicles.size(), kMaxVehicles);
  FrameWriter f(MessageType::kState, kStateHeadSize + count * kVehicleStateSize);
  f.w().le(tick);
  f.w().le(sim_time_ns);
  f.w().le(step_wall_ns);
  f.w().le(static_cast<std::uint16_t>(count));
  std::array<std::uint8_t, kVehicleStateSize> record;
  for (std::size_t i = 0; i < count; ++i) {
    VehicleState s = vehicles[i];
    s.send_wall_ns = send_wall_ns;
    encode(s, std::span<std::uint8_t, kVehicleStateSize>(record));
    f.w().write(record);
  }
  return f.finish();
}

std::vector<std::uint8_t> encode(const StateFrame& m) {
  const std::size_t count = std::min(m.vehicles.size(), kMaxVehicles);
  FrameWriter f(MessageType::kState, kStateHeadSize + count * kVehicleStateSize);
  f.w().le(m.tick);
  f.w().le(m.sim_time_ns);
  f.w().le(m.step_wall_ns);
  f.w().le(static_cast<std::uint16_t>(count));
  for (std::size_t i = 0; i < count; ++i)
    f.w().write(encode(m.vehicles[i]));
  return f.finish();
}

std::vector<std::uint8_t> encode(const DriverChanged& m) {
  FrameWriter f(MessageType::kDriverChanged, 2 + text_size(m.driver, kMaxNameLength));
  f.w().le(m.vehicle);
  f.text(m.driver, kMaxNameLength);
  return f.finish();
}

std::vector<std::uint8_t> encode(const Closing& m) {
  FrameWriter f(MessageType::kClosing, 1 + text_size(m.text, kMaxTextLength));
  f.w().le(static_cast<std::uint8_t>(m.reason));
  f.text(m.text, kMaxTextLength);
  return f.finish();
}

std::vector<std::uint8_t> encode(const SignalStates& m) {
  const std::size_t count = std::min(m.groups.size(), kMaxSignalGroupStates);
  FrameWriter f(MessageType::kSignalStates, kSignalStatesHeadSize + count * kSignalGroupStateSize);
  f.w().le(m.world_time_ms);
  f.w().le(static_cast<std::uint16_t>(count));
  for (std::size_t i = 0; i < count; ++i) {
    const SignalGroupState& g = m.groups[i];
    f.w().le(g.intersection_id);
    f.w().le(g.signal_group);
    f.w().le(static_cast<std::uint8_t>(g.state));
    f.w().le(g.next_change_ms);
    f.w().le(g.likely_change_ms);
  }
  return f.finish();
}

std::vector<std::uint8_t> encode(const ClientMessage& m) {
  return std::visit([](const auto& x) { return encode(x); }, m);
}

std::vector<std::uint8_t> encode(const ServerMessage& m) {
  return std::visit([](const auto& x) { return encode(x); }, m);
}

int clamp(Controls& c) {
  int n = 0;
  auto fix = [&n](float& v, float lo, float hi) {
    if (v < lo || v > hi) {
      v = std::clamp(v, lo, hi);
      ++n;
    }
  };
  fix(c.throttle, 0.0f, 1.0f);
  fix(c.brake, 0.0f, 1.0f);
  fix(c.steer, -1.0f, 1.0f);
  return n;
}

// ---------------------------------------------------------------------------------------------
// Conversation

Expected<bool, ProtocolError> Conversation::check(const ClientMessage& m) const {
  const bool hello = std::holds_alternative<Hello>(m);
  if (hello == greeted_)
    return Unexpected{ProtocolError::kOutOfOrder};
  if (const auto* c = std::get_if<ControlsMsg>(&m); c && !drives(c->vehicle))
    return Unexpected{ProtocolError::kOutOfOrder};
  if (const auto* d = std::get_if<Detach>(&m); d && !drives(d->vehicle))
    return Unexpected{ProtocolError::kOutOfOrder};
  if (const auto* b = std::get_if<ControlsBatch>(&m)) {
    for (const ControlsMsg& e : b->entries) {
      if (!drives(e.vehicle))
        return Unexpected{ProtocolError::kOutOfOrder};
    }
  }
  return true;
}

void Conversation::on_driving(std::uint16_t vehicle) {
  if (drives(vehicle))
    return;
  driven_.push_back(vehicle);
  if (driving_.size() <= vehicle)
    driving_.resize(std::size_t{vehicle} + 1, false);
  driving_[vehicle] = true;
}

void Conversation::on_released(std::uint16_t vehicle) {
  if (!drives(vehicle))
    return;
  std::erase(driven_, vehicle);
  driving_[vehicle] = false;
}

bool Conversation::drives(std::uint16_t vehicle) const {
  return vehicle < driving_.size() && driving_[vehicle];
}

}  // namespace tb::wire::sim
