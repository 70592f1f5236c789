#pragma once
/// @file The road network as the top-down view draws it: lane surfaces coloured by lane type
/// (junction lanes a shade lighter, so that a junction reads as one paved area), then road
/// marks by type, colour and width (broken marks as dashes of their line length and gap).
/// World-space triangles built once from the OpenDRIVE model, in chunks the renderer culls.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <SDL.h>

#include "common/map/opendrive/road_network.hpp"

namespace tb::client {

/// The colour of a lane surface of @p type; empty for lanes not drawn (`none`).
std::optional<SDL_Color> lane_colour(const std::string& type, bool in_junction);
/// The colour of a road mark (`standard` and `white` are white).
SDL_Color mark_colour(const std::string& colour);

class MapLayer {
 public:
  /// @p eps: chord tolerance of the sampled lane borders (m).
  explicit MapLayer(const map::odr::RoadNetwork& net, double eps = 0.05);

  struct Vertex {
    double x = 0.0, y = 0.0;
    SDL_Color colour{};
  };
  /// Consecutive triangles (3 vertices each) of one lane section, with their bounding box.
  struct Chunk {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    std::uint32_t first = 0, count = 0;
  };

  const std::vector<Vertex>& vertices() const { return vertices_; }
  const std::vector<Chunk>& surfaces() const { return surfaces_; }
  const std::vector<Chunk>& marks() const { return marks_; }
  std::size_t triangles() const { return vertices_.size() / 3; }

 private:
  void add_surfaces(const map::odr::Road& road, std::size_t section, double eps);
  void add_marks(const map::odr::Road& road, std::size_t section, double eps);
  /// The band between t = inner(s) and t = outer(s) for s in [s0, s1], as triangles.
  template <class InnerT, class OuterT>
  void band(const map::odr::Road& road, double s0, double s1, double eps, InnerT inner,
            OuterT outer, SDL_Color c);
  void close_chunk(std::vector<Chunk>& into, std::uint32_t first);

  std::vector<Vertex> vertices_;
  std::vector<Chunk> surfaces_;
  std::vector<Chunk> marks_;
};

}  // namespace tb::client
