#include "its-station/facilities/can_vehicle_data.hpp"

#include <spdlog/spdlog.h>

#include "common/can/checksum.hpp"

namespace tb::its::facilities {

std::string_view to_string(CanFrameResult r) {
  switch (r) {
    case CanFrameResult::kAccepted:
      return "accepted";
    case CanFrameResult::kUnknownId:
      return "unknown id";
    case CanFrameResult::kWrongLength:
      return "wrong length";
    case CanFrameResult::kBadChecksum:
      return "bad checksum";
    case CanFrameResult::kRepeatedCounter:
      return "repeated alive counter";
    case CanFrameResult::kCounterJump:
      return "alive counter jump";
  }
  return "?";
}

namespace {

// Signals per message, in the order decode() reads them.
struct Layout {
  std::string_view message;
  std::array<std::string_view, 8> signals;
  std::array<std::string_view, 2> optional_signals{};
};
constexpr Layout kSpeed{"VehicleSpeed", {"VehicleSpeed", "DrivingDirection"}};
constexpr Layout kDynamics{"Dynamics",
                           {"YawRate", "LongitudinalAcceleration", "LateralAcceleration"}};
constexpr Layout kSteering{"Steering", {"SteeringWheelAngle"}};
constexpr Layout kPowertrain{"Powertrain", {"ThrottlePedal", "BrakePedal"}};
constexpr Layout kLights{"Lights",
                         {"IndicatorLeft", "IndicatorRight", "HazardLights", "LowBeam", "HighBeam",
                          "ReverseLight", "FogLight"},
                         {"LightBar", "Siren"}};

constexpr double kKmhToMps = 1.0 / 3.6;

}  // namespace

Expected<CanVehicleDecoder, CanSchemaError> CanVehicleDecoder::create(const can::Database& db) {
  std::map<std::uint32_t, Entry> entries;
  const std::pair<const Layout*, Kind> layouts[] = {{&kSpeed, Kind::kSpeed},
                                                    {&kDynamics, Kind::kDynamics},
                                                    {&kSteering, Kind::kSteering},
                                                    {&kPowertrain, Kind::kPowertrain},
                                                    {&kLights, Kind::kLights}};
  for (const auto& [layout, kind] : layouts) {
    const can::Message* m = db.find_message(layout->message);
    if (!m)
      return Unexpected{CanSchemaError{"the DBC has no message " + std::string(layout->message)}};
    Entry e;
    e.message = m;
    e.kind = kind;
    e.counter = m->find_signal("AliveCounter");
    e.checksum = m->find_signal("Checksum");
    if (!e.counter || !e.checksum)
      return Unexpected{
          CanSchemaError{"message " + m->name + " lacks its AliveCounter or Checksum signal"}};
    for (std::size_t i = 0; i < layout->signals.size() && !layout->signals[i].empty(); ++i) {
      e.signals[i] = m->find_signal(layout->signals[i]);
      if (!e.signals[i])
        return Unexpected{CanSchemaError{"message " + m->name + " has no signal " +
                                         std::string(layout->signals[i])}};
    }
    for (std::size_t i = 0; i < layout->optional_signals.size(); ++i)
      if (!layout->optional_signals[i].empty())
        e.optional_signals[i] = m->find_signal(layout->optional_signals[i]);
    entries[m->extended ? (m->id | can::kEffFlag) : m->id] = e;
  }
  return CanVehicleDecoder(std::move(entries));
}

CanFrameResult CanVehicleDecoder::apply(const can::CanFrame& frame, clock::SteadyTime now) {
  auto it = entries_.find(frame.can_id & ~(can::kRtrFlag | can::kErrFlag));
  if (it == entries_.end() || frame.remote() || (frame.can_id & can::kErrFlag)) {
    ++counters_.unknown;
    return CanFrameResult::kUnknownId;
  }
  Entry& e = it->second;
  if (frame.len != e.message->dlc) {
    ++counters_.bad_length;
    return CanFrameResult::kWrongLength;
  }
  const auto data = frame.payload();
  // vehicle.dbc: CRC-8 SAE J1850 over every byte but the checksum's own, in byte order.
  const unsigned at = e.checksum->start_bit / 8;
  std::array<std::uint8_t, can::kMaxFdLen> rest{};
  std::size_t n = 0;
  for (unsigned i = 0; i < frame.len; ++i)
    if (i != at)
      rest[n++] = data[i];
  if (can::crc8_sae_j1850({rest.data(), n}) !=
      static_cast<std::uint8_t>(e.checksum->extract_raw(data))) {
    ++counters_.bad_checksum;
    return CanFrameResult::kBadChecksum;
  }
  const int counter = static_cast<int>(e.counter->extract_raw(data));
  const int modulo = static_cast<int>(e.counter->raw_max()) + 1;
  if (e.last_counter >= 0) {
    const int delta = ((counter - e.last_counter) % modulo + modulo) % modulo;
    if (delta == 0) {
      ++counters_.bad_counter;
      return CanFrameResult::kRepeatedCounter;
    }
    if (delta > static_cast<int>(kMaxCounterGap) + 1) {
      // A sender restart or a long outage: take the counter as the new reference, but do
      // not trust this one frame (as AUTOSAR E2E's "wrong sequence" state does).
      e.last_counter = counter;
      ++counters_.bad_counter;
      return CanFrameResult::kCounterJump;
    }
    counters_.lost += static_cast<std::uint64_t>(delta - 1);
  }
  e.last_counter = counter;
  decode(e, data);
  state_.received = now;
  ++counters_.accepted;
  return CanFrameResult::kAccepted;
}

void CanVehicleDecoder::decode(const Entry& e, std::span<const std::uint8_t> data) {
  auto value = [&](std::size_t i) { return e.signals[i]->decode(data); };
  switch (e.kind) {
    case Kind::kSpeed: {
      const double direction = value(1);  // 0 standstill, 1 forward, 2 reverse
      const bool reverse = direction > 1.5;
      state_.speed_mps = (reverse ? -1.0 : 1.0) * value(0) * kKmhToMps;
      state_.reversing = reverse;
      break;
    }
    case Kind::kDynamics:
      state_.yaw_rate_dps = value(0);
      state_.longitudinal_acceleration_mps2 = value(1);
      state_.lateral_acceleration_mps2 = value(2);
      break;
    case Kind::kSteering:
      state_.steering_wheel_angle_deg = value(0);
      break;
    case Kind::kPowertrain:
      // Any pedal travel counts: the CDD's AccelerationControl says "engaged", not how much.
      state_.gas_pedal = value(0) > 0.0;
      state_.brake_pedal = value(1) > 0.0;
      break;
    case Kind::kLights: {
      std::uint8_t l = 0;
      const bool hazard = value(2) > 0.5;
      if (value(0) > 0.5 || hazard)
        l |= lights::kLeftTurnSignal;
      if (value(1) > 0.5 || hazard)
        l |= lights::kRightTurnSignal;
      if (value(3) > 0.5)
        l |= lights::kLowBeam;
      if (value(4) > 0.5)
        l |= lights::kHighBeam;
      if (value(5) > 0.5)
        l |= lights::kReverse;
      if (value(6) > 0.5)
        l |= lights::kFog;
      state_.exterior_lights = l;
      if (e.optional_signals[0])
        state_.light_bar = e.optional_signals[0]->decode(data) > 0.5;
      if (e.optional_signals[1])
        state_.siren = e.optional_signals[1]->decode(data) > 0.5;
      break;
    }
  }
}

CanVehicleDataProvider::CanVehicleDataProvider(can::CanBus& bus, CanVehicleDecoder decoder,
                                               const clock::Clock& clock)
    : bus_(bus), decoder_(std::move(decoder)), clock_(clock) {}

void CanVehicleDataProvider::start() {
  bus_.start_on_demand([this](const can::CanFrame& frame, std::int64_t) { on_frame(frame); },
                       kBackstop);
}

void CanVehicleDataProvider::take_in() const {
  const clock::SteadyTime now = clock_.steady_now();
  // Not again from inside a read (a listener that asks for current()).
  if (polling_ || (last_poll_ && now - *last_poll_ < kPollInterval))
    return;
  last_poll_ = now;
  ++polls_;
  polling_ = true;
  // The bus hands the frames to on_frame() through the handler given in start().
  bus_.poll();
  polling_ = false;
}

void CanVehicleDataProvider::on_frame(const can::CanFrame& frame) {
  const auto r = decoder_.apply(frame, clock_.steady_now());
  if (r == CanFrameResult::kAccepted) {
    publish(decoder_.state());
  } else if (r != CanFrameResult::kUnknownId && !warned_bad_) {
    spdlog::warn("CAN: dropped frame 0x{:x}: {} (further drops are only counted)", frame.id(),
                 to_string(r));
    warned_bad_ = true;
  }
}

}  // namespace tb::its::facilities
