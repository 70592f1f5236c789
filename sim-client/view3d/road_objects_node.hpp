#pragma once
/// @file Road-side objects and signals from the OpenDRIVE file as simple shapes by type and
/// size: buildings as boxes of their length, width and height (a darker roof), trees as a
/// trunk and a cone, hedges, walls and barriers as boxes along the road, poles and street
/// lamps, signs as a pole and a plate facing the traffic they are for, anything else as a grey
/// box. Marks on the surface (crosswalks, stop lines, arrows) are junction_marks.hpp's.
///
/// Level of detail for town-sized maps on a software renderer: the shapes are merged into one
/// drawable per 100 m tile and size class (few draw calls), each tile an osg::LOD that shows
/// big things (buildings, trees, walls) to kBigRange and small ones (poles, signs, hedges)
/// to kSmallRange only; view-frustum culling works per tile.

#include <array>
#include <cstddef>
#include <string>

#include <osg/Node>
#include <osg/ref_ptr>

#include "common/map/opendrive/road_network.hpp"

namespace tb::client::view3d {

/// Tile edge (m) and how far big and small shapes are drawn (m, from the eye to the tile).
inline constexpr double kObjectTile = 100.0;
inline constexpr float kBigRange = 1500.0f;
inline constexpr float kSmallRange = 220.0f;

struct ObjectsNodeStats {
  std::size_t shapes = 0;     ///< placed objects and signals drawn
  std::size_t triangles = 0;  ///< in all tiles
  std::size_t tiles = 0;
};

/// The shape class of an object type: building, tree, hedge, wall, pole, mark (not drawn here:
/// lies on the road) or box.
std::string shape_of(const map::odr::RoadObject& o);

/// RGB of a sign plate by catalogue type (DE 206 stop: red; 205 give way, 274 speed limit:
/// white; others white).
std::array<float, 3> plate_colour(const map::odr::RoadSignal& g);

/// RGB of a building's walls and of its roof (the walls' colour darkened), picked by the
/// object's id and copy (a repeat's n-th) so that a street is not all one colour.
std::array<float, 3> wall_colour(const std::string& id, std::size_t copy);
std::array<float, 3> roof_colour(const std::string& id, std::size_t copy);

/// Every object and signal of @p net as shapes, tiled with level of detail.
osg::ref_ptr<osg::Node> make_road_objects_node(const map::odr::RoadNetwork& net,
                                               ObjectsNodeStats* stats = nullptr);

}  // namespace tb::client::view3d
