#pragma once
/// @file The marks painted at junctions, from the OpenDRIVE file: stop lines (signals of the
/// German catalogue's type 294, and "stopLine" signals or roadMark objects), zebra crossings
/// (crosswalk objects) and lane arrows (roadMark objects whose subtype or name says arrow).
///
/// Choices: a stop line is 0.5 m deep (the StVO's Haltlinie in towns) across the signal's
/// width, else the lane's; a crossing's stripes run along the object's heading (hdg 0: along
/// the road), 0.5 m wide with 0.5 m gaps across its width; an arrow points along the object's
/// heading. Like the lane marks (road_node.hpp) they lie kMarkLift above the surface with a
/// polygon offset and are drawn after the road, so that they never z-fight.

#include <array>
#include <cstddef>
#include <vector>

#include <osg/Node>
#include <osg/ref_ptr>

#include "common/map/opendrive/road_network.hpp"

namespace tb::client::view3d {

/// A painted patch: two triangles over four corners, counter-clockwise seen from above.
struct MarkQuad {
  enum class Kind { kStopLine, kCrosswalk, kArrow };
  Kind kind = Kind::kStopLine;
  std::array<float, 3> colour{1, 1, 1};
  std::array<std::array<double, 3>, 4> corners{};
};

/// The junction marks of @p net (renderer-free, so that tests can check them).
std::vector<MarkQuad> junction_mark_quads(const map::odr::RoadNetwork& net);

/// All junction marks as one drawable; @p count gets the number of quads.
osg::ref_ptr<osg::Node> make_junction_marks_node(const map::odr::RoadNetwork& net,
                                                 std::size_t* count = nullptr);

}  // namespace tb::client::view3d
