#pragma once
/// @file The station's own position, and the interface the services take it from.
///
/// Services never talk to gpsd: they subscribe to a PositionProvider, which hands every new
/// fix over as soon as it exists (no polling period, issue 8). Tests inject fixes by hand.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::its::facilities {

/// One GNSS fix in SI units. Confidences are 95 % values, as the CDD's confidence data
/// elements are (TS 102 894-2, DF PosConfidenceEllipse, DE SpeedConfidence, HeadingConfidence);
/// an empty optional means the receiver gave no usable estimate.
struct PositionFix {
  clock::WallTime time;        ///< UTC instant the fix describes (the receiver's fix time)
  clock::SteadyTime received;  ///< when the station got it, for ages and latency traces
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  std::optional<double> altitude_m;  ///< height above the ellipsoid
  std::optional<double> speed_mps;   ///< over ground, never negative
  /// Course over ground as the receiver reports it (direction of motion), clockwise from north,
  /// [0, 360).
  std::optional<double> course_deg;
  /// The vehicle's orientation (CDD Heading), clockwise from north, [0, 360). A bare receiver
  /// cannot tell it from the course and sets it to the course (forward driving);
  /// ReferencePositionProvider derives it from course and drive direction.
  std::optional<double> heading_deg;
  /// The vehicle moves against its orientation (CDD DriveDirection backward); empty: unknown
  /// (a bare receiver's fix).
  std::optional<bool> backward;

  /// 95 % horizontal position error ellipse.
  struct Ellipse {
    double semi_major_m = 0.0;
    double semi_minor_m = 0.0;
    double orientation_deg = 0.0;  ///< of the semi-major axis, clockwise from north, [0, 180)
  };
  std::optional<Ellipse> position_confidence;
  std::optional<double> altitude_confidence_m;
  std::optional<double> speed_confidence_mps;
  std::optional<double> heading_confidence_deg;
};

/// Source of the station's own fixes. Listeners run synchronously, in subscription order, on
/// the thread that delivers the fix (the program's io_context thread).
class PositionProvider {
 public:
  using FixListener = std::function<void(const PositionFix&)>;
  /// Called with true when a fix is (again) available, false when it is lost.
  using AvailabilityListener = std::function<void(bool)>;

  virtual ~PositionProvider() = default;

  /// The newest fix, if the receiver currently has one.
  const std::optional<PositionFix>& current() const { return current_; }

  void on_fix(FixListener l) { fix_listeners_.push_back(std::move(l)); }
  void on_availability(AvailabilityListener l) { availability_listeners_.push_back(std::move(l)); }

 protected:
  /// For implementations: a new fix arrived.
  void publish(const PositionFix& fix);
  /// For implementations: the receiver reports no fix (or went away).
  void publish_loss();

 private:
  std::optional<PositionFix> current_;
  std::vector<FixListener> fix_listeners_;
  std::vector<AvailabilityListener> availability_listeners_;
};

/// A provider fed by hand: tests, and replay tools.
class InjectedPositionProvider final : public PositionProvider {
 public:
  void inject(const PositionFix& fix) { publish(fix); }
  void lose_fix() { publish_loss(); }
};

}  // namespace tb::its::facilities
