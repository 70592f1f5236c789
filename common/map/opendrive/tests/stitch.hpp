#pragma once
/// @file Benchmarks' large maps: OpenDRIVE files copied side by side into one document, each
/// copy's road and junction ids prefixed and its planView shifted.

#include <pugixml.hpp>

#include <string>

namespace tb::map::odr::test {

/// Appends the roads and junctions of @p in to @p root (an OpenDRIVE element), ids prefixed by
/// @p prefix (links and connections too) and every geometry moved by (@p dx, @p dy). Returns the
/// number of roads appended.
inline std::size_t append_copy(pugi::xml_node root, const pugi::xml_document& in,
                               const std::string& prefix, double dx, double dy) {
  std::size_t roads = 0;
  for (pugi::xml_node n : in.child("OpenDRIVE").children()) {
    const std::string name = n.name();
    if (name != "road" && name != "junction")
      continue;
    pugi::xml_node c = root.append_copy(n);
    c.attribute("id").set_value((prefix + c.attribute("id").value()).c_str());
    if (name == "road") {
      ++roads;
      if (std::string(c.attribute("junction").value()) != "-1")
        c.attribute("junction").set_value((prefix + c.attribute("junction").value()).c_str());
      for (const char* l : {"predecessor", "successor"}) {
        if (pugi::xml_node e = c.child("link").child(l))
          e.attribute("elementId").set_value((prefix + e.attribute("elementId").value()).c_str());
      }
      for (pugi::xml_node g : c.child("planView").children("geometry")) {
        g.attribute("x").set_value(g.attribute("x").as_double() + dx);
        g.attribute("y").set_value(g.attribute("y").as_double() + dy);
      }
    } else {
      for (pugi::xml_node con : c.children("connection")) {
        for (const char* a : {"incomingRoad", "connectingRoad", "linkedRoad"}) {
          if (pugi::xml_attribute at = con.attribute(a))
            at.set_value((prefix + at.value()).c_str());
        }
      }
    }
  }
  return roads;
}

}  // namespace tb::map::odr::test
