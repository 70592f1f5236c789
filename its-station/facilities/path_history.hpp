#pragma once
/// @file The station's recent path, for the CAM low-frequency container (CDD PathHistory).

#include <deque>

#include "its-station/facilities/position.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::facilities {

/// Records past fixes at a spacing that keeps the curve (a point every 5 m, or sooner when the
/// heading turned by more than 4°), and turns them into PathPoints relative to a reference
/// fix: each point an offset from the one before it (the first from the reference position),
/// as TS 102 894-2 DF PathHistory defines. Covers up to 40 points or 200 m, whichever is
/// reached first (EN 302 637-2 B.3.5's recommendation for passenger cars).
class PathHistoryRecorder {
 public:
  static constexpr double kSpacingM = 5.0;
  static constexpr double kHeadingStepDeg = 4.0;
  static constexpr double kMaxLengthM = 200.0;

  void add(const PositionFix& fix);
  void clear() { points_.clear(); }
  /// The path behind @p reference (points newer than it are skipped).
  messages::PathHistory build(const PositionFix& reference) const;
  std::size_t recorded() const { return points_.size(); }

 private:
  struct Point {
    clock::WallTime time;
    double latitude_deg, longitude_deg;
    std::optional<double> heading_deg;
  };
  std::deque<Point> points_;  ///< newest first
};

}  // namespace tb::its::facilities
