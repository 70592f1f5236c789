#pragma once
/// @file Where a road's objects and signals stand in the world: road coordinates (s, t) on the
/// reference line, lifted by the elevation (and the superelevation at t) and zOffset, turned
/// by the road's heading. Repeats expand into the copies (or pieces of a continuous object)
/// they stand for, so that a renderer or a physics engine only places boxes.

#include <vector>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

/// A position and heading in the inertial frame.
struct ItemPose {
  double x = 0.0, y = 0.0, z = 0.0;  ///< z: the item's base (road surface at (s, t) + zOffset)
  double heading = 0.0;              ///< rad, ccw from x
};

/// The inertial pose of road coordinates (s, t) raised by @p z_offset, turned by @p hdg from
/// the reference line's direction at s.
ItemPose item_pose(const Road& road, double s, double t, double z_offset, double hdg);

/// One standing copy of an object: its pose (the centre of its footprint: of the outline's
/// bounding box where the object has one) and its size.
struct PlacedObject {
  const RoadObject* object = nullptr;
  ItemPose pose;
  double length = 0.0;  ///< along the heading, m
  double width = 0.0;   ///< across it, m
  double height = 0.0;
  double radius = 0.0;  ///< > 0: round (a pole, a tree)
};

/// The copies of @p o: one without <repeat>; with one, a copy every `distance` metres or, for
/// distance 0, pieces of at most @p piece metres following the road (walls, hedges).
std::vector<PlacedObject> place_object(const Road& road, const RoadObject& o, double piece = 5.0);

/// The pose of a signal: heading is the direction of the traffic it is for (the road's at s for
/// orientation "+", the opposite for "-") turned by hOffset; its face looks back against it.
ItemPose signal_pose(const Road& road, const RoadSignal& g);

/// Stop-line signals (DE catalogue 294, and the OpenDRIVE catalogue's "stopLine"/"294").
bool is_stop_line(const RoadSignal& g);

}  // namespace tb::map::odr
