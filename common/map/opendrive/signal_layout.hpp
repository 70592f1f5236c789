#pragma once
/// @file The traffic lights of a network as the testbed runs them (issue 34): each top-level
/// <controller> is one signal group (its id the SignalGroupID of ISO TS 19091), each signalised
/// junction one intersection (its id the IntersectionID), and each lane that enters a junction
/// under a light an approach with the governing signal group and where its stop line is. The
/// signal controllers in sim-server, the RSU's MAPEM, the scripted drivers and the views read
/// this one index.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/map/opendrive/road_network.hpp"
#include "common/map/opendrive/road_objects.hpp"

namespace tb::map::odr {

/// A dynamic signal (a traffic light head) where it stands.
struct SignalHead {
  const RoadSignal* signal = nullptr;
  int road = -1;  ///< index into RoadNetwork::roads
  double s = 0.0, t = 0.0;
  std::string orientation;          ///< "+", "-" or "none"
  std::vector<LaneRange> validity;  ///< empty: every lane of its orientation
  ItemPose pose;  ///< (x, y) at (s, t); z the head's lower edge; heading the traffic's
  double height = 0.0;
  int signal_group = 0;  ///< its controller's id; 0 for a light no controller switches
};

/// One controller: the lights that always show the same state.
struct SignalGroup {
  int id = 0;                      ///< SignalGroupID 1..254 (= the controller's id)
  std::size_t controller = 0;      ///< index into RoadNetwork::controllers
  std::vector<std::size_t> heads;  ///< indices into SignalLayout::heads()
  int junction = -1;               ///< the junction it serves (index), -1 if none
};

/// A junction with traffic lights: an intersection in MAPEM/SPATEM terms.
struct SignalisedJunction {
  std::size_t junction = 0;  ///< index into RoadNetwork::junctions
  std::uint16_t intersection_id = 0;
  std::vector<int> groups;  ///< its signal groups, ascending
};

/// A lane that enters a junction under a traffic light.
struct SignalApproach {
  int road = -1;  ///< the incoming road (index)
  int lane = 0;
  std::size_t junction = 0;  ///< index into RoadNetwork::junctions
  std::uint16_t intersection_id = 0;
  int signal_group = 0;
  std::size_t head = 0;        ///< the governing light, index into SignalLayout::heads()
  double stop_s = 0.0;         ///< s of the stop line on the incoming road
  bool has_stop_line = false;  ///< a stop-line signal (294) gives stop_s; else the light's s
  SurfacePose stop;  ///< the stop line on the lane's centre; heading: the direction of travel
};

/// The index, built once from a network. @throws MapError (file, element, value) for a light's
/// controller that its junction does not list, a controller serving two junctions, or a
/// signalised junction whose id is not a decimal 0..65535.
class SignalLayout {
 public:
  explicit SignalLayout(const RoadNetwork& net);

  const std::vector<SignalHead>& heads() const { return heads_; }
  /// Ascending by id.
  const std::vector<SignalGroup>& groups() const { return groups_; }
  const std::vector<SignalisedJunction>& junctions() const { return junctions_; }
  const std::vector<SignalApproach>& approaches() const { return approaches_; }

  const SignalGroup* group(int id) const;
  /// The signalised junction of that OpenDRIVE id; nullptr when it has no lights or none is.
  const SignalisedJunction* junction(const std::string& junction_id) const;
  /// The approach for a lane that enters a junction under a light; nullptr for any other lane
  /// (@p road: index into RoadNetwork::roads).
  const SignalApproach* approach(int road, int lane) const;

 private:
  const RoadNetwork& net_;
  std::vector<SignalHead> heads_;
  std::vector<SignalGroup> groups_;
  std::vector<SignalisedJunction> junctions_;
  std::vector<SignalApproach> approaches_;
};

}  // namespace tb::map::odr
