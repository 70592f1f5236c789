#pragma once
/// @file The driver's top-down view (`--view topdown`): a chase view that follows the own car
/// (heading up) over the OpenDRIVE road network (lane surfaces by type, junctions, road marks;
/// map_layer.hpp), every vehicle as an oriented rectangle, and a HUD (speed, gear, controls in
/// effect, lights, connection status, key map on H). Drawn with SDL2's 2D renderer.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <SDL.h>

#include "common/map/opendrive/road_network.hpp"
#include "common/wire/sim_protocol.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-client/view/map_layer.hpp"

namespace tb::client {

struct ViewVehicle {
  wire::VehicleState state;
  float length_m = 4.5f;
  float width_m = 1.8f;
  SDL_Color color{200, 32, 32, 255};
  bool own = false;
};

struct ViewScene {
  /// The world's road network; null: none yet (not connected). The renderer builds its map
  /// layer once per network.
  const map::odr::RoadNetwork* network = nullptr;
  std::vector<ViewVehicle> vehicles;
  std::string connection;  ///< connection status line
  std::string input;       ///< input status line ("keyboard", "controller ...")
  bool help = false;       ///< show the key map
  /// The traffic lights (every junction's groups of the latest SignalStates): a marker at each
  /// signalised approach's stop line in its group's colour (issue 34).
  std::vector<wire::sim::SignalGroupState> signals;
};

/// One signalised approach's marker: on the lane's centre at the stop line (map frame), which
/// light it shows.
struct SignalMarker {
  double x = 0.0, y = 0.0;
  double heading = 0.0;  ///< rad, the direction of travel
  std::uint16_t intersection_id = 0;
  int signal_group = 0;
};
/// The markers of @p net's SignalLayout approaches; none when the layout refuses the map.
std::vector<SignalMarker> signal_markers(const map::odr::RoadNetwork& net);

/// The colours a marker shows for a state, far half then near half (the same for all but
/// red + amber: red beyond amber, as the lamps stand in a head): red, amber, green, or dark
/// grey when the light is dark, unavailable or not in the message.
std::pair<SDL_Color, SDL_Color> marker_colours(std::optional<wire::sim::MovementPhaseState> state);

/// "#rrggbb" to a colour; empty for anything else.
std::optional<SDL_Color> parse_colour(const std::string& text);

/// The colour the own car is outlined with, so it stands out whatever the scenario's colours.
inline constexpr SDL_Color kOwnHighlight{255, 220, 0, 255};

class SceneRenderer {
 public:
  SceneRenderer(SDL_Renderer* renderer, int width, int height)
      : r_(renderer), width_(width), height_(height) {}

  void draw(const ViewScene& scene);

  /// Where the own car sits on screen (centre horizontally, a little below the middle so
  /// that more of the road ahead shows).
  SDL_FPoint anchor() const { return {width_ / 2.0f, height_ * 0.6f}; }
  /// Where a map point was drawn in the last frame (window pixels, origin top left).
  SDL_FPoint screen_of(double x, double y) const { return to_screen(x, y); }
  /// A marker's side (m); 1.4 m is 11 px at the default scale.
  static constexpr double kMarkerSize = 1.4;
  double pixels_per_metre = 8.0;

 private:
  struct Camera {
    double x = 0.0, y = 0.0, yaw = 0.0;
  };
  struct Point {
    double x, y;
  };
  SDL_FPoint to_screen(double x, double y) const;
  void quad(const Point (&corners)[4], SDL_Color c);
  void draw_map(const map::odr::RoadNetwork& net);
  void draw_chunks(const std::vector<MapLayer::Chunk>& chunks);
  void draw_vehicle(const ViewVehicle& v);
  void draw_signals(const std::vector<wire::sim::SignalGroupState>& states);
  void draw_hud(const ViewScene& scene, const ViewVehicle* own);
  void text(int x, int y, std::string_view s, int scale, SDL_Color c);
  void bar(int x, int y, int w, int h, double from, double to, SDL_Color c);

  SDL_Renderer* r_;
  int width_, height_;
  Camera cam_;
  std::unique_ptr<MapLayer> layer_;
  const map::odr::RoadNetwork* layer_of_ = nullptr;
  std::vector<SignalMarker> markers_;  ///< of layer_of_
  std::vector<SDL_Vertex> screen_;     ///< reused each frame
};

/// Where the view is drawn: a window, or an off-screen surface (--headless --screenshot).
class Canvas {
 public:
  /// @throws std::runtime_error with SDL's reason when no window can be made.
  static std::unique_ptr<Canvas> window(int width, int height, const std::string& title);
  static std::unique_ptr<Canvas> offscreen(int width, int height);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  SDL_Renderer* renderer() const { return renderer_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool has_window() const { return window_ != nullptr; }
  /// The window (null off-screen), e.g. for its title.
  SDL_Window* sdl_window() const { return window_; }
  void present();
  /// The last drawn frame, RGBA, row by row (call before present()).
  std::vector<std::uint8_t> read_rgba() const;

 private:
  Canvas() = default;
  SDL_Window* window_ = nullptr;
  SDL_Surface* surface_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  int width_ = 0, height_ = 0;
};

/// Writes RGBA pixels as a PNG. Returns an error text naming the file, or empty on success.
std::string write_png(const std::string& path, int width, int height,
                      const std::vector<std::uint8_t>& rgba);

}  // namespace tb::client
