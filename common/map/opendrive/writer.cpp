#include "common/map/opendrive/writer.hpp"

#include <pugixml.hpp>

#include <cmath>
#include <sstream>

namespace tb::map::odr {

namespace {

void set(pugi::xml_node n, const char* name, double v) {
  // 17 significant digits: the file reads back to the same doubles.
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  n.append_attribute(name) = buf;
}

void set(pugi::xml_node n, const char* name, const std::string& v) {
  n.append_attribute(name) = v.c_str();
}

void cubic(pugi::xml_node parent, const char* child, const char* s_name, const CubicProfile& p) {
  for (const CubicRecord& r : p.records()) {
    pugi::xml_node n = parent.append_child(child);
    set(n, s_name, r.s);
    set(n, "a", r.a);
    set(n, "b", r.b);
    set(n, "c", r.c);
    set(n, "d", r.d);
  }
}

const char* contact_name(ContactPoint c) {
  return c == ContactPoint::kEnd ? "end" : "start";
}

void road_link(pugi::xml_node link, const char* name, const std::optional<RoadLink>& l) {
  if (!l)
    return;
  pugi::xml_node n = link.append_child(name);
  set(n, "elementType", std::string(l->to_junction ? "junction" : "road"));
  set(n, "elementId", l->id);
  if (!l->to_junction || l->contact != ContactPoint::kNone) {
    set(n, "contactPoint", std::string(contact_name(l->contact)));
  }
}

void geometry(pugi::xml_node pv, const Geometry& g) {
  pugi::xml_node n = pv.append_child("geometry");
  set(n, "s", g.s0());
  set(n, "x", g.start().x);
  set(n, "y", g.start().y);
  set(n, "hdg", g.start().hdg);
  set(n, "length", g.length());
  if (dynamic_cast<const Line*>(&g) != nullptr) {
    n.append_child("line");
  } else if (const auto* a = dynamic_cast<const Arc*>(&g)) {
    set(n.append_child("arc"), "curvature", a->curvature(0));
  } else if (const auto* sp = dynamic_cast<const Spiral*>(&g)) {
    pugi::xml_node s = n.append_child("spiral");
    set(s, "curvStart", sp->curvature_start());
    set(s, "curvEnd", sp->curvature_end());
  } else if (const auto* p3 = dynamic_cast<const Poly3*>(&g)) {
    pugi::xml_node s = n.append_child("poly3");
    set(s, "a", p3->a());
    set(s, "b", p3->b());
    set(s, "c", p3->c());
    set(s, "d", p3->d());
  } else if (const auto* pp = dynamic_cast<const ParamPoly3*>(&g)) {
    pugi::xml_node s = n.append_child("paramPoly3");
    const auto& k = pp->coefficients();
    set(s, "aU", k.au);
    set(s, "bU", k.bu);
    set(s, "cU", k.cu);
    set(s, "dU", k.du);
    set(s, "aV", k.av);
    set(s, "bV", k.bv);
    set(s, "cV", k.cv);
    set(s, "dV", k.dv);
    set(s, "pRange", std::string(pp->normalized() ? "normalized" : "arcLength"));
  }
}

void lane(pugi::xml_node side, const Lane& l, bool center) {
  pugi::xml_node n = side.append_child("lane");
  set(n, "id", static_cast<double>(l.id));
  set(n, "type", l.type);
  set(n, "level", std::string(l.level ? "true" : "false"));
  if (l.predecessor || l.successor) {
    pugi::xml_node link = n.append_child("link");
    if (l.predecessor)
      set(link.append_child("predecessor"), "id", static_cast<double>(*l.predecessor));
    if (l.successor)
      set(link.append_child("successor"), "id", static_cast<double>(*l.successor));
  }
  if (!center) {
    if (!l.width.empty()) {
      cubic(n, "width", "sOffset", l.width);
    } else {
      cubic(n, "border", "sOffset", l.border);
    }
  }
  for (const RoadMark& m : l.marks) {
    pugi::xml_node r = n.append_child("roadMark");
    set(r, "sOffset", m.s_offset);
    set(r, "type", m.type);
    set(r, "color", m.color);
    set(r, "width", m.width);
    if (m.type.find("broken") != std::string::npos && (m.line_length != 3.0 || m.space != 9.0)) {
      pugi::xml_node t = r.append_child("type");
      set(t, "name", m.type);
      set(t, "width", m.width);
      pugi::xml_node line = t.append_child("line");
      set(line, "length", m.line_length);
      set(line, "space", m.space);
      set(line, "tOffset", 0.0);
      set(line, "sOffset", 0.0);
    }
  }
  for (const SpeedLimit& sp : l.speeds) {
    pugi::xml_node s = n.append_child("speed");
    set(s, "sOffset", sp.s);
    if (std::isinf(sp.max)) {
      set(s, "max", std::string("no limit"));
    } else {
      set(s, "max", sp.max);
    }
    set(s, "unit", std::string("m/s"));
  }
}

}  // namespace

std::string write_opendrive(const RoadNetwork& net) {
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child("OpenDRIVE");
  pugi::xml_node h = root.append_child("header");
  set(h, "revMajor", 1.0);
  set(h, "revMinor", 7.0);
  set(h, "name", net.header.name);
  set(h, "vendor", net.header.vendor.empty() ? std::string("v2x-testbed") : net.header.vendor);
  set(h, "north", net.header.north);
  set(h, "south", net.header.south);
  set(h, "east", net.header.east);
  set(h, "west", net.header.west);
  if (!net.header.geo_reference.empty()) {
    h.append_child("geoReference")
        .append_child(pugi::node_cdata)
        .set_value(net.header.geo_reference.c_str());
  }
  for (const Road& r : net.roads) {
    pugi::xml_node n = root.append_child("road");
    set(n, "id", r.id);
    if (!r.name.empty())
      set(n, "name", r.name);
    set(n, "length", r.length);
    set(n, "junction", r.junction);
    set(n, "rule", std::string(r.left_hand_traffic ? "LHT" : "RHT"));
    if (r.predecessor || r.successor) {
      pugi::xml_node link = n.append_child("link");
      road_link(link, "predecessor", r.predecessor);
      road_link(link, "successor", r.successor);
    }
    for (const RoadType& t : r.types) {
      pugi::xml_node tn = n.append_child("type");
      set(tn, "s", t.s);
      set(tn, "type", t.type);
      if (t.max_speed) {
        pugi::xml_node sp = tn.append_child("speed");
        if (std::isinf(*t.max_speed)) {
          set(sp, "max", std::string("no limit"));
        } else {
          set(sp, "max", *t.max_speed);
        }
        set(sp, "unit", std::string("m/s"));
      }
    }
    pugi::xml_node pv = n.append_child("planView");
    for (const auto& g : r.geometries)
      geometry(pv, *g);
    if (!r.elevation.empty())
      cubic(n.append_child("elevationProfile"), "elevation", "s", r.elevation);
    if (!r.superelevation.empty()) {
      cubic(n.append_child("lateralProfile"), "superelevation", "s", r.superelevation);
    }
    pugi::xml_node lanes = n.append_child("lanes");
    cubic(lanes, "laneOffset", "s", r.lane_offset);
    for (const LaneSection& ls : r.sections) {
      pugi::xml_node sn = lanes.append_child("laneSection");
      set(sn, "s", ls.s);
      if (ls.single_side)
        set(sn, "singleSide", std::string("true"));
      if (!ls.left.empty()) {
        pugi::xml_node left = sn.append_child("left");
        for (auto it = ls.left.rbegin(); it != ls.left.rend(); ++it)
          lane(left, *it, false);
      }
      lane(sn.append_child("center"), ls.center, true);
      if (!ls.right.empty()) {
        pugi::xml_node right = sn.append_child("right");
        for (const Lane& l : ls.right)
          lane(right, l, false);
      }
    }
  }
  for (const Junction& j : net.junctions) {
    pugi::xml_node n = root.append_child("junction");
    set(n, "id", j.id);
    if (!j.name.empty())
      set(n, "name", j.name);
    set(n, "type", j.type);
    for (const Connection& c : j.connections) {
      pugi::xml_node cn = n.append_child("connection");
      set(cn, "id", c.id);
      set(cn, "incomingRoad", c.incoming);
      set(cn, j.type == "direct" ? "linkedRoad" : "connectingRoad", c.connecting);
      set(cn, "contactPoint", std::string(contact_name(c.contact)));
      for (const LaneLink& ll : c.lane_links) {
        pugi::xml_node l = cn.append_child("laneLink");
        set(l, "from", static_cast<double>(ll.from));
        set(l, "to", static_cast<double>(ll.to));
      }
    }
  }
  std::ostringstream out;
  doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
  return out.str();
}

}  // namespace tb::map::odr
