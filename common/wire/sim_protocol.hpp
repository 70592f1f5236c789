#pragma once
/// @file The sim-server ⇄ sim-client protocol over TCP (sim-server/PROTOCOL.md), version 7.
///
/// Every message is one frame: an 8-byte header (magic "SP", protocol version, message type,
/// payload length, little-endian) and a payload whose size is bounded per type. FrameParser is a
/// pure, incremental state machine fed with whatever bytes the socket delivered; decode_*()
/// turn a complete frame into a message; Conversation checks the order of a client's messages
/// on the server. Nothing here touches a socket or a clock.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/util/expected.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::wire::sim {

/// 2: Controls carries the time its input was sampled (input_ns), for the latency trace's t1.
/// 3: Welcome carries the OpenDRIVE map's text, so that a client needs no map file.
/// 4: Welcome carries the world's start time (docs/time.md: one clock for the whole world).
/// 5: Closing's reason "scenario finished", so that a client can tell the end of the scenario
///    (it exits) from a server that stops (it reconnects).
/// 6: ControlsBatch, the controls of all of a client's vehicles for one step in one message
///    (DESIGN.md: a message carries what belongs to one instant): 1000 scripted vehicles sent
///    100,000 Controls a second, more than the server read.
/// 7: SignalStates, the traffic lights of every junction (issue 34).
inline constexpr std::uint8_t kProtocolVersion = 7;
inline constexpr std::uint8_t kMagic0 = 'S';
inline constexpr std::uint8_t kMagic1 = 'P';
inline constexpr std::size_t kHeaderSize = 8;

/// Limits every peer enforces; a frame beyond them closes the connection.
inline constexpr std::size_t kMaxNameLength = 64;          ///< client and driver names, bytes
inline constexpr std::size_t kMaxTextLength = 255;         ///< ids, colours, reasons, bytes
inline constexpr std::size_t kMaxScenarioText = 1u << 20;  ///< scenario JSON in Welcome
inline constexpr std::size_t kMaxMapText = 32u << 20;      ///< OpenDRIVE text in Welcome
inline constexpr std::size_t kMaxVehicles = 4096;
inline constexpr std::size_t kMaxClientPayload = 64;  ///< client → server, but ControlsBatch
inline constexpr std::size_t kMaxServerPayload = 4u << 20;  ///< server → client but Welcome
/// Welcome: the vehicle list (at most ~2.3 MiB), the scenario and the map.
inline constexpr std::size_t kMaxWelcomePayload = kMaxScenarioText + kMaxMapText + (4u << 20);

enum class MessageType : std::uint8_t {
  // client → server
  kHello = 0x01,
  kAttach = 0x02,
  kControls = 0x03,
  kDetach = 0x04,
  kControlsBatch = 0x05,
  // server → client
  kWelcome = 0x81,
  kAttachResult = 0x82,
  kState = 0x83,
  kDriverChanged = 0x84,
  kClosing = 0x85,
  kSignalStates = 0x86,
};
std::string_view to_string(MessageType t);

/// Which peer sent the bytes a parser reads: decides the accepted types and size limits.
enum class Sender { kClient, kServer };

enum class ProtocolError : std::uint8_t {
  kBadMagic = 1,
  kUnsupportedVersion,
  kUnknownType,   ///< not a type this sender may send
  kOversized,     ///< declared payload larger than the type's bound
  kBadLength,     ///< payload shorter or longer than its fields
  kBadText,       ///< a string too long or with control characters
  kNotFinite,     ///< NaN or infinity in a number
  kBadValue,      ///< an enum or count outside its range
  kBadState,      ///< a vehicle record that tb::wire::decode rejects
  kOutOfOrder,    ///< a message the conversation does not allow now
  kParserFailed,  ///< fed again after an error
};
std::string_view to_string(ProtocolError e);

// ---------------------------------------------------------------------------------------------
// Client → server.

/// First message of every connection.
struct Hello {
  std::string client_name;  ///< ≤ kMaxNameLength printable bytes, shown in logs and to others
  bool operator==(const Hello&) const = default;
};

enum class Role : std::uint8_t { kWatcher = 0, kDriver = 1 };

/// Start the state stream (watcher) or drive a vehicle, given by its index in Welcome's list.
/// A connection may drive several vehicles; each vehicle has at most one driver.
struct Attach {
  Role role = Role::kWatcher;
  std::uint16_t vehicle = 0;  ///< ignored for watchers
  bool operator==(const Attach&) const = default;
};

/// Driver input for one vehicle the connection drives; holds until the next Controls.
/// Values outside their ranges are accepted on the wire and clamped (and counted) by the
/// server; NaN or infinity is malformed.
struct ControlsMsg {
  std::uint16_t vehicle = 0;
  Controls controls;
  std::uint16_t lights = 0;  ///< Light bits the driver switches (indicators, beams, fog, ...)
  /// When the client sampled the input these controls come from (CLOCK_REALTIME ns; 0 when
  /// unknown). Only traced by the server (t1, docs/tracing.md), never acted on: any value is
  /// accepted.
  std::int64_t input_ns = 0;
  bool operator==(const ControlsMsg&) const = default;
};

/// Stop driving a vehicle; it brakes to a stop as if its driver had disconnected.
struct Detach {
  std::uint16_t vehicle = 0;
  bool operator==(const Detach&) const = default;
};

/// Controls of several vehicles the connection drives, for one step: what a client driving many
/// vehicles sends per State frame instead of one Controls each. Each entry acts as one
/// Controls; a vehicle listed twice gets its later entry. The whole batch is refused (and the
/// connection closed) when any entry is malformed or names a vehicle the connection does not
/// drive, so that no part of it is applied.
struct ControlsBatch {
  std::vector<ControlsMsg> entries;  ///< 1 – kMaxVehicles
  bool operator==(const ControlsBatch&) const = default;
};
/// Bytes of one ControlsBatch entry (a Controls payload) and the batch's payload bound.
inline constexpr std::size_t kControlsEntrySize = 2 + 4 * 3 + 1 + 2 + 8;
inline constexpr std::size_t kMaxControlsBatchPayload = 2 + kMaxVehicles * kControlsEntrySize;

using ClientMessage = std::variant<Hello, Attach, ControlsMsg, Detach, ControlsBatch>;

// ---------------------------------------------------------------------------------------------
// Server → client.

enum class DriverKind : std::uint8_t { kHuman = 0, kTimeline = 1, kLaneFollow = 2 };

struct VehicleInfo {
  std::uint16_t index = 0;
  std::string id;
  std::uint32_t station_id = 0;
  std::uint8_t station_type = 5;
  std::string color;  ///< "#rrggbb"
  DriverKind driver_kind = DriverKind::kHuman;
  float length_m = 0, width_m = 0, height_m = 0;
  float wheelbase_m = 0, track_m = 0, wheel_radius_m = 0;
  float max_steer_rad = 0;  ///< road-wheel angle at full lock
  std::string driver;       ///< name of the client driving it, empty when nobody does
  bool operator==(const VehicleInfo&) const = default;
};

/// The server's answer to Hello: what the world is. The scenario JSON is the file the server
/// loaded and the map text the OpenDRIVE file its map names (empty for a built-in layout), so
/// that clients build the same map without any file of their own
/// (tb::scenario::parse(scenario_json, name, map_text)).
struct Welcome {
  std::string server_name;
  std::int64_t step_ns = 0;  ///< physics step
  /// UTC of sim time 0, Unix ns: the scenario's pinned start_time, else the host's clock when
  /// sim-server started (rounded to the second). World UTC = this + sim time.
  std::int64_t world_start_ns = 0;
  std::vector<VehicleInfo> vehicles;
  std::string scenario_json;
  std::string map_text;
  bool operator==(const Welcome&) const = default;
};

enum class AttachStatus : std::uint8_t {
  kOk = 0,
  kUnknownVehicle = 1,
  kAlreadyDriven = 2,  ///< another client drives it; reason names that client
  kRefused = 3,        ///< any other reason, given in `reason`
};
std::string_view to_string(AttachStatus s);

struct AttachResult {
  Role role = Role::kWatcher;
  std::uint16_t vehicle = 0;
  AttachStatus status = AttachStatus::kOk;
  std::string reason;  ///< empty on success
  bool operator==(const AttachResult&) const = default;
};

/// All vehicles after one physics step, in Welcome's order.
struct StateFrame {
  std::uint64_t tick = 0;
  std::int64_t sim_time_ns = 0;
  std::int64_t step_wall_ns = 0;
  std::vector<VehicleState> vehicles;
  bool operator==(const StateFrame&) const = default;
};

/// Someone attached to or left a vehicle (sent to every attached client).
struct DriverChanged {
  std::uint16_t vehicle = 0;
  std::string driver;  ///< empty: nobody drives it now
  bool operator==(const DriverChanged&) const = default;
};

enum class CloseReason : std::uint8_t {
  kProtocolError = 1,     ///< the client sent something malformed or out of order
  kTooSlow = 2,           ///< the client did not read the state stream fast enough
  kShutdown = 3,          ///< the server stops (a signal): a client reconnects
  kScenarioFinished = 4,  ///< the scenario's duration is over: nothing more will come
};
std::string_view to_string(CloseReason r);

/// The last message before the server closes a connection.
struct Closing {
  CloseReason reason = CloseReason::kShutdown;
  std::string text;
  bool operator==(const Closing&) const = default;
};

/// DSRC MovementPhaseState (ISO TS 19091 / SAE J2735 DSRC module): the state of a signal group.
enum class MovementPhaseState : std::uint8_t {
  kUnavailable = 0,
  kDark = 1,
  kStopThenProceed = 2,
  kStopAndRemain = 3,  ///< red
  kPreMovement = 4,    ///< red + amber
  kPermissiveMovementAllowed = 5,
  kProtectedMovementAllowed = 6,  ///< green
  kPermissiveClearance = 7,
  kProtectedClearance = 8,  ///< amber
  kCautionConflictingTraffic = 9,
};
/// The DSRC name ("stop-And-Remain", "protected-Movement-Allowed", ...).
std::string_view to_string(MovementPhaseState s);

/// One signal group's state. Times are world-clock UTC, Unix ms (docs/time.md); only the
/// SPATEM turns them into TimeMarks.
struct SignalGroupState {
  std::uint16_t intersection_id = 0;  ///< IntersectionID: the OpenDRIVE junction id
  std::uint8_t signal_group = 0;      ///< SignalGroupID 1..254: the OpenDRIVE controller id
  MovementPhaseState state = MovementPhaseState::kUnavailable;
  /// When the state ends (SPAT minEndTime); 0: no change planned.
  std::int64_t next_change_ms = 0;
  /// When it most likely ends (SPAT likelyTime); 0: unknown. Fixed-time plans: next_change_ms.
  std::int64_t likely_change_ms = 0;
  bool operator==(const SignalGroupState&) const = default;
};

/// Every signal group of every junction, as of one physics step: sent to every attached client
/// in each step where a state changes, else once a second, and to a client right after its
/// Welcome. Entries strictly ascending by (intersection, signal group).
struct SignalStates {
  std::int64_t world_time_ms = 0;        ///< UTC of the step (start time + sim time), Unix ms
  std::vector<SignalGroupState> groups;  ///< at most kMaxSignalGroupStates
  bool operator==(const SignalStates&) const = default;
};
inline constexpr std::size_t kMaxSignalGroupStates = 4096;
inline constexpr std::size_t kSignalGroupStateSize = 2 + 1 + 1 + 8 + 8;

using ServerMessage =
    std::variant<Welcome, AttachResult, StateFrame, DriverChanged, Closing, SignalStates>;

// ---------------------------------------------------------------------------------------------
// Framing.

struct Frame {
  MessageType type = MessageType::kHello;
  std::vector<std::uint8_t> payload;
};

/// Incremental frame parser. Feed it any slice of the byte stream; it consumes bytes up to the
/// end of one frame and reports kFrame when frame() holds a complete one. After an error it
/// stays failed (the connection has lost framing and must be closed).
class FrameParser {
 public:
  enum class Status { kNeedMore, kFrame };

  explicit FrameParser(Sender from) : from_(from) {}

  /// Consumes bytes from the front of @p data (advancing it) until a frame is complete or the
  /// bytes run out. Header errors are reported as soon as the 8 header bytes are in, before any
  /// payload is buffered.
  Expected<Status, ProtocolError> parse(std::span<const std::uint8_t>& data);
  /// The last complete frame; valid until the next parse().
  const Frame& frame() const { return frame_; }

 private:
  enum class Step { kHeader, kPayload, kFailed };
  Expected<Status, ProtocolError> check_header();

  Sender from_;
  Step step_ = Step::kHeader;
  std::array<std::uint8_t, kHeaderSize> header_{};
  std::size_t header_fill_ = 0;
  std::size_t payload_size_ = 0;
  Frame frame_;
};

/// Payload bound of @p type when sent by @p from; 0 for a type that sender may not send.
std::size_t max_payload(Sender from, MessageType type);

Expected<ClientMessage, ProtocolError> decode_client(const Frame& f);
Expected<ServerMessage, ProtocolError> decode_server(const Frame& f);

/// Complete frames (header + payload), ready to write to a socket.
std::vector<std::uint8_t> encode(const Hello& m);
std::vector<std::uint8_t> encode(const Attach& m);
std::vector<std::uint8_t> encode(const ControlsMsg& m);
std::vector<std::uint8_t> encode(const Detach& m);
/// At most kMaxVehicles entries are encoded (the encoder's caller owns the limit).
std::vector<std::uint8_t> encode(const ControlsBatch& m);
std::vector<std::uint8_t> encode(const Welcome& m);
std::vector<std::uint8_t> encode(const AttachResult& m);
std::vector<std::uint8_t> encode(const StateFrame& m);
std::vector<std::uint8_t> encode(const DriverChanged& m);
std::vector<std::uint8_t> encode(const Closing& m);
/// At most kMaxSignalGroupStates entries are encoded, in the order given.
std::vector<std::uint8_t> encode(const SignalStates& m);
std::vector<std::uint8_t> encode(const ClientMessage& m);
std::vector<std::uint8_t> encode(const ServerMessage& m);

/// Encodes a state frame straight from the server's vehicle array, stamping @p send_wall_ns
/// into every record (one encoding is shared by all clients).
std::vector<std::uint8_t> encode_state(std::uint64_t tick, std::int64_t sim_time_ns,
                                       std::int64_t step_wall_ns,
                                       std::span<const VehicleState> vehicles,
                                       std::int64_t send_wall_ns);

/// Clamps throttle and brake to [0, 1] and steer to [-1, 1]; returns how many were out of
/// range (the server counts them).
int clamp(Controls& c);

/// Order of a client's messages, as the server sees them: Hello first and once; Controls,
/// ControlsBatch and Detach only for vehicles this connection drives (the server reports
/// successful driver attachments with on_driving()). drives() is a lookup, not a search: it runs
/// for every entry of every batch.
class Conversation {
 public:
  Expected<bool, ProtocolError> check(const ClientMessage& m) const;
  void on_driving(std::uint16_t vehicle);
  void on_released(std::uint16_t vehicle);
  void on_hello() { greeted_ = true; }
  bool greeted() const { return greeted_; }
  bool drives(std::uint16_t vehicle) const;
  const std::vector<std::uint16_t>& driven() const { return driven_; }

 private:
  bool greeted_ = false;
  std::vector<std::uint16_t> driven_;
  std::vector<bool> driving_;  ///< by vehicle index, grown on demand
};

}  // namespace tb::wire::sim
