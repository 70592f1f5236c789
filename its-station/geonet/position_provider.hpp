#pragma once
/// @file Where the router gets its ego position vector (EPV, EN 302 636-4-1 clause 8.2): the
/// facilities' positioning service implements PositionProvider.

#include <optional>

#include "common/clock/clock.hpp"

namespace tb::its::geonet {

struct EgoPosition {
  /// When the fix was taken (UTC); becomes the position vector's TST.
  clock::WallTime time{};
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double speed_mps = 0.0;    ///< negative when reversing
  double heading_deg = 0.0;  ///< clockwise from north
  /// PAI: whether the position's confidence is within itsGnPaiInterval (clause 9.5.2).
  bool accurate = false;
};

class PositionProvider {
 public:
  virtual ~PositionProvider() = default;
  /// The latest fix, or nullopt while there is none; the router sends nothing but what it must
  /// forward until there is one.
  virtual std::optional<EgoPosition> current_position() const = 0;
};

/// A provider that returns what it was last given (tests, fixed road-side units, tools).
class StaticPositionProvider final : public PositionProvider {
 public:
  std::optional<EgoPosition> current_position() const override { return position_; }
  void set(const EgoPosition& p) { position_ = p; }
  void clear() { position_.reset(); }

 private:
  std::optional<EgoPosition> position_;
};

}  // namespace tb::its::geonet
