#pragma once
/// @file The road network model read from ASAM OpenDRIVE 1.4-1.7: roads with their planView,
/// profiles and lane sections, and junctions. Plain data plus the evaluation every consumer
/// needs (reference line, lane borders); queries that need an index live in lane_locator.hpp
/// and lane_graph.hpp. Road and junction ids are strings, as the standard allows.

#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/map/opendrive/geometry.hpp"

namespace tb::map::odr {

/// A bad input file: which file, where in it (an XPath-like element path such as
/// `road[@id='5']/planView/geometry[2]`) and why.
class MapError : public std::runtime_error {
 public:
  MapError(std::string file, std::string path, const std::string& reason);
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

 private:
  std::string file_;
  std::string path_;
};

/// a + b ds + c ds^2 + d ds^3 from `s` on (the record form of elevation, superelevation,
/// laneOffset, lane width and border).
struct CubicRecord {
  double s = 0.0;
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
};

/// Piecewise cubic over s: each record holds from its s to the next record's s.
class CubicProfile {
 public:
  CubicProfile() = default;
  explicit CubicProfile(std::vector<CubicRecord> records) : records_(std::move(records)) {}
  bool empty() const { return records_.empty(); }
  const std::vector<CubicRecord>& records() const { return records_; }
  double value(double s) const;       ///< 0 where no record holds
  double derivative(double s) const;  ///< d value / ds

 private:
  const CubicRecord* at(double s) const;
  std::vector<CubicRecord> records_;
};

enum class ContactPoint { kNone, kStart, kEnd };

struct RoadMark {
  double s_offset = 0.0;
  std::string type = "none";  ///< solid, broken, solid solid, botts dots, ...
  std::string color = "standard";
  double width = 0.12;       ///< m; 0.12 where the file gives none
  double line_length = 3.0;  ///< broken marks: painted length (m), 3 m unless <type><line>
  double space = 9.0;        ///< broken marks: gap (m), 9 m unless <type><line>
};

struct SpeedLimit {
  double s = 0.0;    ///< lane: offset from the section start; road: s on the road
  double max = 0.0;  ///< m/s; +inf for "no limit"
};

struct Lane {
  int id = 0;
  std::string type = "none";
  bool drivable = false;  ///< a vehicle may drive it (driving, entry, exit, ramps, bus, ...)
  bool level = false;
  CubicProfile width;   ///< s of each record relative to the section start (sOffset)
  CubicProfile border;  ///< alternative to width: outer border t from the centre lane
  std::optional<int> predecessor;
  std::optional<int> successor;
  bool has_link = false;  ///< the file gave a <link> element with predecessor or successor
  std::vector<RoadMark> marks;
  std::vector<SpeedLimit> speeds;
};

struct LaneSection {
  double s = 0.0;
  double s_end = 0.0;
  bool single_side = false;
  std::vector<Lane> left;   ///< ids 1, 2, ... in this order (outwards)
  Lane center;              ///< id 0
  std::vector<Lane> right;  ///< ids -1, -2, ... in this order (outwards)
  const Lane* lane(int id) const;
};

struct RoadLink {
  bool to_junction = false;
  std::string id;
  ContactPoint contact = ContactPoint::kNone;
  int index = -1;  ///< resolved index into roads or junctions
};

struct RoadType {
  double s = 0.0;
  std::string type;
  std::optional<double> max_speed;  ///< m/s
};

/// Lateral borders of every lane at one s: t of the outer border, centre lane at `center`.
struct LaneBorders {
  double center = 0.0;        ///< t of the centre lane (laneOffset)
  std::vector<double> left;   ///< left[i]: outer border of lane i+1
  std::vector<double> right;  ///< right[i]: outer border of lane -(i+1)
  /// Inner and outer t of lane @p id (outer > inner on the left, < on the right).
  double inner(int id) const;
  double outer(int id) const;
};

/// A point of the road surface with its orientation.
struct SurfacePose {
  double x = 0.0, y = 0.0, z = 0.0;
  double heading = 0.0;  ///< rad, ccw from x (east), of the road's s direction
  double pitch = 0.0;    ///< rad, positive uphill along s
  double roll = 0.0;     ///< rad, superelevation: positive raises the left (+t) side
};

/// <repeat> of an object (OpenDRIVE 1.7, 13.3): copies every `distance` metres along
/// [s, s + length], or one continuous object (a wall, a fence, a hedge) where distance is 0;
/// t, size and height go linearly from their start to their end value.
struct ObjectRepeat {
  double s = 0.0;
  double length = 0.0;
  double distance = 0.0;
  double t_start = 0.0, t_end = 0.0;
  double z_offset_start = 0.0, z_offset_end = 0.0;
  std::optional<double> height_start, height_end;
  std::optional<double> width_start, width_end;
  std::optional<double> length_start, length_end;
  std::optional<double> radius_start, radius_end;
};

/// One corner of an object's outline in its local frame (<cornerLocal>, 13.2): u along the
/// object's heading, v to its left, z up from its base, height of the outline there.
struct OutlineCorner {
  double u = 0.0, v = 0.0, z = 0.0, height = 0.0;
};

/// <object> (OpenDRIVE 1.7, 13): a road-side or road-surface item placed at road
/// coordinates. Sizes are 0 where the file gives none; `radius` > 0 makes it round.
struct RoadObject {
  std::string id;
  std::string type = "none";  ///< e.g. pole, tree, vegetation, barrier, building, crosswalk
  std::string subtype;
  std::string name;
  double s = 0.0, t = 0.0;
  double z_offset = 0.0;
  double hdg = 0.0;  ///< rad, relative to the reference line's direction at s
  double pitch = 0.0, roll = 0.0;
  double length = 0.0, width = 0.0, height = 0.0, radius = 0.0;
  std::string orientation = "none";  ///< "+", "-" or "none"
  std::vector<ObjectRepeat> repeats;
  std::vector<OutlineCorner> outline;  ///< the first <outline>'s <cornerLocal>s, if any
};

/// Lanes from..to of a road, inclusive (a <validity> element).
struct LaneRange {
  int from = 0;
  int to = 0;
};

/// <signal> (OpenDRIVE 1.7, 14): a sign, a light or a road mark (e.g. DE 294 stop line) of a
/// national catalogue, placed at road coordinates.
struct RoadSignal {
  std::string id;
  std::string name;
  double s = 0.0, t = 0.0;
  double z_offset = 0.0;  ///< the plate's lower edge above the road
  double h_offset = 0.0;  ///< rad, heading relative to the orientation's direction
  double pitch = 0.0, roll = 0.0;
  std::string orientation = "+";  ///< valid for traffic along s ("+"), against ("-"), both
  bool dynamic = false;
  std::string country;  ///< e.g. DE, OpenDRIVE
  std::string type;     ///< catalogue number (DE 206 stop sign, DE 294 stop line), "-1" none
  std::string subtype;
  std::optional<double> value;
  std::string unit;
  std::string text;
  double height = 0.0, width = 0.0;  ///< m; 0 where the file gives none
  /// <validity> (14.3): the lanes it holds for, from..to inclusive each; empty: every lane of
  /// its orientation.
  std::vector<LaneRange> validity;
  /// Whether it holds for lane @p lane_id by its validity (orientation not considered).
  bool valid_for(int lane_id) const;
};

/// <signalReference> / <objectReference>: an item of another road also valid on this one.
struct ItemReference {
  std::string id;  ///< the referenced signal's or object's id
  double s = 0.0, t = 0.0;
  std::string orientation = "none";
};

struct Road {
  std::string id;
  std::string name;
  double length = 0.0;
  std::string junction = "-1";
  int junction_index = -1;
  bool left_hand_traffic = false;  ///< rule="LHT": left lanes run along s
  std::optional<RoadLink> predecessor;
  std::optional<RoadLink> successor;
  std::vector<std::unique_ptr<Geometry>> geometries;
  CubicProfile elevation;
  CubicProfile superelevation;
  CubicProfile lane_offset;
  std::vector<LaneSection> sections;
  std::vector<RoadType> types;
  std::vector<RoadObject> objects;
  std::vector<RoadSignal> signals;
  std::vector<ItemReference> object_references;
  std::vector<ItemReference> signal_references;

  RefPoint reference(double s) const;
  double curvature(double s) const;
  std::size_t section_index(double s) const;
  LaneBorders borders(std::size_t section, double s) const;
  /// The surface at road coordinates (s, t).
  SurfacePose surface(double s, double t) const;
  /// Whether lane @p id runs in the direction of growing s.
  bool forward(int lane_id) const { return left_hand_traffic ? lane_id > 0 : lane_id < 0; }
  /// Speed limit of the road type at s (m/s), if the file gives one.
  std::optional<double> speed_limit(double s) const;
};

struct LaneLink {
  int from = 0;
  int to = 0;
};

struct Connection {
  std::string id;
  std::string incoming;
  std::string connecting;  ///< connectingRoad, or linkedRoad in a direct junction
  ContactPoint contact = ContactPoint::kNone;
  int incoming_index = -1;
  int connecting_index = -1;
  std::vector<LaneLink> lane_links;
};

/// <controller> inside a <junction> (10.9): a controller the junction's signals run by.
struct JunctionController {
  std::string id;  ///< a top-level Controller's id
  std::string type;
  std::optional<int> sequence;
};

struct Junction {
  std::string id;
  std::string name;
  std::string type = "default";  ///< default, direct (1.7), virtual
  std::vector<Connection> connections;
  std::vector<JunctionController> controllers;
};

/// <control> of a controller: one dynamic signal it switches.
struct Control {
  std::string signal_id;
  std::string type;
};

/// Top-level <controller> (14.7): dynamic signals that always show the same state. In the
/// testbed its id is a decimal 1..254, the SignalGroupID (ISO TS 19091) of the manoeuvres its
/// signals govern; the reader refuses any other.
struct Controller {
  std::string id;
  std::string name;
  std::optional<int> sequence;
  std::vector<Control> controls;
  int signal_group() const { return std::stoi(id); }
};

struct Header {
  int rev_major = 1;
  int rev_minor = 0;
  std::string name;
  std::string date;
  std::string vendor;
  double north = 0, south = 0, east = 0, west = 0;
  std::string geo_reference;  ///< the PROJ string, trimmed; empty when the file has none
  bool has_offset = false;    ///< 1.6 <offset>: inertial = file + offset (kept, not applied)
  double offset_x = 0, offset_y = 0, offset_z = 0, offset_hdg = 0;
};

struct RoadNetwork {
  std::string source;  ///< the file it came from, for messages
  Header header;
  std::vector<Road> roads;
  std::vector<Junction> junctions;
  std::vector<Controller> controllers;
  std::vector<std::string> warnings;  ///< things read but not modelled, each named once

  /// Index of the road / junction with that id; -1 when there is none.
  int road_index(const std::string& id) const;
  int junction_index(const std::string& id) const;
  /// Which end of a connection's incoming road touches junction @p junction: the end whose
  /// road link names the junction, else the end the connecting road's own link names.
  ContactPoint incoming_end(const Connection& c, std::size_t junction) const;
};

/// Lane types a vehicle drives on (OpenDRIVE 1.7 clause 9.5.3).
bool is_drivable(const std::string& lane_type);

}  // namespace tb::map::odr
