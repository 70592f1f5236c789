#include "its-station/facilities/reference_position.hpp"

#include <cmath>
#include <numbers>

#include "common/geodesy/local_frame.hpp"

namespace tb::its::facilities {

std::optional<bool> OrientationFromCourse::moving_backward(const VehicleData* vehicle) {
  if (!vehicle)
    return std::nullopt;
  // The wheels' sense of rotation says how the car moves, whatever the gear (rolling back on a
  // slope in first gear is backward); at standstill the selected gear says how it will move.
  if (vehicle->speed_mps && std::abs(*vehicle->speed_mps) >= kMinWheelSpeedMps)
    return *vehicle->speed_mps < 0.0;
  if (vehicle->reversing)
    return *vehicle->reversing;
  if (vehicle->speed_mps)
    return false;
  return std::nullopt;
}

OrientationFromCourse::Result OrientationFromCourse::update(const PositionFix& raw,
                                                            const VehicleData* vehicle) {
  Result r;
  r.backward = moving_backward(vehicle);
  const bool moving = raw.speed_mps && *raw.speed_mps >= kMinSpeedMps;
  if (raw.course_deg && moving) {
    last_heading_deg_ = geodesy::wrap_360(*raw.course_deg + (r.backward.value_or(false) ? 180 : 0));
  } else if (!last_heading_deg_ && raw.course_deg) {
    return {raw.course_deg, r.backward};  // no motion seen yet: the course is all there is
  }
  r.heading_deg = last_heading_deg_;
  return r;
}

PositionFix antenna_to_reference_point(const PositionFix& antenna_fix, double heading_deg,
                                       const AntennaGeometry& g) {
  const double forward = 0.5 * g.vehicle_length_m - g.antenna_forward_m;
  const double left = -g.antenna_left_m;
  if (forward == 0.0 && left == 0.0)
    return antenna_fix;
  const double h = heading_deg * std::numbers::pi / 180.0;
  // Forward is (sin h, cos h) in (east, north); left of it is (-cos h, sin h).
  const geodesy::Enu offset{forward * std::sin(h) - left * std::cos(h),
                            forward * std::cos(h) + left * std::sin(h), 0.0};
  // A frame at the antenna: exact ellipsoidal ENU over a few metres.
  const geodesy::LocalFrame at_antenna(geodesy::Geodetic{
      antenna_fix.latitude_deg, antenna_fix.longitude_deg, antenna_fix.altitude_m.value_or(0.0)});
  const geodesy::Geodetic p = at_antenna.to_geodetic(offset);
  PositionFix out = antenna_fix;
  out.latitude_deg = p.latitude_deg;
  out.longitude_deg = p.longitude_deg;
  return out;
}

ReferencePositionProvider::ReferencePositionProvider(PositionProvider& gnss,
                                                     const VehicleDataProvider* vehicle,
                                                     AntennaGeometry geometry)
    : vehicle_(vehicle), geometry_(geometry) {
  gnss.on_fix([this](const PositionFix& raw) { publish(convert(raw)); });
  gnss.on_availability([this](bool available) {
    if (!available)
      publish_loss();
  });
}

PositionFix ReferencePositionProvider::convert(const PositionFix& raw) {
  const VehicleData* vd = vehicle_ && vehicle_->current() ? &*vehicle_->current() : nullptr;
  const auto o = orientation_.update(raw, vd);
  PositionFix fix = raw;
  fix.heading_deg = o.heading_deg;
  fix.backward = o.backward;
  if (fix.heading_deg)
    fix = antenna_to_reference_point(fix, *fix.heading_deg, geometry_);
  // Without any orientation the antenna position is the best there is.
  return fix;
}

}  // namespace tb::its::facilities
