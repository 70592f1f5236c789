#include "sim-client/view/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <png.h>

#include "common/map/opendrive/signal_layout.hpp"
#include "sim-client/input/keyboard.hpp"
#include "sim-client/view/font.hpp"

namespace tb::client {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr SDL_Color kGrass{46, 84, 46, 255};
constexpr SDL_Color kText{245, 245, 245, 255};
constexpr SDL_Color kDim{150, 150, 150, 255};
constexpr SDL_Color kPanel{0, 0, 0, 170};
constexpr SDL_Color kAmber{255, 170, 0, 255};

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

std::string gear_text(int gear) {
  if (gear < 0)
    return "R";
  if (gear == 0)
    return "N";
  return std::to_string(gear);
}

}  // namespace

std::optional<SDL_Color> parse_colour(const std::string& t) {
  if (t.size() != 7 || t[0] != '#')
    return std::nullopt;
  unsigned v = 0;
  for (std::size_t i = 1; i < 7; ++i) {
    const char c = t[i];
    unsigned d = 0;
    if (c >= '0' && c <= '9') {
      d = static_cast<unsigned>(c - '0');
    } else if (c >= 'a' && c <= 'f') {
      d = static_cast<unsigned>(c - 'a' + 10);
    } else if (c >= 'A' && c <= 'F') {
      d = static_cast<unsigned>(c - 'A' + 10);
    } else {
      return std::nullopt;
    }
    v = v * 16 + d;
  }
  return SDL_Color{static_cast<Uint8>(v >> 16), static_cast<Uint8>(v >> 8 & 0xff),
                   static_cast<Uint8>(v & 0xff), 255};
}

SDL_FPoint SceneRenderer::to_screen(double x, double y) const {
  // Heading up: rotate the world so that the camera's yaw points to the top of the screen.
  const double dx = x - cam_.x, dy = y - cam_.y;
  const double a = kPi / 2 - cam_.yaw;
  const double rx = dx * std::cos(a) - dy * std::sin(a);
  const double ry = dx * std::sin(a) + dy * std::cos(a);
  const SDL_FPoint o = anchor();
  return {static_cast<float>(o.x + rx * pixels_per_metre),
          static_cast<float>(o.y - ry * pixels_per_metre)};
}

void SceneRenderer::quad(const Point (&c)[4], SDL_Color col) {
  SDL_Vertex v[4];
  for (int i = 0; i < 4; ++i)
    v[i] = SDL_Vertex{to_screen(c[i].x, c[i].y), col, {0, 0}};
  const int idx[6] = {0, 1, 2, 0, 2, 3};
  SDL_RenderGeometry(r_, nullptr, v, 4, idx, 6);
}

// The map layer's chunks near the camera, transformed to the screen in one batch.
void SceneRenderer::draw_chunks(const std::vector<MapLayer::Chunk>& chunks) {
  const double reach = std::hypot(width_, height_) / pixels_per_metre;
  const auto& world = layer_->vertices();
  screen_.clear();
  for (const MapLayer::Chunk& c : chunks) {
    if (c.x1 < cam_.x - reach || c.x0 > cam_.x + reach || c.y1 < cam_.y - reach ||
        c.y0 > cam_.y + reach) {
      continue;
    }
    for (std::uint32_t i = c.first; i < c.first + c.count; ++i) {
      const MapLayer::Vertex& v = world[i];
      screen_.push_back(SDL_Vertex{to_screen(v.x, v.y), v.colour, {0, 0}});
    }
  }
  if (!screen_.empty()) {
    SDL_RenderGeometry(r_, nullptr, screen_.data(), static_cast<int>(screen_.size()), nullptr, 0);
  }
}

void SceneRenderer::draw_map(const map::odr::RoadNetwork& net) {
  if (layer_of_ != &net) {
    layer_ = std::make_unique<MapLayer>(net);
    markers_ = signal_markers(net);
    layer_of_ = &net;
  }
  draw_chunks(layer_->surfaces());
  draw_chunks(layer_->marks());
}

std::vector<SignalMarker> signal_markers(const map::odr::RoadNetwork& net) {
  std::vector<SignalMarker> out;
  try {
    const map::odr::SignalLayout layout(net);
    for (const map::odr::SignalApproach& a : layout.approaches())
      out.push_back({a.stop.x, a.stop.y, a.stop.heading, a.intersection_id, a.signal_group});
  } catch (const std::exception&) {
    // Lights the layout refuses (the scenario loader refuses such a map first): no markers.
  }
  return out;
}

std::pair<SDL_Color, SDL_Color> marker_colours(std::optional<wire::sim::MovementPhaseState> s) {
  using P = wire::sim::MovementPhaseState;
  constexpr SDL_Color red{235, 30, 20, 255}, amber{255, 170, 0, 255}, green{30, 220, 90, 255},
      dark{70, 70, 70, 255};
  if (!s)
    return {dark, dark};
  switch (*s) {
    case P::kStopAndRemain:
    case P::kStopThenProceed:
      return {red, red};
    case P::kPreMovement:
      return {red, amber};
    case P::kPermissiveClearance:
    case P::kProtectedClearance:
    case P::kCautionConflictingTraffic:
      return {amber, amber};
    case P::kPermissiveMovementAllowed:
    case P::kProtectedMovementAllowed:
      return {green, green};
    case P::kUnavailable:
    case P::kDark:
      break;
  }
  return {dark, dark};
}

void SceneRenderer::draw_signals(const std::vector<wire::sim::SignalGroupState>& states) {
  const double reach = std::hypot(width_, height_) / pixels_per_metre;
  for (const SignalMarker& m : markers_) {
    if (std::abs(m.x - cam_.x) > reach || std::abs(m.y - cam_.y) > reach)
      continue;
    std::optional<wire::sim::MovementPhaseState> state;
    for (const auto& g : states)
      if (g.intersection_id == m.intersection_id && g.signal_group == m.signal_group)
        state = g.state;
    const auto [far, near] = marker_colours(state);
    // A square on the lane centred on the stop line, in a black frame so that it reads on any
    // asphalt; red + amber splits it across the lane.
    const double c = std::cos(m.heading), sn = std::sin(m.heading);
    const auto square = [&](double a0, double a1, double half, Point(&q)[4]) {
      const double along[4] = {a0, a1, a1, a0};
      const double across[4] = {-half, -half, half, half};
      for (int i = 0; i < 4; ++i)
        q[i] = {m.x + along[i] * c - across[i] * sn, m.y + along[i] * sn + across[i] * c};
    };
    const double h = kMarkerSize / 2;
    Point q[4];
    square(-h - 0.2, h + 0.2, h + 0.2, q);
    quad(q, SDL_Color{0, 0, 0, 255});
    square(-h, 0.0, h, q);
    quad(q, near);
    square(0.0, h, h, q);
    quad(q, far);
  }
}

void SceneRenderer::draw_vehicle(const ViewVehicle& v) {
  const auto& s = v.state;
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const auto corners = [&](double half_l, double half_w, Point(&q)[4]) {
    const double px = s.position[0], py = s.position[1];
    const double lx[4] = {half_l, half_l, -half_l, -half_l};
    const double ly[4] = {half_w, -half_w, -half_w, half_w};
    for (int i = 0; i < 4; ++i)
      q[i] = {px + lx[i] * c - ly[i] * sn, py + lx[i] * sn + ly[i] * c};
  };
  Point q[4];
  if (v.own) {
    corners(v.length_m / 2 + 0.35, v.width_m / 2 + 0.35, q);
    quad(q, kOwnHighlight);
  }
  corners(v.length_m / 2, v.width_m / 2, q);
  quad(q, v.color);
  // Windscreen, so that the front reads at a glance.
  const double fl = v.length_m / 2;
  const Point w[4] = {{s.position[0] + (fl * 0.45) * c - (v.width_m * 0.4) * sn,
                       s.position[1] + (fl * 0.45) * sn + (v.width_m * 0.4) * c},
                      {s.position[0] + (fl * 0.45) * c + (v.width_m * 0.4) * sn,
                       s.position[1] + (fl * 0.45) * sn - (v.width_m * 0.4) * c},
                      {s.position[0] + (fl * 0.1) * c + (v.width_m * 0.4) * sn,
                       s.position[1] + (fl * 0.1) * sn - (v.width_m * 0.4) * c},
                      {s.position[0] + (fl * 0.1) * c - (v.width_m * 0.4) * sn,
                       s.position[1] + (fl * 0.1) * sn + (v.width_m * 0.4) * c}};
  quad(w, SDL_Color{30, 40, 60, 255});
  // Lit indicators and brake lights as small squares at the corners.
  const bool blink = (s.sim_time_ns / 400'000'000) % 2 == 0;
  const bool left = (s.lights & (wire::kIndicatorLeft | wire::kHazard)) != 0 && blink;
  const bool right = (s.lights & (wire::kIndicatorRight | wire::kHazard)) != 0 && blink;
  const auto dot = [&](double lx, double ly, SDL_Color col) {
    const double px = s.position[0] + lx * c - ly * sn, py = s.position[1] + lx * sn + ly * c;
    const Point d[4] = {{px - 0.25, py - 0.25},
                        {px + 0.25, py - 0.25},
                        {px + 0.25, py + 0.25},
                        {px - 0.25, py + 0.25}};
    quad(d, col);
  };
  if (left) {
    dot(fl, v.width_m / 2, kAmber);
    dot(-fl, v.width_m / 2, kAmber);
  }
  if (right) {
    dot(fl, -v.width_m / 2, kAmber);
    dot(-fl, -v.width_m / 2, kAmber);
  }
  if (s.controls.brake > 0.05f || (s.lights & wire::kBrakeLights) != 0) {
    dot(-fl, v.width_m / 3, SDL_Color{255, 30, 30, 255});
    dot(-fl, -v.width_m / 3, SDL_Color{255, 30, 30, 255});
  }
  if (!v.own) {
    const SDL_FPoint p = to_screen(s.position[0], s.position[1]);
    const std::string label = std::to_string(s.station_id);
    const int tw = font::text_width(label, 2);
    const int x = static_cast<int>(p.x) - tw / 2;
    const int y = static_cast<int>(p.y - v.length_m * pixels_per_metre / 2) - 22;
    SDL_SetRenderDrawBlendMode(r_, SDL_BLENDMODE_BLEND);
    SDL_SetRenderDrawColor(r_, kPanel.r, kPanel.g, kPanel.b, kPanel.a);
    const SDL_Rect bg{x - 3, y - 3, tw + 6, font::kGlyphHeight * 2 + 6};
    SDL_RenderFillRect(r_, &bg);
    text(x, y, label, 2, kText);
  }
}

void SceneRenderer::text(int x, int y, std::string_view s, int scale, SDL_Color c) {
  std::vector<SDL_Rect> px;
  px.reserve(s.size() * 20);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto g = font::glyph(s[i]);
    const int gx = x + static_cast<int>(i) * font::kAdvance * scale;
    for (int r = 0; r < font::kGlyphHeight; ++r) {
      for (int col = 0; col < font::kGlyphWidth; ++col) {
        if (g[r] & (1u << (font::kGlyphWidth - 1 - col)))
          px.push_back(SDL_Rect{gx + col * scale, y + r * scale, scale, scale});
      }
    }
  }
  SDL_SetRenderDrawColor(r_, c.r, c.g, c.b, c.a);
  SDL_RenderFillRects(r_, px.data(), static_cast<int>(px.size()));
}

// A horizontal gauge filled between fractions `from` and `to` of its width.
void SceneRenderer::bar(int x, int y, int w, int h, double from, double to, SDL_Color c) {
  SDL_SetRenderDrawColor(r_, 90, 90, 90, 255);
  const SDL_Rect frame{x, y, w, h};
  SDL_RenderDrawRect(r_, &frame);
  const double a = std::clamp(std::min(from, to), 0.0, 1.0);
  const double b = std::clamp(std::max(from, to), 0.0, 1.0);
  const SDL_Rect fill{x + 1 + static_cast<int>(a * (w - 2)), y + 1,
                      std::max(static_cast<int>((b - a) * (w - 2)), 1), h - 2};
  SDL_SetRenderDrawColor(r_, c.r, c.g, c.b, c.a);
  SDL_RenderFillRect(r_, &fill);
}

void SceneRenderer::draw_hud(const ViewScene& scene, const ViewVehicle* own) {
  SDL_SetRenderDrawBlendMode(r_, SDL_BLENDMODE_BLEND);
  SDL_SetRenderDrawColor(r_, kPanel.r, kPanel.g, kPanel.b, kPanel.a);
  const SDL_Rect panel{8, 8, 250, 150};
  SDL_RenderFillRect(r_, &panel);
  if (own != nullptr) {
    const auto& s = own->state;
    text(18, 18, fmt::format("{:.0f}", std::abs(s.speed) * 3.6), 5, kText);
    text(130, 36, "KM/H", 2, kDim);
    text(200, 18, gear_text(s.gear), 5, s.gear < 0 ? kAmber : kText);
    text(18, 70, "THR", 2, kDim);
    bar(60, 70, 180, 12, 0.0, s.controls.throttle, SDL_Color{60, 200, 90, 255});
    text(18, 88, "BRK", 2, kDim);
    bar(60, 88, 180, 12, 0.0, s.controls.brake, SDL_Color{220, 60, 60, 255});
    text(18, 106, "STR", 2, kDim);
    bar(60, 106, 180, 12, 0.5, 0.5 + s.controls.steer / 2.0, SDL_Color{80, 150, 240, 255});
    std::string flags;
    if (s.controls.reverse)
      flags += "REV ";
    if (s.controls.handbrake)
      flags += "HB ";
    if (s.lights & wire::kIndicatorLeft)
      flags += "<< ";
    if (s.lights & wire::kIndicatorRight)
      flags += ">> ";
    if (s.lights & wire::kHazard)
      flags += "HAZ ";
    if (s.lights & wire::kLowBeam)
      flags += "LOW ";
    if (s.lights & wire::kHighBeam)
      flags += "HIGH ";
    if (s.lights & wire::kFogLight)
      flags += "FOG";
    text(18, 126, flags, 2, kAmber);
    text(18, 142, fmt::format("T {:.1f} S  ST {}", s.sim_time_ns * 1e-9, s.station_id), 1, kDim);
  } else {
    text(18, 18, "NO CAR", 3, kDim);
  }
  SDL_SetRenderDrawColor(r_, kPanel.r, kPanel.g, kPanel.b, kPanel.a);
  const SDL_Rect status{0, height_ - 26, width_, 26};
  SDL_RenderFillRect(r_, &status);
  text(10, height_ - 20, scene.connection, 2, kText);
  const std::string right = scene.input + "   H: KEYS";
  text(width_ - font::text_width(right, 2) - 10, height_ - 20, right, 2, kDim);

  if (scene.help) {
    const auto& keys = key_map_help();
    const int h = static_cast<int>(keys.size()) * 22 + 40;
    const SDL_Rect box{width_ / 2 - 230, height_ / 2 - h / 2, 460, h};
    SDL_SetRenderDrawColor(r_, 0, 0, 0, 210);
    SDL_RenderFillRect(r_, &box);
    text(box.x + 16, box.y + 12, "KEYS", 2, kAmber);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const int y = box.y + 36 + static_cast<int>(i) * 22;
      text(box.x + 16, y, keys[i].keys, 2, kText);
      text(box.x + 220, y, keys[i].action, 2, kDim);
    }
  }
}

void SceneRenderer::draw(const ViewScene& scene) {
  const ViewVehicle* own = nullptr;
  for (const auto& v : scene.vehicles) {
    if (v.own) {
      own = &v;
      break;
    }
  }
  if (own != nullptr) {
    cam_ = {own->state.position[0], own->state.position[1], own->state.yaw};
  } else if (!scene.vehicles.empty()) {
    // A watcher follows the first vehicle, north up.
    cam_ = {scene.vehicles.front().state.position[0], scene.vehicles.front().state.position[1],
            kPi / 2};
  }
  SDL_SetRenderDrawBlendMode(r_, SDL_BLENDMODE_NONE);
  SDL_SetRenderDrawColor(r_, kGrass.r, kGrass.g, kGrass.b, 255);
  SDL_RenderClear(r_);
  if (scene.network != nullptr) {
    draw_map(*scene.network);
    draw_signals(scene.signals);
  }
  for (const auto& v : scene.vehicles) {
    if (!v.own)
      draw_vehicle(v);
  }
  if (own != nullptr)
    draw_vehicle(*own);  // on top
  draw_hud(scene, own);
}

std::unique_ptr<Canvas> Canvas::window(int width, int height, const std::string& title) {
  std::unique_ptr<Canvas> c(new Canvas);
  c->width_ = width;
  c->height_ = height;
  c->window_ = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                width, height, SDL_WINDOW_SHOWN);
  if (c->window_ == nullptr)
    throw std::runtime_error(std::string("cannot open a window: ") + SDL_GetError() +
                             " (use --headless without a display)");
  c->renderer_ = SDL_CreateRenderer(c->window_, -1, SDL_RENDERER_ACCELERATED);
  if (c->renderer_ == nullptr)
    c->renderer_ = SDL_CreateRenderer(c->window_, -1, SDL_RENDERER_SOFTWARE);
  if (c->renderer_ == nullptr)
    throw std::runtime_error(std::string("cannot create a renderer: ") + SDL_GetError());
  return c;
}

std::unique_ptr<Canvas> Canvas::offscreen(int width, int height) {
  std::unique_ptr<Canvas> c(new Canvas);
  c->width_ = width;
  c->height_ = height;
  c->surface_ = SDL_CreateRGBSurfaceWithFormat(0, width, height, 32, SDL_PIXELFORMAT_RGBA32);
  if (c->surface_ == nullptr)
    throw std::runtime_error(std::string("cannot create an off-screen surface: ") + SDL_GetError());
  c->renderer_ = SDL_CreateSoftwareRenderer(c->surface_);
  if (c->renderer_ == nullptr)
    throw std::runtime_error(std::string("cannot create a software renderer: ") + SDL_GetError());
  return c;
}

Canvas::~Canvas() {
  if (renderer_ != nullptr)
    SDL_DestroyRenderer(renderer_);
  if (surface_ != nullptr)
    SDL_FreeSurface(surface_);
  if (window_ != nullptr)
    SDL_DestroyWindow(window_);
}

void Canvas::present() {
  if (window_ != nullptr)
    SDL_RenderPresent(renderer_);
}

std::vector<std::uint8_t> Canvas::read_rgba() const {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(width_) * height_ * 4);
  if (SDL_RenderReadPixels(renderer_, nullptr, SDL_PIXELFORMAT_RGBA32, px.data(), width_ * 4) !=
      0) {
    return {};
  }
  return px;
}

std::string write_png(const std::string& path, int width, int height,
                      const std::vector<std::uint8_t>& rgba) {
  if (rgba.size() != static_cast<std::size_t>(width) * height * 4)
    return path + ": no pixels to write (reading the frame failed)";
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width);
  img.height = static_cast<png_uint_32>(height);
  img.format = PNG_FORMAT_RGBA;
  if (png_image_write_to_file(&img, path.c_str(), 0, rgba.data(), width * 4, nullptr) == 0) {
    std::string why = img.message;
    png_image_free(&img);
    return path + ": cannot write PNG: " + why;
  }
  return {};
}

}  // namespace tb::client
