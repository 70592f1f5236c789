#include "sim-client/view/map_layer.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/map/opendrive/mesh.hpp"

namespace tb::client {
namespace {

namespace odr = map::odr;

// Lane surfaces (OpenDRIVE 1.7 clause 9.5.3 lane types).
constexpr SDL_Color kAsphalt{64, 64, 68, 255};
constexpr SDL_Color kJunctionAsphalt{74, 74, 80, 255};
constexpr SDL_Color kShoulder{98, 94, 86, 255};
constexpr SDL_Color kBorder{112, 112, 108, 255};
constexpr SDL_Color kRestricted{92, 70, 70, 255};
constexpr SDL_Color kParking{70, 80, 102, 255};
constexpr SDL_Color kMedian{58, 104, 58, 255};
constexpr SDL_Color kBiking{150, 66, 60, 255};
constexpr SDL_Color kWalking{156, 154, 144, 255};
constexpr SDL_Color kCurb{186, 184, 176, 255};
constexpr SDL_Color kRail{104, 86, 66, 255};
// Where a dashed line's marks and gaps are a few centimetres, dots are drawn as squares.
constexpr double kBottsDot = 0.15;     // m, side of a Botts' dot
constexpr double kBottsSpacing = 1.5;  // m

}  // namespace

std::optional<SDL_Color> lane_colour(const std::string& type, bool in_junction) {
  static const std::string asphalt[] = {
      "driving",       "entry",    "exit",    "onRamp",   "offRamp",  "connectingRamp",
      "bidirectional", "stop",     "bus",     "taxi",     "HOV",      "slipLane",
      "roadWorks",     "mwyEntry", "mwyExit", "special1", "special2", "special3"};
  if (std::find(std::begin(asphalt), std::end(asphalt), type) != std::end(asphalt))
    return in_junction ? kJunctionAsphalt : kAsphalt;
  if (type == "shoulder")
    return kShoulder;
  if (type == "border")
    return kBorder;
  if (type == "restricted")
    return kRestricted;
  if (type == "parking")
    return kParking;
  if (type == "median")
    return kMedian;
  if (type == "biking")
    return kBiking;
  if (type == "sidewalk" || type == "walking")
    return kWalking;
  if (type == "curb")
    return kCurb;
  if (type == "rail" || type == "tram")
    return kRail;
  return std::nullopt;
}

SDL_Color mark_colour(const std::string& c) {
  if (c == "yellow")
    return {240, 196, 32, 255};
  if (c == "blue")
    return {60, 110, 230, 255};
  if (c == "green")
    return {60, 180, 80, 255};
  if (c == "red")
    return {220, 50, 40, 255};
  if (c == "orange")
    return {240, 130, 30, 255};
  if (c == "violet")
    return {150, 80, 200, 255};
  return {236, 236, 232, 255};  // standard, white
}

MapLayer::MapLayer(const odr::RoadNetwork& net, double eps) {
  for (const odr::Road& road : net.roads) {
    for (std::size_t k = 0; k < road.sections.size(); ++k)
      add_surfaces(road, k, eps);
  }
  // Marks after every surface, so that no lane is drawn over them.
  for (const odr::Road& road : net.roads) {
    for (std::size_t k = 0; k < road.sections.size(); ++k)
      add_marks(road, k, eps);
  }
}

void MapLayer::close_chunk(std::vector<Chunk>& into, std::uint32_t first) {
  const auto end = static_cast<std::uint32_t>(vertices_.size());
  if (end == first)
    return;
  Chunk c{1e300, 1e300, -1e300, -1e300, first, end - first};
  for (std::uint32_t i = first; i < end; ++i) {
    c.x0 = std::min(c.x0, vertices_[i].x);
    c.y0 = std::min(c.y0, vertices_[i].y);
    c.x1 = std::max(c.x1, vertices_[i].x);
    c.y1 = std::max(c.y1, vertices_[i].y);
  }
  into.push_back(c);
}

template <class InnerT, class OuterT>
void MapLayer::band(const odr::Road& road, double s0, double s1, double eps, InnerT ta, OuterT tb,
                    SDL_Color c) {
  if (s1 - s0 < 1e-6)
    return;
  const double reach = std::max(std::fabs(ta(s0)), std::fabs(tb(s0))) + 1.0;
  const std::vector<double> ss = odr::sample_s(road, s0, s1, eps, reach);
  Vertex prev_a, prev_b;
  for (std::size_t i = 0; i < ss.size(); ++i) {
    const odr::SurfacePose pa = road.surface(ss[i], ta(ss[i]));
    const odr::SurfacePose pb = road.surface(ss[i], tb(ss[i]));
    const Vertex va{pa.x, pa.y, c}, vb{pb.x, pb.y, c};
    if (i > 0) {
      vertices_.insert(vertices_.end(), {prev_a, prev_b, va});
      vertices_.insert(vertices_.end(), {prev_b, vb, va});
    }
    prev_a = va;
    prev_b = vb;
  }
}

void MapLayer::add_surfaces(const odr::Road& road, std::size_t k, double eps) {
  const odr::LaneSection& ls = road.sections[k];
  const auto first = static_cast<std::uint32_t>(vertices_.size());
  const bool junction = road.junction_index >= 0;
  for (const auto* side : {&ls.left, &ls.right}) {
    for (const odr::Lane& lane : *side) {
      const auto colour = lane_colour(lane.type, junction);
      if (!colour)
        continue;
      const int id = lane.id;
      band(
          road, ls.s, ls.s_end, eps, [&](double s) { return road.borders(k, s).inner(id); },
          [&](double s) { return road.borders(k, s).outer(id); }, *colour);
    }
  }
  close_chunk(surfaces_, first);
}

void MapLayer::add_marks(const odr::Road& road, std::size_t k, double eps) {
  const odr::LaneSection& ls = road.sections[k];
  const auto first = static_cast<std::uint32_t>(vertices_.size());
  const auto mark_lane = [&](const odr::Lane& lane) {
    const int id = lane.id;
    // Marks lie on the lane's outer border; the centre lane's on the centre line.
    const auto border = [&](double s) {
      const odr::LaneBorders b = road.borders(k, s);
      return id == 0 ? b.center : b.outer(id);
    };
    for (std::size_t m = 0; m < lane.marks.size(); ++m) {
      const odr::RoadMark& mk = lane.marks[m];
      const double s0 = ls.s + mk.s_offset;
      const double s1 = m + 1 < lane.marks.size() ? ls.s + lane.marks[m + 1].s_offset : ls.s_end;
      if (mk.type == "none" || s1 <= s0)
        continue;
      const SDL_Color c = mark_colour(mk.color);
      const double w = mk.width > 0.0 ? mk.width : 0.12;
      // One painted line at lateral offset @p off, solid or broken.
      const auto line = [&](double off, bool broken) {
        const auto inner = [&](double s) { return border(s) + off - w / 2; };
        const auto outer = [&](double s) { return border(s) + off + w / 2; };
        if (!broken) {
          band(road, s0, std::min(s1, road.length), eps, inner, outer, c);
          return;
        }
        const double period = std::max(mk.line_length + mk.space, 0.1);
        for (double s = s0; s < s1; s += period)
          band(road, s, std::min({s + mk.line_length, s1, road.length}), eps, inner, outer, c);
      };
      std::istringstream words(mk.type);
      std::vector<std::string> parts;
      for (std::string word; words >> word;)
        parts.push_back(word);
      if (mk.type == "botts dots") {
        for (double s = s0; s < s1; s += kBottsSpacing) {
          const auto a = [&](double ss) { return border(ss) - kBottsDot / 2; };
          const auto b = [&](double ss) { return border(ss) + kBottsDot / 2; };
          band(road, s, std::min(s + kBottsDot, s1), eps, a, b, c);
        }
      } else if (parts.size() == 2 && (parts[0] == "solid" || parts[0] == "broken")) {
        // Two lines a line width apart: the first word on the left (+t) side.
        line(w, parts[0] == "broken");
        line(-w, parts[1] == "broken");
      } else {
        // solid, broken, and the rest (curb, grass, edge, custom) as a solid line.
        line(0.0, mk.type == "broken");
      }
    }
  };
  for (const auto* side : {&ls.left, &ls.right}) {
    for (const odr::Lane& lane : *side)
      mark_lane(lane);
  }
  mark_lane(ls.center);
  close_chunk(marks_, first);
}

}  // namespace tb::client
