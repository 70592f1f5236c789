#include "common/map/opendrive/reader.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace tb::map::odr {

namespace {

/// How far past a road's end an item's s may lie, taken as the end: files round s, and some
/// exporters place an item a little past the end of the road it belongs to.
constexpr double kSTolerance = 1.0;
/// The largest object or signal dimension (m): big buildings, long walls are in range.
constexpr double kMaxObjectSize = 5000.0;
/// The most copies one <repeat> may make.
constexpr double kMaxRepeatCopies = 10000.0;

/// Reads one document into a RoadNetwork, carrying the file name and element paths for errors.
class Reader {
 public:
  explicit Reader(std::string source) { net_.source = std::move(source); }

  RoadNetwork read(std::string_view xml) {
    pugi::xml_document doc;
    const pugi::xml_parse_result ok = doc.load_buffer(xml.data(), xml.size());
    if (!ok) {
      fail("", "malformed XML at byte " + std::to_string(ok.offset) + ": " + ok.description());
    }
    const pugi::xml_node root = doc.child("OpenDRIVE");
    if (!root)
      fail("", "no <OpenDRIVE> root element");
    read_header(root.child("header"));
    for (pugi::xml_node r : root.children("road"))
      read_road(r);
    for (pugi::xml_node j : root.children("junction"))
      read_junction(j);
    for (pugi::xml_node c : root.children("controller"))
      read_controller(c);
    if (net_.roads.empty())
      fail("", "no <road>");
    resolve_links();
    resolve_controllers();
    if (skipped_structures_ > 0) {
      net_.warnings.push_back(std::to_string(skipped_structures_) + " <tunnel>/<bridge> skipped");
    }
    for (const std::string& w : ignored_)
      net_.warnings.push_back(w);
    for (std::string& w : not_applied_)
      net_.warnings.push_back(std::move(w));
    return std::move(net_);
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw MapError(net_.source, path, reason);
  }

  void ignore_once(const std::string& what) { ignored_.insert(what + " ignored"); }

  /// A 1.6/1.7 element that changes the geometry but is not applied to it: one warning per
  /// occurrence, naming the file, the element's path (road and lane) and the values.
  void not_applied(const std::string& path, const std::string& what) {
    not_applied_.push_back(net_.source + ": " + path + ": " + what + " not applied");
  }

  double number(pugi::xml_node n, const char* name, const std::string& path) const {
    const pugi::xml_attribute a = n.attribute(name);
    if (!a)
      fail(path, std::string("attribute '") + name + "' missing");
    return parse_number(a.value(), name, path);
  }

  double number_or(pugi::xml_node n, const char* name, double fallback,
                   const std::string& path) const {
    const pugi::xml_attribute a = n.attribute(name);
    return a ? parse_number(a.value(), name, path) : fallback;
  }

  double parse_number(const char* text, const char* name, const std::string& path) const {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text, &end);
    while (end != nullptr && (*end == ' ' || *end == '\t'))
      ++end;
    if (end == text || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
      fail(path, std::string("attribute '") + name + "' is not a finite number: '" + text + "'");
    }
    if (std::fabs(v) > kMaxCoordinate) {
      fail(path, std::string("attribute '") + name + "' is " + text +
                     ", beyond the largest magnitude a map may give (1e8)");
    }
    return v;
  }

  int integer(pugi::xml_node n, const char* name, const std::string& path) const {
    const double v = number(n, name, path);
    if (v != std::floor(v) || std::fabs(v) > 1e6) {
      fail(path, std::string("attribute '") + name + "' is not an integer: '" +
                     n.attribute(name).value() + "'");
    }
    return static_cast<int>(v);
  }

  std::string text(pugi::xml_node n, const char* name, const std::string& path) const {
    const pugi::xml_attribute a = n.attribute(name);
    if (!a || a.value()[0] == '\0')
      fail(path, std::string("attribute '") + name + "' missing");
    return a.value();
  }

  static std::string indexed(const std::string& parent, const char* name, int i) {
    return (parent.empty() ? "" : parent + "/") + name + "[" + std::to_string(i) + "]";
  }

  void read_header(pugi::xml_node h) {
    if (!h) {
      ignore_once("missing <header> (OpenDRIVE 1.0 assumed)");
      return;
    }
    Header& hd = net_.header;
    hd.rev_major = h.attribute("revMajor") ? integer(h, "revMajor", "header") : 1;
    hd.rev_minor = h.attribute("revMinor") ? integer(h, "revMinor", "header") : 0;
    hd.name = h.attribute("name").value();
    hd.date = h.attribute("date").value();
    hd.vendor = h.attribute("vendor").value();
    hd.north = number_or(h, "north", 0, "header");
    hd.south = number_or(h, "south", 0, "header");
    hd.east = number_or(h, "east", 0, "header");
    hd.west = number_or(h, "west", 0, "header");
    if (pugi::xml_node g = h.child("geoReference")) {
      std::string s = g.child_value();
      const auto b = s.find_first_not_of(" \t\r\n");
      const auto e = s.find_last_not_of(" \t\r\n");
      hd.geo_reference = b == std::string::npos ? "" : s.substr(b, e - b + 1);
    }
    if (pugi::xml_node o = h.child("offset")) {
      hd.has_offset = true;
      hd.offset_x = number_or(o, "x", 0, "header/offset");
      hd.offset_y = number_or(o, "y", 0, "header/offset");
      hd.offset_z = number_or(o, "z", 0, "header/offset");
      hd.offset_hdg = number_or(o, "hdg", 0, "header/offset");
      if (hd.offset_x != 0 || hd.offset_y != 0 || hd.offset_z != 0 || hd.offset_hdg != 0) {
        not_applied("header/offset",
                    "<offset x=\"" + std::string(o.attribute("x").value()) + "\" y=\"" +
                        o.attribute("y").value() + "\" z=\"" + o.attribute("z").value() +
                        "\" hdg=\"" + o.attribute("hdg").value() +
                        "\"> (the inertial frame's shift; coordinates are the file's)");
      }
    }
  }

  static ContactPoint contact(pugi::xml_node n) {
    const std::string c = n.attribute("contactPoint").value();
    if (c == "start")
      return ContactPoint::kStart;
    if (c == "end")
      return ContactPoint::kEnd;
    return ContactPoint::kNone;
  }

  std::optional<RoadLink> road_link(pugi::xml_node n, const std::string& path) const {
    if (!n)
      return std::nullopt;
    RoadLink l;
    const std::string type = n.attribute("elementType").value();
    if (type == "junction") {
      l.to_junction = true;
    } else if (type != "road") {
      fail(path, "elementType must be 'road' or 'junction', got '" + type + "'");
    }
    l.id = text(n, "elementId", path);
    l.contact = contact(n);
    return l;
  }

  void read_road(pugi::xml_node r) {
    Road road;
    road.id = text(r, "id", "road[" + std::to_string(net_.roads.size() + 1) + "]");
    const std::string path = "road[@id='" + road.id + "']";
    if (!road_ids_.emplace(road.id, static_cast<int>(net_.roads.size())).second) {
      fail(path, "duplicate road id '" + road.id + "'");
    }
    road.name = r.attribute("name").value();
    road.length = number(r, "length", path);
    if (!(road.length > 0))
      fail(path, "length must be > 0, got " + std::string(r.attribute("length").value()));
    if (road.length > kMaxRoadLength) {
      fail(path, "length " + std::string(r.attribute("length").value()) +
                     " is longer than a road may be (100 km)");
    }
    total_length_ += road.length;
    if (total_length_ > kMaxNetworkLength)
      fail(path, "the roads up to this one are longer than a map may be (10,000 km in all)");
    road.junction = r.attribute("junction") ? r.attribute("junction").value() : "-1";
    if (road.junction.empty())
      road.junction = "-1";
    road.left_hand_traffic = std::string(r.attribute("rule").value()) == "LHT";
    if (pugi::xml_node link = r.child("link")) {
      road.predecessor = road_link(link.child("predecessor"), path + "/link/predecessor");
      road.successor = road_link(link.child("successor"), path + "/link/successor");
    }
    int ti = 0;
    for (pugi::xml_node t : r.children("type")) {
      const std::string tp = indexed(path, "type", ++ti);
      RoadType rt;
      rt.s = number(t, "s", tp);
      rt.type = t.attribute("type").value();
      if (pugi::xml_node sp = t.child("speed"))
        rt.max_speed = speed(sp, tp + "/speed");
      road.types.push_back(rt);
    }
    read_plan_view(r.child("planView"), road, path);
    if (pugi::xml_node e = r.child("elevationProfile")) {
      road.elevation = profile(e, "elevation", "s", path + "/elevationProfile");
    }
    if (pugi::xml_node lp = r.child("lateralProfile")) {
      road.superelevation = profile(lp, "superelevation", "s", path + "/lateralProfile");
      const auto& recs = road.superelevation.records();
      has_superelevation_ = std::any_of(recs.begin(), recs.end(), [](const CubicRecord& c) {
        return c.a != 0 || c.b != 0 || c.c != 0 || c.d != 0;
      });
      if (lp.child("crossfall"))
        ignore_once("lateralProfile <crossfall>");
      if (lp.child("shape"))
        ignore_once("lateralProfile <shape>");
    }
    read_lanes(r.child("lanes"), road, path);
    has_superelevation_ = false;
    check_extent(road, path);
    read_objects_and_signals(r, road, path);
    net_.roads.push_back(std::move(road));
  }

  /// Lanes within kMaxLateral of the reference line, curves no tighter than kMaxCurvature,
  /// heights within kMaxCoordinate: looked at every 5 m and at every record start. Absurd
  /// values (1e300-wide lanes, 1 mm radii) would make the lane index and the meshes explode.
  void check_extent(const Road& road, const std::string& path) {
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const LaneSection& ls = road.sections[k];
      std::vector<double> ss{ls.s, ls.s_end};
      for (double s = ls.s; s < ls.s_end; s += 5.0)
        ss.push_back(s);
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const Lane& l : *side) {
          for (const auto* prof : {&l.width, &l.border}) {
            for (const CubicRecord& r : prof->records())
              ss.push_back(std::min(ls.s + r.s, ls.s_end));
          }
        }
      }
      for (const CubicRecord& r : road.lane_offset.records())
        ss.push_back(std::clamp(r.s, ls.s, ls.s_end));
      const std::string p = indexed(path + "/lanes", "laneSection", static_cast<int>(k) + 1);
      for (double s : ss) {
        const LaneBorders b = road.borders(k, s);
        double reach = std::fabs(b.center);
        for (double v : b.left)
          reach = std::max(reach, std::fabs(v));
        for (double v : b.right)
          reach = std::max(reach, std::fabs(v));
        if (!(reach <= kMaxLateral)) {
          fail(p, "lanes reach " + std::to_string(reach) + " m from the reference line at s " +
                      std::to_string(s) + ", more than a map may have (1000 m)");
        }
      }
    }
    for (const auto& g : road.geometries) {
      for (double f : {0.0, 0.5, 1.0}) {
        const double s = g->s0() + f * g->length();
        const double k = road.curvature(std::min(s, road.length));
        if (!(std::fabs(k) <= kMaxCurvature)) {
          fail(path + "/planView", "curvature " + std::to_string(k) + " /m at s " +
                                       std::to_string(s) +
                                       " is tighter than a road may turn (10 /m: 0.1 m radius)");
        }
      }
    }
    for (double s = 0.0; s <= road.length; s += std::max(5.0, road.length / 1000.0)) {
      const double z = road.elevation.value(s);
      if (!(std::fabs(z) <= kMaxCoordinate)) {
        fail(path + "/elevationProfile",
             "elevation " + std::to_string(z) + " m at s " + std::to_string(s) + " out of range");
      }
    }
  }

  /// <objects> and <signals> (OpenDRIVE 1.7, 13 and 14); tunnels and bridges are counted.
  void read_objects_and_signals(pugi::xml_node r, Road& road, const std::string& path) {
    if (pugi::xml_node o = r.child("objects")) {
      int i = 0, ri = 0;
      for (pugi::xml_node c : o.children()) {
        const std::string n = c.name();
        if (n == "object") {
          road.objects.push_back(object(c, road, indexed(path + "/objects", "object", ++i)));
        } else if (n == "objectReference") {
          road.object_references.push_back(
              reference(c, road, indexed(path + "/objects", "objectReference", ++ri)));
        } else if (n == "tunnel" || n == "bridge") {
          ++skipped_structures_;
        }
      }
    }
    if (pugi::xml_node sg = r.child("signals")) {
      int i = 0, ri = 0;
      for (pugi::xml_node c : sg.children()) {
        const std::string n = c.name();
        if (n == "signal") {
          road.signals.push_back(signal(c, road, indexed(path + "/signals", "signal", ++i)));
        } else if (n == "signalReference") {
          road.signal_references.push_back(
              reference(c, road, indexed(path + "/signals", "signalReference", ++ri)));
        }
      }
    }
  }

  /// s on the road (a little past either end is rounding, not an error).
  double road_s(pugi::xml_node n, const Road& road, const std::string& path) const {
    const double s = number(n, "s", path);
    if (s < -kSTolerance || s > road.length + kSTolerance) {
      fail(path, "attribute 's' is " + std::string(n.attribute("s").value()) +
                     ", outside the road (0 to " + std::to_string(road.length) + ")");
    }
    return std::clamp(s, 0.0, road.length);
  }

  /// A size: >= 0 and at most kMaxSize (a 100 km wide building would only blow the meshes up).
  double size_or(pugi::xml_node n, const char* name, double fallback,
                 const std::string& path) const {
    const double v = number_or(n, name, fallback, path);
    if (v < 0.0 || v > kMaxObjectSize) {
      fail(path, std::string("attribute '") + name + "' is " + n.attribute(name).value() +
                     ", not a size between 0 and " + std::to_string(int(kMaxObjectSize)) + " m");
    }
    return v;
  }

  std::string orientation(pugi::xml_node n, const char* fallback, const std::string& path) const {
    const pugi::xml_attribute a = n.attribute("orientation");
    if (!a)
      return fallback;
    const std::string v = a.value();
    if (v != "+" && v != "-" && v != "none")
      fail(path, "attribute 'orientation' must be '+', '-' or 'none', got '" + v + "'");
    return v;
  }

  RoadObject object(pugi::xml_node n, const Road& road, const std::string& at) {
    RoadObject o;
    o.id = text(n, "id", at);
    const std::string path = at.substr(0, at.rfind('[')) + "[@id='" + o.id + "']";
    o.type = n.attribute("type") ? n.attribute("type").value() : "none";
    o.subtype = n.attribute("subtype").value();
    o.name = n.attribute("name").value();
    o.s = road_s(n, road, path);
    o.t = number(n, "t", path);
    check_lateral(o.t, "t", n, path);
    o.z_offset = number_or(n, "zOffset", 0.0, path);
    o.hdg = number_or(n, "hdg", 0.0, path);
    o.pitch = number_or(n, "pitch", 0.0, path);
    o.roll = number_or(n, "roll", 0.0, path);
    o.length = size_or(n, "length", 0.0, path);
    o.width = size_or(n, "width", 0.0, path);
    o.height = size_or(n, "height", 0.0, path);
    o.radius = size_or(n, "radius", 0.0, path);
    o.orientation = orientation(n, "none", path);
    int i = 0;
    for (pugi::xml_node rp : n.children("repeat"))
      o.repeats.push_back(repeat(rp, road, indexed(path, "repeat", ++i)));
    pugi::xml_node outline = n.child("outlines").child("outline");
    if (!outline)
      outline = n.child("outline");  // OpenDRIVE 1.4 has one <outline> without <outlines>
    int k = 0;
    for (pugi::xml_node c : outline.children("cornerLocal")) {
      const std::string cp = indexed(path + "/outline", "cornerLocal", ++k);
      OutlineCorner oc;
      oc.u = number(c, "u", cp);
      oc.v = number(c, "v", cp);
      check_lateral(oc.u, "u", c, cp);
      check_lateral(oc.v, "v", c, cp);
      oc.z = number_or(c, "z", 0.0, cp);
      oc.height = size_or(c, "height", 0.0, cp);
      o.outline.push_back(oc);
    }
    if (outline && outline.child("cornerRoad"))
      ignore_once("object outline <cornerRoad>");
    return o;
  }

  ObjectRepeat repeat(pugi::xml_node n, const Road& road, const std::string& path) const {
    ObjectRepeat r;
    r.s = road_s(n, road, path);
    r.length = number(n, "length", path);
    if (r.length < 0.0 || r.s + r.length > road.length + kSTolerance) {
      fail(path, "attribute 'length' is " + std::string(n.attribute("length").value()) +
                     ": the repeat must lie on the road (s " + std::to_string(r.s) + " to " +
                     std::to_string(road.length) + ")");
    }
    r.length = std::min(r.length, road.length - r.s);
    r.distance = number(n, "distance", path);
    if (r.distance < 0.0)
      fail(path, "attribute 'distance' is negative: '" +
                     std::string(n.attribute("distance").value()) + "'");
    if (r.distance > 0.0 && r.length / r.distance > kMaxRepeatCopies) {
      fail(path, "attribute 'distance' " + std::string(n.attribute("distance").value()) +
                     " makes more than 10000 copies over " + std::to_string(r.length) + " m");
    }
    r.t_start = number(n, "tStart", path);
    r.t_end = number(n, "tEnd", path);
    check_lateral(r.t_start, "tStart", n, path);
    check_lateral(r.t_end, "tEnd", n, path);
    r.z_offset_start = number_or(n, "zOffsetStart", 0.0, path);
    r.z_offset_end = number_or(n, "zOffsetEnd", 0.0, path);
    auto opt = [&](const char* name) -> std::optional<double> {
      if (!n.attribute(name))
        return std::nullopt;
      return size_or(n, name, 0.0, path);
    };
    r.height_start = opt("heightStart");
    r.height_end = opt("heightEnd");
    r.width_start = opt("widthStart");
    r.width_end = opt("widthEnd");
    r.length_start = opt("lengthStart");
    r.length_end = opt("lengthEnd");
    r.radius_start = opt("radiusStart");
    r.radius_end = opt("radiusEnd");
    return r;
  }

  RoadSignal signal(pugi::xml_node n, const Road& road, const std::string& at) const {
    RoadSignal g;
    g.id = text(n, "id", at);
    const std::string path = at.substr(0, at.rfind('[')) + "[@id='" + g.id + "']";
    g.name = n.attribute("name").value();
    g.s = road_s(n, road, path);
    g.t = number(n, "t", path);
    check_lateral(g.t, "t", n, path);
    g.z_offset = number_or(n, "zOffset", 0.0, path);
    g.h_offset = number_or(n, "hOffset", 0.0, path);
    g.pitch = number_or(n, "pitch", 0.0, path);
    g.roll = number_or(n, "roll", 0.0, path);
    g.orientation = orientation(n, "+", path);
    const std::string dyn = n.attribute("dynamic").value();
    if (dyn == "yes" || dyn == "true") {
      g.dynamic = true;
    } else if (!dyn.empty() && dyn != "no" && dyn != "false") {
      fail(path, "attribute 'dynamic' must be 'yes' or 'no', got '" + dyn + "'");
    }
    g.country = n.attribute("country").value();
    g.type = n.attribute("type") ? n.attribute("type").value() : "-1";
    g.subtype = n.attribute("subtype") ? n.attribute("subtype").value() : "-1";
    // "value" is optional and some tools write "-1" or "" for none.
    if (n.attribute("value") && n.attribute("value").value()[0] != '\0')
      g.value = number(n, "value", path);
    g.unit = n.attribute("unit").value();
    g.text = n.attribute("text").value();
    g.height = size_or(n, "height", 0.0, path);
    g.width = size_or(n, "width", 0.0, path);
    int vi = 0;
    for (pugi::xml_node v : n.children("validity")) {
      const std::string vp = indexed(path, "validity", ++vi);
      g.validity.push_back({integer(v, "fromLane", vp), integer(v, "toLane", vp)});
    }
    return g;
  }

  ItemReference reference(pugi::xml_node n, const Road& road, const std::string& at) const {
    ItemReference r;
    r.id = text(n, "id", at);
    const std::string path = at.substr(0, at.rfind('[')) + "[@id='" + r.id + "']";
    r.s = road_s(n, road, path);
    r.t = number(n, "t", path);
    check_lateral(r.t, "t", n, path);
    r.orientation = orientation(n, "none", path);
    return r;
  }

  void check_lateral(double v, const char* name, pugi::xml_node n, const std::string& path) const {
    if (std::fabs(v) > kMaxLateral) {
      fail(path, std::string("attribute '") + name + "' is " + n.attribute(name).value() +
                     ", more than a map may have (1000 m)");
    }
  }

  std::optional<double> speed(pugi::xml_node sp, const std::string& path) const {
    const std::string max = sp.attribute("max").value();
    if (max == "no limit" || max == "undefined")
      return std::numeric_limits<double>::infinity();
    const double v = number(sp, "max", path);
    const std::string unit = sp.attribute("unit").value();
    if (unit.empty() || unit == "m/s")
      return v;
    if (unit == "km/h")
      return v / 3.6;
    if (unit == "mph")
      return v * 0.44704;
    fail(path, "unknown speed unit '" + unit + "'");
  }

  CubicProfile profile(pugi::xml_node parent, const char* child, const char* s_name,
                       const std::string& path) const {
    std::vector<CubicRecord> rec;
    int i = 0;
    for (pugi::xml_node n : parent.children(child)) {
      const std::string p = indexed(path, child, ++i);
      CubicRecord c;
      c.s = number(n, s_name, p);
      c.a = number_or(n, "a", 0, p);
      c.b = number_or(n, "b", 0, p);
      c.c = number_or(n, "c", 0, p);
      c.d = number_or(n, "d", 0, p);
      if (!rec.empty() && c.s < rec.back().s) {
        fail(p, std::string(s_name) + " " + std::to_string(c.s) + " before the previous record's");
      }
      rec.push_back(c);
    }
    return CubicProfile(std::move(rec));
  }

  void read_plan_view(pugi::xml_node pv, Road& road, const std::string& path) {
    if (!pv)
      fail(path, "no <planView>");
    int i = 0;
    for (pugi::xml_node g : pv.children("geometry")) {
      const std::string p = path + "/planView/geometry[" + std::to_string(++i) + "]";
      const double s0 = number(g, "s", p);
      const RefPoint start{number(g, "x", p), number(g, "y", p), number(g, "hdg", p)};
      const double len = number(g, "length", p);
      if (!(len > 0))
        fail(p, "length must be > 0, got " + std::string(g.attribute("length").value()));
      if (!road.geometries.empty() && s0 < road.geometries.back()->s0()) {
        fail(p, "s " + std::string(g.attribute("s").value()) + " before the previous geometry's");
      }
      pugi::xml_node shape = g.first_child();
      while (shape && shape.type() != pugi::node_element)
        shape = shape.next_sibling();
      const std::string kind = shape ? shape.name() : "";
      const std::string sp = p + "/" + kind;
      if (kind == "line") {
        road.geometries.push_back(std::make_unique<Line>(s0, start, len));
      } else if (kind == "arc") {
        road.geometries.push_back(
            std::make_unique<Arc>(s0, start, len, number(shape, "curvature", sp)));
      } else if (kind == "spiral") {
        road.geometries.push_back(make_spiral(s0, start, len, number(shape, "curvStart", sp),
                                              number(shape, "curvEnd", sp)));
      } else if (kind == "poly3") {
        road.geometries.push_back(std::make_unique<Poly3>(
            s0, start, len, number_or(shape, "a", 0, sp), number_or(shape, "b", 0, sp),
            number_or(shape, "c", 0, sp), number_or(shape, "d", 0, sp)));
      } else if (kind == "paramPoly3") {
        ParamPoly3::Coefficients c;
        c.au = number_or(shape, "aU", 0, sp);
        c.bu = number_or(shape, "bU", 0, sp);
        c.cu = number_or(shape, "cU", 0, sp);
        c.du = number_or(shape, "dU", 0, sp);
        c.av = number_or(shape, "aV", 0, sp);
        c.bv = number_or(shape, "bV", 0, sp);
        c.cv = number_or(shape, "cV", 0, sp);
        c.dv = number_or(shape, "dV", 0, sp);
        const std::string range = shape.attribute("pRange").value();
        if (!range.empty() && range != "normalized" && range != "arcLength") {
          fail(sp, "pRange must be 'arcLength' or 'normalized', got '" + range + "'");
        }
        // 1.4 has no pRange and means normalized.
        road.geometries.push_back(
            std::make_unique<ParamPoly3>(s0, start, len, c, range != "arcLength"));
      } else if (kind.empty()) {
        fail(p, "geometry has no shape element (line, arc, spiral, poly3, paramPoly3)");
      } else {
        fail(p, "unknown geometry element <" + kind + ">");
      }
    }
    if (road.geometries.empty())
      fail(path + "/planView", "planView has no <geometry>");
  }

  Lane read_lane(pugi::xml_node l, const std::string& path, bool center) {
    Lane lane;
    lane.id = integer(l, "id", path);
    lane.type = l.attribute("type") ? l.attribute("type").value() : "none";
    lane.drivable = is_drivable(lane.type);
    const std::string level = l.attribute("level").value();
    lane.level = level == "true" || level == "1";
    if (lane.level && has_superelevation_) {
      not_applied(path,
                  "level=\"" + level + "\" (the lane is tilted with the road's superelevation)");
    }
    int hi = 0;
    for (pugi::xml_node h : l.children("height")) {
      const std::string hp = indexed(path, "height", ++hi);
      const double inner = number_or(h, "inner", 0, hp);
      const double outer = number_or(h, "outer", 0, hp);
      if (inner != 0 || outer != 0) {
        not_applied(hp, "<height inner=\"" + std::string(h.attribute("inner").value()) +
                            "\" outer=\"" + h.attribute("outer").value() +
                            "\"> (the lane lies on the road surface)");
      }
    }
    if (pugi::xml_node link = l.child("link")) {
      if (pugi::xml_node p = link.child("predecessor")) {
        lane.predecessor = integer(p, "id", path + "/link/predecessor");
        lane.has_link = true;
      }
      if (pugi::xml_node s = link.child("successor")) {
        lane.successor = integer(s, "id", path + "/link/successor");
        lane.has_link = true;
      }
    }
    if (!center) {
      lane.width = profile(l, "width", "sOffset", path);
      if (lane.width.empty())
        lane.border = profile(l, "border", "sOffset", path);
      if (lane.width.empty() && lane.border.empty())
        fail(path, "lane has no <width> or <border>");
    }
    int mi = 0;
    for (pugi::xml_node m : l.children("roadMark")) {
      const std::string mp = indexed(path, "roadMark", ++mi);
      RoadMark mark;
      mark.s_offset = number_or(m, "sOffset", 0, mp);
      if (m.attribute("type"))
        mark.type = m.attribute("type").value();
      if (m.attribute("color"))
        mark.color = m.attribute("color").value();
      mark.width = number_or(m, "width", mark.width, mp);
      if (pugi::xml_node t = m.child("type")) {
        if (pugi::xml_node line = t.child("line")) {
          mark.line_length = number_or(line, "length", mark.line_length, mp + "/type/line");
          mark.space = number_or(line, "space", mark.space, mp + "/type/line");
        }
      }
      lane.marks.push_back(mark);
    }
    int si = 0;
    for (pugi::xml_node sp : l.children("speed")) {
      const std::string p = indexed(path, "speed", ++si);
      if (auto v = speed(sp, p))
        lane.speeds.push_back({number_or(sp, "sOffset", 0, p), *v});
    }
    return lane;
  }

  void read_side(pugi::xml_node side, const char* name, int sign, std::vector<Lane>& out,
                 const std::string& path) {
    if (!side)
      return;
    const std::string sp = path + "/" + name;
    for (pugi::xml_node l : side.children("lane")) {
      const std::string id = l.attribute("id").value();
      const std::string lp = sp + "/lane[@id='" + id + "']";
      Lane lane = read_lane(l, lp, false);
      if (lane.id * sign <= 0) {
        fail(lp, std::string("lane id must be ") + (sign > 0 ? "positive" : "negative") +
                     " on the " + name);
      }
      out.push_back(std::move(lane));
    }
    std::sort(out.begin(), out.end(),
              [](const Lane& a, const Lane& b) { return std::abs(a.id) < std::abs(b.id); });
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (std::abs(out[i].id) != static_cast<int>(i) + 1) {
        fail(sp, "lane ids must run " + std::to_string(sign) + ", " + std::to_string(2 * sign) +
                     ", ... without gaps or repeats");
      }
    }
  }

  void read_lanes(pugi::xml_node lanes, Road& road, const std::string& path) {
    if (!lanes)
      fail(path, "no <lanes>");
    const std::string lp = path + "/lanes";
    road.lane_offset = profile(lanes, "laneOffset", "s", lp);
    int i = 0;
    for (pugi::xml_node s : lanes.children("laneSection")) {
      const std::string p = indexed(lp, "laneSection", ++i);
      LaneSection ls;
      ls.s = number(s, "s", p);
      ls.single_side = std::string(s.attribute("singleSide").value()) == "true";
      if (!road.sections.empty() && ls.s < road.sections.back().s) {
        fail(p, "s " + std::string(s.attribute("s").value()) + " before the previous section's");
      }
      if (ls.s >= road.length)
        fail(p, "s " + std::string(s.attribute("s").value()) + " past the road's length");
      read_side(s.child("left"), "left", 1, ls.left, p);
      read_side(s.child("right"), "right", -1, ls.right, p);
      if (pugi::xml_node c = s.child("center").child("lane")) {
        ls.center = read_lane(c, p + "/center/lane[@id='0']", true);
      }
      if (ls.left.empty() && ls.right.empty())
        fail(p, "lane section has no left or right lane");
      road.sections.push_back(std::move(ls));
    }
    if (road.sections.empty())
      fail(lp, "no <laneSection>");
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      road.sections[k].s_end = k + 1 < road.sections.size() ? road.sections[k + 1].s : road.length;
    }
  }

  void read_junction(pugi::xml_node j) {
    Junction junction;
    junction.id = text(j, "id", "junction[" + std::to_string(net_.junctions.size() + 1) + "]");
    const std::string path = "junction[@id='" + junction.id + "']";
    if (!junction_ids_.emplace(junction.id, static_cast<int>(net_.junctions.size())).second) {
      fail(path, "duplicate junction id '" + junction.id + "'");
    }
    junction.name = j.attribute("name").value();
    if (j.attribute("type"))
      junction.type = j.attribute("type").value();
    int ci = 0;
    for (pugi::xml_node c : j.children("connection")) {
      ++ci;
      Connection con;
      con.id = c.attribute("id").value();
      const std::string cp = con.id.empty() ? indexed(path, "connection", ci)
                                            : path + "/connection[@id='" + con.id + "']";
      con.incoming = text(c, "incomingRoad", cp);
      con.connecting = c.attribute("connectingRoad") ? text(c, "connectingRoad", cp)
                       : c.attribute("linkedRoad")   ? text(c, "linkedRoad", cp)
                                                     : "";
      if (con.connecting.empty())
        fail(cp, "attribute 'connectingRoad' (or 'linkedRoad') missing");
      con.contact = contact(c);
      int li = 0;
      for (pugi::xml_node ll : c.children("laneLink")) {
        const std::string lp = indexed(cp, "laneLink", ++li);
        con.lane_links.push_back({integer(ll, "from", lp), integer(ll, "to", lp)});
      }
      junction.connections.push_back(std::move(con));
    }
    int ki = 0;
    for (pugi::xml_node c : j.children("controller")) {
      const std::string kp = indexed(path, "controller", ++ki);
      JunctionController jc;
      jc.id = text(c, "id", kp);
      jc.type = c.attribute("type").value();
      if (c.attribute("sequence"))
        jc.sequence = integer(c, "sequence", kp);
      junction.controllers.push_back(std::move(jc));
    }
    net_.junctions.push_back(std::move(junction));
  }

  /// A top-level <controller> (14.7) with its <control>s.
  void read_controller(pugi::xml_node c) {
    Controller k;
    k.id = text(c, "id", indexed("", "controller", static_cast<int>(net_.controllers.size()) + 1));
    const std::string path = "controller[@id='" + k.id + "']";
    // Any id OpenDRIVE allows: that a controller's id is a SignalGroupID is the testbed's signal
    // model's rule, checked by SignalLayout when the lights are used.
    if (!controller_ids_.emplace(k.id, net_.controllers.size()).second)
      fail(path, "duplicate controller id '" + k.id + "'");
    k.name = c.attribute("name").value();
    if (c.attribute("sequence"))
      k.sequence = integer(c, "sequence", path);
    int i = 0;
    for (pugi::xml_node n : c.children("control")) {
      const std::string cp = indexed(path, "control", ++i);
      k.controls.push_back({text(n, "signalId", cp), n.attribute("type").value()});
    }
    net_.controllers.push_back(std::move(k));
  }

  /// Whether @p text is a plain decimal (digits only) within [lo, hi].
  static bool decimal_in(const std::string& text, long lo, long hi) {
    if (text.empty() || text.size() > 6 ||
        !std::all_of(text.begin(), text.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
      return false;
    const long v = std::stol(text);
    return v >= lo && v <= hi;
  }

  /// Controllers name dynamic signals that exist, each signal at most one controller; the
  /// junctions name controllers that exist and, having any, carry an id that can be an
  /// IntersectionID (a decimal 0..65535, ISO TS 19091 IntersectionReferenceID.id).
  void resolve_controllers() {
    struct Where {
      const Road* road;
      const RoadSignal* signal;
      int count;
    };
    std::unordered_map<std::string, Where> signals;
    for (const Road& r : net_.roads) {
      for (const RoadSignal& g : r.signals) {
        auto [it, fresh] = signals.emplace(g.id, Where{&r, &g, 1});
        if (!fresh)
          ++it->second.count;
      }
    }
    std::unordered_map<std::string, std::string> owner;  // signal id -> controller id
    for (const Controller& k : net_.controllers) {
      int i = 0;
      for (const Control& c : k.controls) {
        const std::string cp = indexed("controller[@id='" + k.id + "']", "control", ++i);
        auto it = signals.find(c.signal_id);
        if (it == signals.end())
          fail(cp, "attribute 'signalId' is '" + c.signal_id + "': no road has that signal");
        if (it->second.count > 1) {
          fail(cp, "attribute 'signalId' is '" + c.signal_id +
                       "': " + std::to_string(it->second.count) + " signals have that id");
        }
        if (!it->second.signal->dynamic) {
          fail(cp, "attribute 'signalId' is '" + c.signal_id + "': signal '" + c.signal_id +
                       "' of road '" + it->second.road->id +
                       "' is not dynamic (dynamic=\"yes\"), a controller cannot switch it");
        }
        auto [o, fresh] = owner.emplace(c.signal_id, k.id);
        if (!fresh) {
          fail(cp, "attribute 'signalId' is '" + c.signal_id + "': signal '" + c.signal_id +
                       "' is already controlled by controller '" + o->second +
                       "'; a signal belongs to one controller (one signal group)");
        }
      }
    }
    for (const Junction& j : net_.junctions) {
      const std::string path = "junction[@id='" + j.id + "']";
      int i = 0;
      for (const JunctionController& jc : j.controllers) {
        const std::string kp = indexed(path, "controller", ++i);
        if (controller_ids_.find(jc.id) == controller_ids_.end())
          fail(kp, "attribute 'id' is '" + jc.id + "': no <controller> has that id");
      }
      if (!j.controllers.empty() && !decimal_in(j.id, 0, 65535)) {
        fail(path, "attribute 'id' is '" + j.id +
                       "': a junction with controllers is an intersection whose id "
                       "(IntersectionID) must be a decimal 0..65535");
      }
    }
  }

  /// The lane section of @p road at the end given by @p c (start: first, end: last).
  static const LaneSection& end_section(const Road& road, ContactPoint c) {
    return c == ContactPoint::kEnd ? road.sections.back() : road.sections.front();
  }

  void resolve_link(std::optional<RoadLink>& link, const Road& road, const std::string& path) {
    if (!link)
      return;
    if (link->to_junction) {
      auto it = junction_ids_.find(link->id);
      if (it == junction_ids_.end())
        fail(path, "junction '" + link->id + "' does not exist");
      link->index = it->second;
      return;
    }
    auto it = road_ids_.find(link->id);
    if (it == road_ids_.end())
      fail(path, "road '" + link->id + "' does not exist");
    link->index = it->second;
    if (link->contact == ContactPoint::kNone) {
      fail(path, "link to road '" + link->id + "' has no contactPoint");
    }
    (void)road;
  }

  void check_lane_links(const Road& road, const std::string& path) {
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const LaneSection& ls = road.sections[k];
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const Lane& lane : *side) {
          const std::string lp = path + "/lanes/laneSection[" + std::to_string(k + 1) + "]/" +
                                 (lane.id > 0 ? "left" : "right") + "/lane[@id='" +
                                 std::to_string(lane.id) + "']/link";
          check_lane_link(road, k, lane.predecessor, false, lp + "/predecessor");
          check_lane_link(road, k, lane.successor, true, lp + "/successor");
        }
      }
    }
  }

  void check_lane_link(const Road& road, std::size_t k, std::optional<int> id, bool next,
                       const std::string& path) {
    if (!id)
      return;
    const LaneSection* target = nullptr;
    std::string where;
    if (next && k + 1 < road.sections.size()) {
      target = &road.sections[k + 1];
      where = "the next lane section of road '" + road.id + "'";
    } else if (!next && k > 0) {
      target = &road.sections[k - 1];
      where = "the previous lane section of road '" + road.id + "'";
    } else {
      const auto& link = next ? road.successor : road.predecessor;
      if (!link || link->to_junction)
        return;  // junction: the connections say where
      const Road& other = net_.roads[static_cast<std::size_t>(link->index)];
      target = &end_section(other, link->contact);
      where = "road '" + other.id + "' at its " +
              (link->contact == ContactPoint::kEnd ? "end" : "start");
    }
    if (target->lane(*id) == nullptr) {
      fail(path, "lane " + std::to_string(*id) + " does not exist in " + where);
    }
  }

  void resolve_links() {
    for (Road& road : net_.roads) {
      const std::string path = "road[@id='" + road.id + "']";
      resolve_link(road.predecessor, road, path + "/link/predecessor");
      resolve_link(road.successor, road, path + "/link/successor");
      if (road.junction != "-1") {
        auto it = junction_ids_.find(road.junction);
        if (it == junction_ids_.end()) {
          fail(path, "junction '" + road.junction + "' does not exist");
        }
        road.junction_index = it->second;
      }
    }
    for (const Road& road : net_.roads)
      check_lane_links(road, "road[@id='" + road.id + "']");
    for (std::size_t ji = 0; ji < net_.junctions.size(); ++ji) {
      Junction& j = net_.junctions[ji];
      const std::string path = "junction[@id='" + j.id + "']";
      int ci = 0;
      for (Connection& c : j.connections) {
        ++ci;
        const std::string cp = c.id.empty() ? indexed(path, "connection", ci)
                                            : path + "/connection[@id='" + c.id + "']";
        auto in = road_ids_.find(c.incoming);
        if (in == road_ids_.end())
          fail(cp, "incomingRoad '" + c.incoming + "' does not exist");
        auto con = road_ids_.find(c.connecting);
        if (con == road_ids_.end())
          fail(cp, "connectingRoad '" + c.connecting + "' does not exist");
        c.incoming_index = in->second;
        c.connecting_index = con->second;
        const Road& incoming = net_.roads[static_cast<std::size_t>(in->second)];
        const Road& connecting = net_.roads[static_cast<std::size_t>(con->second)];
        const ContactPoint in_end = net_.incoming_end(c, ji);
        const LaneSection& from = end_section(incoming, in_end);
        const LaneSection& to = end_section(connecting, c.contact);
        int li = 0;
        bool swapped = false;
        for (LaneLink& ll : c.lane_links) {
          const std::string lp = indexed(cp, "laneLink", ++li);
          const bool from_ok = ll.from != 0 && from.lane(ll.from) != nullptr;
          const bool to_ok = ll.to != 0 && to.lane(ll.to) != nullptr;
          if (from_ok && to_ok)
            continue;
          // Some generators write from = connecting road's lane, to = incoming road's; take
          // that reading when only it names existing lanes (one warning per connection).
          if (ll.to != 0 && from.lane(ll.to) != nullptr && ll.from != 0 &&
              to.lane(ll.from) != nullptr) {
            std::swap(ll.from, ll.to);
            swapped = true;
            continue;
          }
          if (!from_ok) {
            fail(lp, "lane " + std::to_string(ll.from) + " does not exist on incoming road '" +
                         incoming.id + "' at its " +
                         (in_end == ContactPoint::kEnd ? "end" : "start"));
          }
          fail(lp, "lane " + std::to_string(ll.to) + " does not exist on road '" + connecting.id +
                       "' at its " + (c.contact == ContactPoint::kEnd ? "end" : "start"));
        }
        if (swapped) {
          net_.warnings.push_back(cp + ": laneLink from/to read as connecting -> incoming lane");
        }
      }
    }
  }

 private:
  RoadNetwork net_;
  std::unordered_map<std::string, int> road_ids_;
  std::unordered_map<std::string, int> junction_ids_;
  std::unordered_map<std::string, std::size_t> controller_ids_;
  std::set<std::string> ignored_;
  std::vector<std::string> not_applied_;
  bool has_superelevation_ = false;  ///< the road being read banks somewhere
  std::size_t skipped_structures_ = 0;
  double total_length_ = 0.0;
};

}  // namespace

RoadNetwork parse_opendrive(std::string_view xml, const std::string& source) {
  return Reader(source).read(xml);
}

RoadNetwork load_opendrive(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw MapError(path, "", "cannot open file");
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad())
    throw MapError(path, "", "cannot read file");
  return parse_opendrive(buf.str(), path);
}

}  // namespace tb::map::odr
