#pragma once
/// @file The traffic lights of the 3D view (issue 34): at each dynamic signal of the map's
/// SignalLayout a housing with three lamps (red over amber over green) facing the traffic it is
/// for, lit by the state of its signal group in the latest SignalStates.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <osg/Group>
#include <osg/ref_ptr>

#include "common/map/opendrive/road_network.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-client/view3d/vehicle_node.hpp"

namespace tb::client::view3d {

/// Which lamps of a head show a state (ISO TS 19091 MovementPhaseState as a vehicle signal
/// head shows it): red for stop-And-Remain, red and amber for pre-Movement, amber for the
/// clearances, green for the movements allowed; stop-Then-Proceed (a flashing red) and
/// caution-Conflicting-Traffic (a flashing amber) light their lamp in the first half of each
/// second of @p sim_time_ns; dark and unavailable none.
struct LampSet {
  bool red = false, amber = false, green = false;
  bool operator==(const LampSet&) const = default;
};
LampSet lamps_for(wire::sim::MovementPhaseState s, std::int64_t sim_time_ns = 0);

class SignalHeadsNode {
 public:
  enum LampIndex { kRed = 0, kAmber = 1, kGreen = 2 };

  /// The heads of @p net's SignalLayout. A map whose lights the layout refuses gets none (the
  /// scenario loader refuses such a map before a client sees it).
  explicit SignalHeadsNode(const map::odr::RoadNetwork& net);
  osg::Group* node() const { return root_.get(); }

  /// Lights every head by its group's state in @p states (every junction's); a head whose group
  /// is missing, or that no controller switches, is dark.
  void update(std::span<const wire::sim::SignalGroupState> states, std::int64_t sim_time_ns);

  std::size_t heads() const { return heads_.size(); }
  /// The centre of a lamp's face, world frame (tests look at the pixel it projects to).
  osg::Vec3d lamp_centre(std::size_t head, LampIndex lamp) const;
  /// What the last update lit at @p head.
  LampSet lit(std::size_t head) const;

 private:
  struct Head {
    std::uint16_t intersection_id = 0;
    int signal_group = 0;
    std::array<osg::Vec3d, 3> centres;
    std::array<std::unique_ptr<Lamp>, 3> lamps;
  };
  osg::ref_ptr<osg::Group> root_;
  std::vector<Head> heads_;
};

}  // namespace tb::client::view3d
