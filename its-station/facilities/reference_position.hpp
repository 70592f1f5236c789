#pragma once
/// @file The station's own position as the CAM and the applications need it: the vehicle's
/// orientation instead of the receiver's course, and the CAM reference point instead of the
/// antenna.
///
/// A GNSS receiver knows where its antenna is and which way it moves (course over ground). The
/// CDD's Heading is the orientation of the vehicle (TS 102 894-2 DE Heading; EN 302 637-2
/// B.3 heading of the vehicle's body), and a vehicle's reference position is the ground
/// position of the centre of the front side of its bounding box (EN 302 637-2 annex B,
/// TS 102 894-2 DF ReferencePosition). While reversing the course points out of the tail and
/// the antenna (a roof antenna at the centre, say) is half a car behind the reference point;
/// both are corrected here, once, for every consumer (CA service, GN ego position, LCRW, HMI).

#include <optional>

#include "its-station/facilities/position.hpp"
#include "its-station/facilities/vehicle_data.hpp"

namespace tb::its::facilities {

/// Orientation from course and drive direction.
///
/// The drive direction comes from the vehicle, not the receiver: the sign of the wheel speed
/// while the wheels turn, otherwise the reverse gear (CAN). Moving backward, the orientation is
/// the course turned by 180°. Below kMinSpeedMps the course is noise (or a held value of an
/// earlier motion), so the last orientation is kept; before any, the course is the best guess.
class OrientationFromCourse {
 public:
  /// Below this speed over ground the course does not tell the orientation (gpsd reports no
  /// track below about this, and the GNSS agent holds its last course below 0.2 m/s).
  static constexpr double kMinSpeedMps = 0.3;
  /// Wheel speeds below this say nothing about the direction (standstill, creeping).
  static constexpr double kMinWheelSpeedMps = 0.1;

  struct Result {
    std::optional<double> heading_deg;
    std::optional<bool> backward;  ///< empty when the vehicle gives no direction
  };

  /// Moving backward per the vehicle's signals, or empty when they do not tell.
  static std::optional<bool> moving_backward(const VehicleData* vehicle);

  Result update(const PositionFix& raw, const VehicleData* vehicle);
  void reset() { last_heading_deg_.reset(); }

 private:
  std::optional<double> last_heading_deg_;
};

/// Where the GNSS antenna sits on the vehicle, and the vehicle's length.
struct AntennaGeometry {
  /// 0 when the vehicle is not known (no scenario): the fix then stays where the antenna is.
  double vehicle_length_m = 0.0;
  double antenna_forward_m = 0.0;  ///< of the bounding-box centre, along the orientation
  double antenna_left_m = 0.0;     ///< of the bounding-box centre, across
};

/// Moves a fix from the antenna to the reference point (front centre of the bounding box) along
/// @p heading_deg (the orientation). The position confidence is kept: the lever arm is known
/// and the orientation error it adds (≤ 0.1 m for 3 m and 2°) is far below the GNSS error.
PositionFix antenna_to_reference_point(const PositionFix& antenna_fix, double heading_deg,
                                       const AntennaGeometry& geometry);

/// A PositionProvider that republishes every fix of @p gnss with the orientation
/// (OrientationFromCourse) and at the reference point (antenna_to_reference_point).
class ReferencePositionProvider final : public PositionProvider {
 public:
  /// @p gnss and @p vehicle (may be null: no drive direction, orientation = course) must
  /// outlive this object.
  ReferencePositionProvider(PositionProvider& gnss, const VehicleDataProvider* vehicle,
                            AntennaGeometry geometry);

  /// The conversion of one fix, for tests and tools; updates the orientation state.
  PositionFix convert(const PositionFix& raw);

 private:
  const VehicleDataProvider* vehicle_;
  AntennaGeometry geometry_;
  OrientationFromCourse orientation_;
};

}  // namespace tb::its::facilities
