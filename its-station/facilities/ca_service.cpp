#include "its-station/facilities/ca_service.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include <spdlog/spdlog.h>

#include "common/trace/tracer.hpp"
#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/ssp_permissions.hpp"

namespace tb::its::facilities {

std::optional<messages::SpecialVehicleContainer> special_vehicle_container(
    const CaConfig& config, const VehicleData* vehicle) {
  namespace m = messages;
  m::LightBarSirenInUse lbs = 0;
  if (vehicle && vehicle->light_bar.value_or(false))
    lbs |= m::light_bar_siren::kLightBarActivated;
  if (vehicle && vehicle->siren.value_or(false))
    lbs |= m::light_bar_siren::kSirenActivated;
  switch (config.vehicle_role) {
    case m::VehicleRole::publicTransport:
      return m::PublicTransportContainer{};
    case m::VehicleRole::specialTransport:
      return m::SpecialTransportContainer{0, lbs};
    case m::VehicleRole::dangerousGoods:
      // miscellaneousDangerousSubstances (19) when the configuration names nothing better.
      return m::DangerousGoodsContainer{config.dangerous_goods.value_or(19)};
    case m::VehicleRole::roadWork:
      return m::RoadWorksContainerBasic{std::nullopt, lbs, std::nullopt};
    case m::VehicleRole::rescue:
      return m::RescueContainer{lbs};
    case m::VehicleRole::emergency:
      return m::EmergencyContainer{lbs, std::nullopt, std::nullopt};
    case m::VehicleRole::safetyCar:
      return m::SafetyCarContainer{lbs, std::nullopt, std::nullopt, std::nullopt};
    default:
      return std::nullopt;
  }
}

messages::Cam build_cam(const CaConfig& config, const PositionFix& fix, const VehicleData* vehicle,
                        const messages::PathHistory* low_frequency_path,
                        bool with_special_vehicle) {
  messages::Cam cam;
  cam.header.stationID = config.station_id;
  // EN 302 637-2 B.3: generationDeltaTime is the time of the reference position.
  cam.cam.generationDeltaTime = generation_delta_time(timestamp_its(fix.time));
  auto& p = cam.cam.camParameters;
  p.basicContainer.stationType = config.station_type;
  p.basicContainer.referencePosition = cdd::reference_position(fix);

  if (config.station_type == messages::station_type::kRoadSideUnit) {
    // EN 302 637-2 B.2.2/B.3: an RSU's CAM is its basic container and the RSU high-frequency
    // container; the low-frequency and special-vehicle containers are a vehicle's. No
    // protected communication zones (no CEN DSRC tolling station in the testbed).
    p.highFrequencyContainer = messages::RSUContainerHighFrequency{};
    return cam;
  }
  auto& hf = *messages::vehicle_hf(p);
  hf.heading = cdd::heading(fix.heading_deg, fix.heading_confidence_deg);
  hf.speed.speedValue = cdd::speed_value(fix.speed_mps);
  if (hf.speed.speedValue != messages::kSpeedValueUnavailable)
    hf.speed.speedConfidence = cdd::speed_confidence(fix.speed_confidence_mps);
  if (config.vehicle_length_m) {
    hf.vehicleLength.vehicleLengthValue = static_cast<messages::VehicleLengthValue>(
        std::clamp<long>(std::lround(*config.vehicle_length_m * 10.0), 1, 1022));
    hf.vehicleLength.vehicleLengthConfidenceIndication =
        messages::VehicleLengthConfidenceIndication::noTrailerPresent;
  }
  if (config.vehicle_width_m)
    hf.vehicleWidth = static_cast<messages::VehicleWidth>(
        std::clamp<long>(std::lround(*config.vehicle_width_m * 10.0), 1, 61));

  // DriveDirection is the motion relative to the heading (the orientation): the fix's verdict
  // (ReferencePositionProvider), the reverse gear where the fix has none.
  if (fix.backward)
    hf.driveDirection =
        *fix.backward ? messages::DriveDirection::backward : messages::DriveDirection::forward;
  if (vehicle) {
    if (!fix.backward && vehicle->reversing)
      hf.driveDirection = *vehicle->reversing ? messages::DriveDirection::backward
                                              : messages::DriveDirection::forward;
    hf.longitudinalAcceleration.longitudinalAccelerationValue =
        cdd::acceleration_value(vehicle->longitudinal_acceleration_mps2);
    hf.yawRate = cdd::yaw_rate(vehicle->yaw_rate_dps);
    const auto speed_for_curvature = vehicle->speed_mps ? vehicle->speed_mps : fix.speed_mps;
    hf.curvature = cdd::curvature(vehicle->yaw_rate_dps, speed_for_curvature);
    if (hf.curvature.curvatureValue != messages::kCurvatureValueUnavailable)
      hf.curvatureCalculationMode = messages::CurvatureCalculationMode::yawRateUsed;
    if (vehicle->brake_pedal || vehicle->gas_pedal) {
      messages::AccelerationControl ac = 0;
      if (vehicle->brake_pedal.value_or(false))
        ac |= messages::acceleration_control::kBrakePedalEngaged;
      if (vehicle->gas_pedal.value_or(false))
        ac |= messages::acceleration_control::kGasPedalEngaged;
      hf.accelerationControl = ac;
    }
    if (vehicle->steering_wheel_angle_deg)
      hf.steeringWheelAngle = cdd::steering_wheel_angle(vehicle->steering_wheel_angle_deg);
    if (vehicle->lateral_acceleration_mps2) {
      messages::LateralAcceleration la;
      la.lateralAccelerationValue = cdd::acceleration_value(vehicle->lateral_acceleration_mps2);
      hf.lateralAcceleration = la;
    }
  }

  if (low_frequency_path) {
    messages::BasicVehicleContainerLowFrequency lf;
    lf.vehicleRole = config.vehicle_role;
    lf.exteriorLights = vehicle && vehicle->exterior_lights ? *vehicle->exterior_lights : 0;
    lf.pathHistory = *low_frequency_path;
    p.lowFrequencyContainer = lf;
  }
  if (with_special_vehicle)
    p.specialVehicleContainer = special_vehicle_container(config, vehicle);
  return cam;
}

scenario::CamPolicy effective_policy(const CaConfig& config) {
  if (config.station_type != messages::station_type::kRoadSideUnit)
    return config.policy;
  // EN 302 637-2 clause 6.1.4 (an RSU ITS-S): the vehicle's dynamic conditions of 6.1.3 do
  // not apply to a station that stands still; an RSU generates its CAM at a fixed interval,
  // here T_GenCamMax (1000 ms).
  return {scenario::CamPolicy::Kind::kFixed,
          std::chrono::duration<double, std::milli>(config.timing.T_GenCamMax).count()};
}

CaService::CaService(clock::Runtime& runtime, PositionProvider& position,
                     VehicleDataProvider* vehicle, MessageSender& sender, Ldm& ldm, CaConfig config)
    : runtime_(runtime),
      position_(position),
      vehicle_(vehicle),
      sender_(sender),
      ldm_(ldm),
      config_(config),
      rules_(config.timing, effective_policy(config)) {
  position_.on_fix([this](const PositionFix& fix) {
    auto& tracer = trace::global();
    if (tracer.enabled()) {
      // read_ns: when the gpsd report that completed the fix was read (fix.received, moved
      // from the steady clock to the trace's), so that the report tells gpsd from the uptake.
      const std::int64_t now_ns = trace::Tracer::now_ns();
      tracer.record_at(now_ns, "its.fix",
                       {{"station", config_.station_id},
                        {"fix_ms", clock::to_unix_ns(fix.time) / 1'000'000},
                        {"read_ns", now_ns - (runtime_.steady_now() - fix.received).count()}});
    }
    path_.add(fix);
    if (running_)
      check();
  });
  position_.on_availability([this](bool available) {
    if (!running_)
      return;
    if (available) {
      spdlog::info("CA service: GNSS fix available, CAMs resume");
      reported_no_fix_ = false;
    } else if (!reported_no_fix_) {
      spdlog::warn("CA service: no GNSS fix, no CAMs until it returns");
      reported_no_fix_ = true;
    }
  });
  // Vehicle data only fills the CAM: the conditions of clause 6.1.3 are the fix's heading,
  // position and speed and the time since the last CAM, so a CAN update cannot make a CAM due
  // (the timer covers every instant at which the passing of time can).
}

CaService::~CaService() {
  stop();
}

void CaService::start() {
  running_ = true;
  rules_.reset();
  check();
}

void CaService::stop() {
  running_ = false;
  runtime_.cancel(check_timer_);
}

bool CaService::fix_fits_time_cam(const PositionFix& fix, clock::SteadyTime now) const {
  // A time-based CAM (condition 2, or the fixed policy's period) is made from the fix that
  // describes its due instant: one that arrived at that instant or after it, or at most
  // fresh_fix_wait before it (the GNSS epochs jitter around their 100 ms grid). When the due
  // instant falls between two fixes (T_GenCam, the time between the last two CAMs, need not be
  // a multiple of the fix period), the check of the next fix's arrival makes it: that is at
  // most one T_CheckCamGen later (clause 6.1.3), and the CAM carries a state one fix period
  // newer. Only when no fix comes by time_cam_deadline() is the older fix sent.
  const auto deadline = rules_.time_cam_deadline();
  return fix_of_due_instant(fix) || (deadline && now >= *deadline);
}

bool CaService::fix_of_due_instant(const PositionFix& fix) const {
  const auto due = rules_.next_time_due();
  return !due || fix.received + rules_.timing().fresh_fix_wait >= *due;
}

void CaService::schedule_check() {
  runtime_.cancel(check_timer_);
  const auto now = runtime_.steady_now();
  // At the latest every T_CheckCamGen (≤ T_GenCamMin, clause 6.1.3) ...
  auto when = now + rules_.timing().T_CheckCamGen;
  const auto earlier = [&](std::optional<clock::SteadyTime> t) {
    if (t && *t > now)
      when = std::min(when, *t);
  };
  const auto& fix = position_.current();
  if (const auto last = rules_.last_time(); fix && last) {
    // ... at the instant T_GenCam_Dcc has elapsed if the newest fix meets a condition already:
    // no CAM may come earlier (clause 6.1.3), and this one must carry that fix, not wait for
    // the next check or the next fix. A fix arriving 99.5 ms after the last CAM (jitter) is
    // sent at 100.0 ms.
    const auto dcc = *last + rules_.timing().T_GenCam_Dcc;
    if (dcc > now && rules_.check(dcc, *fix) != CamTrigger::kNone)
      earlier(dcc);
    // ... when a time-based CAM falls due and the newest fix is the one of that instant ...
    if (fix_of_due_instant(*fix))
      earlier(rules_.next_time_due());
    // ... and when it can wait no longer for a fresh fix.
    earlier(rules_.time_cam_deadline());
  }
  check_timer_ = runtime_.schedule_at(when, [this] { check(); });
}

void CaService::check() {
  const auto& fix = position_.current();
  if (!fix) {
    ++counters_.suppressed_no_fix;
    if (!reported_no_fix_) {
      spdlog::warn("CA service: no GNSS fix, no CAMs until it returns");
      reported_no_fix_ = true;
    }
    // The next CAM after the fix returns is a first CAM again (fresh LF container too).
    rules_.reset();
    schedule_check();
    return;
  }
  const auto now = runtime_.steady_now();
  auto why = rules_.check(now, *fix);
  if ((why == CamTrigger::kTime || why == CamTrigger::kFixed) && !fix_fits_time_cam(*fix, now))
    why = CamTrigger::kNone;
  if (why != CamTrigger::kNone)
    generate(why, *fix);
  schedule_check();
}

void CaService::generate(CamTrigger why, const PositionFix& fix) {
  const auto now = runtime_.steady_now();
  const std::int64_t fix_ms = clock::to_unix_ns(fix.time) / 1'000'000;
  trace::global().record("its.cam_build",
                         {{"station", config_.station_id},
                          {"fix_ms", fix_ms},
                          {"gdt", unsigned{generation_delta_time(timestamp_its(fix.time))}},
                          {"trigger", to_string(why)}});
  std::optional<messages::PathHistory> path;
  if (rules_.low_frequency_due(now))
    path = path_.build(fix);
  const VehicleData* vd = vehicle_ && vehicle_->current() ? &*vehicle_->current() : nullptr;
  // Clause 6.1.3: the special-vehicle container in the first CAM, then once 500 ms or more
  // have passed since the last CAM that carried it.
  const bool special = rules_.special_vehicle_due(now);
  const auto cam = build_cam(config_, fix, vd, path ? &*path : nullptr, special);

  // Tracing: the build ends and the encoding starts here (p3.build | p3.encode).
  const std::int64_t encode_ns = trace::global().enabled() ? trace::Tracer::now_ns() : 0;
  std::array<std::uint8_t, messages::kCamMaxEncodedSize> buf;
  auto n = messages::encode(cam, buf);
  if (!n) {
    ++counters_.encode_errors;
    spdlog::error("CA service: cannot encode CAM: {}", asn1::to_string(n.error()));
    return;
  }
  rules_.generated(now, fix, why);
  if (path)
    rules_.low_frequency_sent(now);
  if (cam.cam.camParameters.specialVehicleContainer)
    rules_.special_vehicle_sent(now);
  // its.cam_tx marks the hand-over to the network (end of p3, start of t4): stamped before the
  // send, which on a veth or hwsim radio already delivers the frame to the medium and beyond;
  // sent_ns when the send returned, the frame on the interface (end of t4).
  const std::int64_t handed_ns = trace::Tracer::now_ns();
  const auto result = sender_.send_single_hop(kBtpPortCam, std::span(buf.data(), *n));
  const std::int64_t sent_ns = trace::Tracer::now_ns();
  if (result != SendResult::kSent) {
    ++counters_.send_errors;
    spdlog::warn("CA service: CAM not sent: {}", to_string(result));
  } else {
    ++counters_.sent;
  }
  trace::global().record_at(handed_ns, "its.cam_tx",
                            {{"station", config_.station_id},
                             {"fix_ms", fix_ms},
                             {"gdt", unsigned{cam.cam.generationDeltaTime}},
                             {"bytes", *n},
                             {"lf", path.has_value()},
                             {"encode_ns", encode_ns},
                             {"sent_ns", sent_ns}});
  for (auto& l : sent_listeners_)
    l(cam, why, fix);
}

void CaService::set_shared_decoder(SharedCamDecoder* decoder) {
  decoder_ = decoder;
  if (decoder != nullptr)
    ldm_.share_sender_index(decoder->senders());
}

void CaService::receive(std::span<const std::uint8_t> payload, clock::WallTime rx_time,
                        std::optional<std::span<const std::uint8_t>> ssp) {
  // Decoded into the object the LDM keeps (issue 33: no copy per station).
  auto decoded = decoder_ ? decoder_->decode(payload) : decode_shared_cam(payload);
  if (!decoded) {
    ++counters_.decode_errors;
    spdlog::debug("CA service: dropped undecodable CAM: {}", asn1::to_string(decoded.error()));
    return;
  }
  std::shared_ptr<const messages::Cam> cam = std::move(*decoded);
  if (cam->header.stationID == config_.station_id) {
    ++counters_.own_dropped;
    return;
  }
  if (ssp) {
    if (const auto missing = cam_not_permitted(*cam, *ssp)) {
      ++counters_.not_permitted;
      spdlog::debug("CA service: dropped CAM of {}: its AT does not permit {}",
                    cam->header.stationID, missing->name);
      return;
    }
  }
  ++counters_.received;
  const auto from = cam->header.stationID;
  const unsigned gdt = cam->cam.generationDeltaTime;
  if (config_.trace_receptions)
    trace::global().record("its.cam_rx",
                           {{"station", config_.station_id}, {"from", from}, {"gdt", gdt}});
  ldm_.add_cam(std::move(cam), rx_time, decoder_ ? decoder_->sender_row() : SenderIndex::kNoRow);
  if (config_.trace_receptions)
    trace::global().record("its.ldm",
                           {{"station", config_.station_id}, {"from", from}, {"gdt", gdt}});
}

}  // namespace tb::its::facilities
