#include "sim-client/view3d/hud.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <osg/BlendFunc>
#include <osgText/String>

#include "sim-client/input/keyboard.hpp"

namespace tb::client::view3d {
namespace {

using Align = osgText::Text::AlignmentType;

const osg::Vec4 kWhite(1, 1, 1, 1);
const osg::Vec4 kDim(0.55f, 0.57f, 0.6f, 1);
const osg::Vec4 kPanel(0.0f, 0.0f, 0.0f, 0.5f);
const osg::Vec4 kGreen(0.25f, 0.85f, 0.35f, 1);
const osg::Vec4 kRed(0.95f, 0.2f, 0.15f, 1);
const osg::Vec4 kBlue(0.35f, 0.6f, 1.0f, 1);
const osg::Vec4 kAmber(1.0f, 0.7f, 0.1f, 1);

}  // namespace

osg::ref_ptr<osgText::Font> dejavu(const char* file) {
  const std::string path = std::string(kFontDir) + "/" + file;
  if (!std::filesystem::exists(path))
    throw std::runtime_error(fmt::format(
        "font {} not found: the 3D view writes with DejaVu (Debian package fonts-dejavu-core, "
        "scripts/install-deps)",
        path));
  osg::ref_ptr<osgText::Font> f = osgText::readRefFontFile(path);
  if (!f)
    throw std::runtime_error(fmt::format(
        "cannot load font {}: OpenSceneGraph's freetype plugin (osgdb_freetype) is missing", path));
  return f;
}

namespace {

std::string gear_text(const wire::VehicleState& s) {
  if (s.gear < 0 || s.controls.reverse)
    return "R";
  if (s.gear == 0)
    return "N";
  return std::to_string(s.gear);
}

std::string case_text(const std::string& c) {
  std::string out = c;
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

}  // namespace

Shapes2D::Shapes2D()
    : geometry_(new osg::Geometry),
      v_(new osg::Vec3Array),
      c_(new osg::Vec4Array),
      draw_(new osg::DrawArrays(GL_TRIANGLES, 0, 0)) {
  geometry_->setUseDisplayList(false);
  geometry_->setUseVertexBufferObjects(true);
  geometry_->setDataVariance(osg::Object::DYNAMIC);
  geometry_->setVertexArray(v_);
  geometry_->setColorArray(c_, osg::Array::BIND_PER_VERTEX);
  geometry_->addPrimitiveSet(draw_);
}

void Shapes2D::clear() {
  v_->clear();
  c_->clear();
}

void Shapes2D::rect(float x, float y, float w, float h, const osg::Vec4& c) {
  const osg::Vec3 a(x, y, 0), b(x + w, y, 0), d(x + w, y + h, 0), e(x, y + h, 0);
  for (const auto& p : {a, b, d, a, d, e}) {
    v_->push_back(p);
    c_->push_back(c);
  }
}

void Shapes2D::line(float x0, float y0, float x1, float y1, float width, const osg::Vec4& c) {
  osg::Vec3 dir(x1 - x0, y1 - y0, 0);
  if (dir.length2() < 1e-6f)
    return;
  dir.normalize();
  const osg::Vec3 n = osg::Vec3(-dir.y(), dir.x(), 0) * (width / 2);
  const osg::Vec3 a = osg::Vec3(x0, y0, 0) - n, b = osg::Vec3(x1, y1, 0) - n,
                  d = osg::Vec3(x1, y1, 0) + n, e = osg::Vec3(x0, y0, 0) + n;
  for (const auto& p : {a, b, d, a, d, e}) {
    v_->push_back(p);
    c_->push_back(c);
  }
}

void Shapes2D::frame(float x, float y, float w, float h, float width, const osg::Vec4& c) {
  rect(x - width, y - width, w + 2 * width, width, c);
  rect(x - width, y + h, w + 2 * width, width, c);
  rect(x - width, y, width, h, c);
  rect(x + w, y, width, h, c);
}

void Shapes2D::disc(float cx, float cy, float r, const osg::Vec4& c, int segments) {
  for (int i = 0; i < segments; ++i) {
    const double a0 = 2.0 * std::numbers::pi * i / segments;
    const double a1 = 2.0 * std::numbers::pi * (i + 1) / segments;
    for (const osg::Vec3& p : {osg::Vec3(cx, cy, 0),
                               osg::Vec3(cx + r * static_cast<float>(std::cos(a0)),
                                         cy + r * static_cast<float>(std::sin(a0)), 0),
                               osg::Vec3(cx + r * static_cast<float>(std::cos(a1)),
                                         cy + r * static_cast<float>(std::sin(a1)), 0)}) {
      v_->push_back(p);
      c_->push_back(c);
    }
  }
}

void Shapes2D::finish() {
  draw_->setCount(static_cast<GLsizei>(v_->size()));
  v_->dirty();
  c_->dirty();
  geometry_->dirtyBound();
}

Hud::Hud()
    : camera_(new osg::Camera),
      regular_(dejavu("DejaVuSans.ttf")),
      bold_(dejavu("DejaVuSans-Bold.ttf")),
      text_geode_(new osg::Geode),
      over_text_geode_(new osg::Geode) {
  camera_->setReferenceFrame(osg::Transform::ABSOLUTE_RF);
  camera_->setClearMask(GL_DEPTH_BUFFER_BIT);
  camera_->setRenderOrder(osg::Camera::POST_RENDER, 10);
  camera_->setAllowEventFocus(false);
  camera_->setViewMatrix(osg::Matrix::identity());
  camera_->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  camera_->setInheritanceMask(osg::CullSettings::NO_VARIABLES);
  camera_->setDrawBuffer(GL_BACK);
  camera_->setReadBuffer(GL_BACK);
  osg::StateSet* ss = camera_->getOrCreateStateSet();
  ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF | osg::StateAttribute::OVERRIDE);
  ss->setMode(GL_DEPTH_TEST, osg::StateAttribute::OFF | osg::StateAttribute::OVERRIDE);
  ss->setMode(GL_FOG, osg::StateAttribute::OFF | osg::StateAttribute::OVERRIDE);
  ss->setMode(GL_BLEND, osg::StateAttribute::ON);
  ss->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
  // Panels, then their text, then the key map's panel and text over everything.
  osg::ref_ptr<osg::Geode> back = new osg::Geode;
  back->addDrawable(back_.geometry());
  osg::ref_ptr<osg::Geode> over = new osg::Geode;
  over->addDrawable(over_.geometry());
  int bin = 1;
  for (osg::Geode* g : {back.get(), text_geode_.get(), over.get(), over_text_geode_.get()}) {
    g->getOrCreateStateSet()->setRenderBinDetails(bin++, "RenderBin");
    camera_->addChild(g);
  }
}

void Hud::text(const std::string& key, const std::string& s, float x, float y, float size,
               const osg::Vec4& colour, Align align, Font f, bool over) {
  Slot& slot = texts_[key];
  slot.used = true;
  if (!slot.text) {
    slot.text = new osgText::Text;
    slot.text->setDataVariance(osg::Object::DYNAMIC);
    slot.text->setCharacterSizeMode(osgText::Text::OBJECT_COORDS);
    slot.text->setFontResolution(48, 48);
    slot.text->setFont(f == Font::kBold ? bold_ : regular_);
    (over ? over_text_geode_ : text_geode_)->addDrawable(slot.text);
  }
  osgText::Text& t = *slot.text;
  if (t.getText().createUTF8EncodedString() != s)
    t.setText(s, osgText::String::ENCODING_UTF8);
  if (t.getCharacterHeight() != size)
    t.setCharacterSize(size);
  if (t.getPosition() != osg::Vec3(x, y, 0))
    t.setPosition(osg::Vec3(x, y, 0));
  if (t.getColor() != colour)
    t.setColor(colour);
  if (t.getAlignment() != align)
    t.setAlignment(align);
}

void Hud::telemetry(const FrameInput& in, const wire::VehicleState& s, float k) {
  const bool cockpit = in.choice.camera == CameraMode::kCockpit;
  const float x0 = 12 * k, y0 = 10 * k, pw = 300 * k, ph = cockpit ? 70 * k : 160 * k;
  if (!cockpit) {
    back_.rect(x0, y0, pw, ph, kPanel);
    const double kmh = std::abs(s.speed) * 3.6;
    text("speed", fmt::format("{:.0f}", kmh), x0 + 16 * k, y0 + 80 * k, 56 * k, kWhite,
         Align::LEFT_BASE_LINE, Font::kBold);
    text("unit", "km/h", x0 + 16 * k, y0 + 60 * k, 16 * k, kDim, Align::LEFT_BASE_LINE);
    text("gear", gear_text(s), x0 + pw - 16 * k, y0 + 80 * k, 44 * k,
         s.gear < 0 || s.controls.reverse ? kAmber : kWhite, Align::RIGHT_BASE_LINE, Font::kBold);
    // Indicators and lights on the panel's top line.
    const bool blink = std::fmod(static_cast<double>(s.sim_time_ns) * 1e-9, 0.7) < 0.35;
    const bool left = (s.lights & (wire::kIndicatorLeft | wire::kHazard)) != 0;
    const bool right = (s.lights & (wire::kIndicatorRight | wire::kHazard)) != 0;
    const float ty = y0 + ph - 24 * k;
    text("ind_l", "◀", x0 + 16 * k, ty, 20 * k, left && blink ? kGreen : kDim,
         Align::LEFT_BASE_LINE);
    text("ind_r", "▶", x0 + 44 * k, ty, 20 * k, right && blink ? kGreen : kDim,
         Align::LEFT_BASE_LINE);
    std::string lights;
    const std::pair<std::uint16_t, const char*> named[] = {{wire::kLowBeam, "LOW"},
                                                           {wire::kHighBeam, "HIGH"},
                                                           {wire::kFogLight, "FOG"},
                                                           {wire::kHazard, "HAZARD"}};
    for (const auto& [bit, name] : named)
      if ((s.lights & bit) != 0)
        lights += std::string(lights.empty() ? "" : " ") + name;
    if (s.controls.handbrake)
      lights += std::string(lights.empty() ? "" : " ") + "HANDBRAKE";
    text("lights", lights, x0 + 80 * k, ty, 15 * k, kBlue, Align::LEFT_BASE_LINE);
  }
  // Throttle, brake and steer as the server applied them.
  const float bx = x0 + 86 * k, bw = 196 * k, bh = 9 * k;
  const float rows[3] = {y0 + 46 * k, y0 + 30 * k, y0 + 14 * k};
  const char* names[3] = {"throttle", "brake", "steer"};
  for (int i = 0; i < 3; ++i) {
    text(std::string("label_") + names[i], names[i], x0 + 16 * k, rows[i], 13 * k, kDim,
         Align::LEFT_BASE_LINE);
    back_.rect(bx, rows[i], bw, bh, osg::Vec4(1, 1, 1, 0.15f));
  }
  back_.rect(bx, rows[0], bw * std::clamp(s.controls.throttle, 0.0f, 1.0f), bh, kGreen);
  back_.rect(bx, rows[1], bw * std::clamp(s.controls.brake, 0.0f, 1.0f), bh, kRed);
  const float steer = std::clamp(s.controls.steer, -1.0f, 1.0f);
  const float mid = bx + bw / 2;
  back_.rect(std::min(mid, mid + steer * bw / 2), rows[2], std::abs(steer) * bw / 2 + 1, bh,
             kWhite);
  back_.rect(mid - 1, rows[2] - 2 * k, 2, bh + 4 * k, kAmber);
}

void Hud::dashboard(const wire::VehicleState& s, float k, int width) {
  const float h = 150 * k;
  back_.rect(0, 0, static_cast<float>(width), h, osg::Vec4(0.07f, 0.07f, 0.08f, 1.0f));
  back_.rect(0, h, static_cast<float>(width), 4 * k, osg::Vec4(0.2f, 0.2f, 0.22f, 1));
  auto gauge = [&](const std::string& key, float cx, float cy, float r, double value, double max,
                   int major, const std::string& label, const std::string& centre) {
    // 240° sweep, from lower left (210°) clockwise to lower right (-30°).
    auto at = [&](double f, float radius) {
      const double a = (210.0 - 240.0 * std::clamp(f, 0.0, 1.0)) * std::numbers::pi / 180.0;
      return osg::Vec2(cx + radius * static_cast<float>(std::cos(a)),
                       cy + radius * static_cast<float>(std::sin(a)));
    };
    for (int i = 0; i <= major; ++i) {
      const osg::Vec2 p0 = at(static_cast<double>(i) / major, r),
                      p1 = at(static_cast<double>(i) / major, r * 0.84f);
      back_.line(p0.x(), p0.y(), p1.x(), p1.y(), 2 * k, kWhite);
    }
    for (int i = 0; i < 48; ++i) {
      const osg::Vec2 p0 = at(i / 48.0, r), p1 = at((i + 1) / 48.0, r);
      back_.line(p0.x(), p0.y(), p1.x(), p1.y(), 1.5f * k, kDim);
    }
    const osg::Vec2 tip = at(value / max, r * 0.9f);
    back_.line(cx, cy, tip.x(), tip.y(), 3 * k, kRed);
    text(key + "_label", label, cx, cy - 0.55f * r, 12 * k, kDim, Align::CENTER_BASE_LINE);
    text(key + "_value", centre, cx, cy - 0.3f * r, 22 * k, kWhite, Align::CENTER_BASE_LINE,
         Font::kBold);
  };
  const float cy = 72 * k, r = 62 * k;
  const double kmh = std::abs(s.speed) * 3.6;
  gauge("speedo", width / 2.0f - 110 * k, cy, r, kmh, 240.0, 12, "km/h",
        fmt::format("{:.0f}", kmh));
  gauge("revs", width / 2.0f + 110 * k, cy, r, s.engine_rpm, 8000.0, 8, "rpm ×1000",
        fmt::format("{:.1f}", s.engine_rpm / 1000.0));
  text("dash_gear", gear_text(s), width / 2.0f, cy, 40 * k,
       s.gear < 0 || s.controls.reverse ? kAmber : kWhite, Align::CENTER_BASE_LINE, Font::kBold);
  const bool blink = std::fmod(static_cast<double>(s.sim_time_ns) * 1e-9, 0.7) < 0.35;
  const bool left = (s.lights & (wire::kIndicatorLeft | wire::kHazard)) != 0;
  const bool right = (s.lights & (wire::kIndicatorRight | wire::kHazard)) != 0;
  text("dash_l", "◀", width / 2.0f - 26 * k, cy + 44 * k, 20 * k, left && blink ? kGreen : kDim,
       Align::CENTER_BASE_LINE);
  text("dash_r", "▶", width / 2.0f + 26 * k, cy + 44 * k, 20 * k, right && blink ? kGreen : kDim,
       Align::CENTER_BASE_LINE);
  const bool beams = (s.lights & (wire::kLowBeam | wire::kHighBeam)) != 0;
  text("dash_beam", (s.lights & wire::kHighBeam) != 0 ? "HIGH" : "LOW", width / 2.0f, cy - 30 * k,
       13 * k, beams ? kBlue : osg::Vec4(0.25f, 0.25f, 0.28f, 1), Align::CENTER_BASE_LINE);
}

std::optional<std::uint32_t> Hud::warned_station(const FrameInput& in, int subject) const {
  if (!in.v2x_enabled)
    return std::nullopt;
  // The driver's own HMI, whichever car the camera shows; the followed car's when watching.
  const int warned = in.own >= 0 ? in.own : subject;
  if (!in.world || warned < 0 || static_cast<std::size_t>(warned) >= in.world->vehicles.size())
    return std::nullopt;
  return in.world->vehicles[static_cast<std::size_t>(warned)].station_id;
}

void Hud::warning(const FrameInput& in, int subject, float k, int width, int height,
                  const Rect* mirror) {
  banner_.clear();
  const auto station_id = warned_station(in, subject);
  if (!station_id)
    return;
  const std::uint32_t station = *station_id;
  const int warned = in.own >= 0 ? in.own : subject;
  const v2x::LcrwAlert* a = in.v2x.alert_for(station);
  if (a == nullptr)
    return;
  const bool critical = a->severity == "critical";
  const std::string ttc = a->ttc_s ? fmt::format("TTC {:.1f} s", *a->ttc_s) : "TTC –";
  banner_ = fmt::format(
      "{} · {} · {} · {:.0f} m", critical ? "COLLISION WARNING – BRAKE" : "COLLISION WARNING",
      case_text(a->collision_case.empty() ? "collision" : a->collision_case), ttc, a->distance_m);
  if (warned != in.own)
    banner_ = fmt::format("{}: {}", station, banner_);
  const float bw = std::min(820 * k, width - 40 * k), bh = 54 * k;
  // Under the mirror, or under the top-left lines when there is none.
  const float top = mirror != nullptr ? mirror->y - 14 * k : height - 62 * k;
  banner_rect_ = {static_cast<int>((width - bw) / 2), static_cast<int>(top - bh),
                  static_cast<int>(bw), static_cast<int>(bh)};
  // A critical warning flashes (4 Hz) between two reds; a warning is steady.
  const bool flash =
      critical && std::fmod(static_cast<double>(in.sim_time_ns) * 1e-9, 0.25) < 0.125;
  const osg::Vec4 fill =
      critical ? (flash ? osg::Vec4(1.0f, 0.1f, 0.05f, 0.95f) : osg::Vec4(0.75f, 0.0f, 0.0f, 0.95f))
               : osg::Vec4(0.85f, 0.16f, 0.06f, 0.92f);
  back_.rect(static_cast<float>(banner_rect_.x), static_cast<float>(banner_rect_.y), bw, bh, fill);
  back_.frame(static_cast<float>(banner_rect_.x), static_cast<float>(banner_rect_.y), bw, bh, 3 * k,
              osg::Vec4(1, 0.85f, 0.2f, 1));
  text("banner", "⚠ " + banner_, width / 2.0f, banner_rect_.y + bh / 2, 24 * k, kWhite,
       Align::CENTER_CENTER, Font::kBold);
}

void Hud::signal_panel(const FrameInput& in, int subject, float k, int width, int height) {
  signal_.reset();
  const auto station = warned_station(in, subject);
  if (!station)
    return;
  signal_ = v2x::signal_panel(in.v2x, *station);
  if (!signal_)
    return;
  const v2x::SignalPanel& p = *signal_;
  // On the right, its top 282 px (of 720) under the window's: below the mirror and both
  // banners stacked under it (the lower one ends 266 px down), above the status lines
  // (bottom right) and clear of the instruments (bottom left).
  const float pw = 236 * k, ph = 172 * k;
  const float x0 = width - 14 * k - pw, y0 = height - 282 * k - ph;
  signal_rect_ = {static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(pw),
                  static_cast<int>(ph)};
  back_.rect(x0, y0, pw, ph, kPanel);
  // The icon: a housing with three lamps, lit in the colours of a real head, unlit ones dark;
  // dark and unavailable leave all three grey.
  const float hx = x0 + 10 * k, hy = y0 + 10 * k, hw = 56 * k, hh = ph - 20 * k;
  back_.rect(hx, hy, hw, hh, osg::Vec4(0.08f, 0.08f, 0.09f, 1));
  back_.frame(hx, hy, hw, hh, 2 * k, osg::Vec4(0.3f, 0.3f, 0.32f, 1));
  const bool off = p.light == v2x::SignalLight::kDark || p.light == v2x::SignalLight::kUnavailable;
  const osg::Vec4 unlit = off ? osg::Vec4(0.42f, 0.42f, 0.44f, 1) : osg::Vec4(0.2f, 0.2f, 0.2f, 1);
  const std::array<bool, 3> lit{p.red, p.amber, p.green};
  const std::array<osg::Vec4, 3> colour{osg::Vec4(1.0f, 0.12f, 0.1f, 1),
                                        osg::Vec4(1.0f, 0.72f, 0.0f, 1),
                                        osg::Vec4(0.1f, 0.95f, 0.3f, 1)};
  for (std::size_t i = 0; i < 3; ++i) {
    lamps_[i] = {hx + hw / 2, hy + hh * (5.0f - 2.0f * static_cast<float>(i)) / 6.0f, 20 * k};
    back_.disc(lamps_[i].x, lamps_[i].y, lamps_[i].r, lit[i] ? colour[i] : unlit);
  }
  const osg::Vec4 accent = p.green             ? colour[2]
                           : p.amber && !p.red ? colour[1]
                           : p.red             ? colour[0]
                                               : kDim;
  const float tx = x0 + 80 * k;
  text("sig_caption", p.caption, tx, y0 + ph - 26 * k, 13 * k, osg::Vec4(0.8f, 0.8f, 0.82f, 1),
       Align::LEFT_BASE_LINE);
  text("sig_countdown", p.countdown.empty() ? "–" : p.countdown, tx, y0 + ph - 72 * k, 40 * k,
       accent, Align::LEFT_BASE_LINE, Font::kBold);
  text("sig_distance", p.distance + " to stop line", tx, y0 + 64 * k, 15 * k, kWhite,
       Align::LEFT_BASE_LINE);
  if (!p.advice.empty()) {
    text("sig_advice_label", "speed for green", tx, y0 + 40 * k, 12 * k, kDim,
         Align::LEFT_BASE_LINE);
    text("sig_advice", p.advice, tx, y0 + 16 * k, 20 * k, kGreen, Align::LEFT_BASE_LINE,
         Font::kBold);
  }
}

void Hud::rlvw(const FrameInput& in, int subject, float k, int width, int height,
               const Rect* mirror) {
  rlvw_banner_.clear();
  const auto station = warned_station(in, subject);
  if (!station)
    return;
  rlvw_banner_ = v2x::rlvw_banner(in.v2x, *station);
  if (rlvw_banner_.empty())
    return;
  if (in.own < 0)
    rlvw_banner_ = fmt::format("{}: {}", *station, rlvw_banner_);
  const float bw = std::min(820 * k, width - 40 * k), bh = 54 * k;
  // Where the collision banner goes, or under it when both are up.
  const float top = !banner_.empty()    ? banner_rect_.y - 10 * k
                    : mirror != nullptr ? mirror->y - 14 * k
                                        : height - 62 * k;
  rlvw_banner_rect_ = {static_cast<int>((width - bw) / 2), static_cast<int>(top - bh),
                       static_cast<int>(bw), static_cast<int>(bh)};
  // Pulses (2 Hz) between two deep reds, slower than a critical collision warning's flash.
  const bool pulse = std::fmod(static_cast<double>(in.sim_time_ns) * 1e-9, 0.5) < 0.25;
  const osg::Vec4 fill =
      pulse ? osg::Vec4(0.85f, 0.0f, 0.02f, 0.95f) : osg::Vec4(0.68f, 0.0f, 0.02f, 0.95f);
  const float x = static_cast<float>(rlvw_banner_rect_.x),
              y = static_cast<float>(rlvw_banner_rect_.y);
  back_.rect(x, y, bw, bh, fill);
  back_.frame(x, y, bw, bh, 3 * k, kWhite);
  text("rlvw_banner", "⚠ " + rlvw_banner_, width / 2.0f, y + bh / 2, 24 * k, kWhite,
       Align::CENTER_CENTER, Font::kBold);
}

void Hud::help(float k, int width, int height) {
  const auto& keys = key_map_help();
  const float line = 22 * k, pw = 560 * k;
  const float ph = line * static_cast<float>(keys.size() + 2);
  const float x = (width - pw) / 2, y = (height - ph) / 2;
  over_.rect(x, y, pw, ph, osg::Vec4(0.05f, 0.06f, 0.08f, 0.88f));
  text("help_title", "Keys", x + 20 * k, y + ph - line, 18 * k, kAmber, Align::LEFT_BASE_LINE,
       Font::kBold, true);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const float ly = y + ph - line * static_cast<float>(i + 2);
    text(fmt::format("help_k{}", i), std::string(keys[i].keys), x + 20 * k, ly, 15 * k, kWhite,
         Align::LEFT_BASE_LINE, Font::kBold, true);
    text(fmt::format("help_a{}", i), std::string(keys[i].action), x + 220 * k, ly, 15 * k, kWhite,
         Align::LEFT_BASE_LINE, Font::kRegular, true);
  }
}

void Hud::update(const FrameInput& in, int subject, int width, int height, const Rect* mirror) {
  camera_->setProjectionMatrixAsOrtho2D(0, width, 0, height);
  camera_->setViewport(0, 0, width, height);
  for (auto& [key, slot] : texts_)
    slot.used = false;
  back_.clear();
  over_.clear();
  const float k = static_cast<float>(height) / 720.0f;

  const wire::VehicleState* s = nullptr;
  if (subject >= 0 && static_cast<std::size_t>(subject) < in.vehicles.size())
    s = &in.vehicles[static_cast<std::size_t>(subject)];
  const VehicleLook* look =
      in.world && subject >= 0 && static_cast<std::size_t>(subject) < in.world->vehicles.size()
          ? &in.world->vehicles[static_cast<std::size_t>(subject)]
          : nullptr;

  // Top left: whose view, which camera, sim time.
  std::string who = "waiting for the server";
  if (look != nullptr)
    who =
        fmt::format("{}{} · station {}", in.own < 0 ? "watching " : "", look->id, look->station_id);
  text("who", who, 14 * k, height - 28 * k, 19 * k, kWhite, Align::LEFT_BASE_LINE, Font::kBold);
  text("sub",
       fmt::format("{} camera · sim time {:.1f} s · H keys", to_string(in.choice.camera),
                   static_cast<double>(in.sim_time_ns) * 1e-9),
       14 * k, height - 48 * k, 14 * k, kDim, Align::LEFT_BASE_LINE);
  if (in.choice.show_fps)
    text("fps", fmt::format("{:.0f} fps · {:.1f} ms", in.fps, in.fps > 0 ? 1000.0 / in.fps : 0.0),
         width - 14 * k, height - 28 * k, 16 * k, kAmber, Align::RIGHT_BASE_LINE, Font::kBold);

  if (mirror != nullptr) {
    back_.frame(static_cast<float>(mirror->x), static_cast<float>(mirror->y),
                static_cast<float>(mirror->w), static_cast<float>(mirror->h), 4 * k,
                osg::Vec4(0.05f, 0.05f, 0.05f, 1));
  }
  if (s != nullptr) {
    if (in.choice.camera == CameraMode::kCockpit)
      dashboard(*s, k, width);
    telemetry(in, *s, k);
  }
  warning(in, subject, k, width, height, mirror);
  rlvw(in, subject, k, width, height, mirror);
  signal_panel(in, subject, k, width, height);

  // Bottom right: the links to the outside world.
  const float sy = in.choice.camera == CameraMode::kCockpit ? 160 * k : 12 * k;
  text("conn", in.status.connection, width - 14 * k, sy + 18 * k, 13 * k, kDim,
       Align::RIGHT_BASE_LINE);
  std::string line = in.status.input;
  if (!in.status.mqtt.empty())
    line += " · " + in.status.mqtt;
  text("input", line, width - 14 * k, sy, 13 * k, kDim, Align::RIGHT_BASE_LINE);

  if (in.status.finished) {
    // The end of the scenario: said over the last picture, which stays until the window closes.
    const float pw = std::min(620 * k, width - 40 * k), ph = 92 * k;
    const float x = (width - pw) / 2, y = (height - ph) / 2;
    over_.rect(x, y, pw, ph, osg::Vec4(0.05f, 0.06f, 0.08f, 0.88f));
    text("finished", "scenario finished", width / 2.0f, y + ph * 0.62f, 30 * k, kWhite,
         Align::CENTER_CENTER, Font::kBold, true);
    text("finished_sub", "close the window (or Esc) to quit", width / 2.0f, y + ph * 0.24f, 15 * k,
         kDim, Align::CENTER_CENTER, Font::kRegular, true);
  }
  if (in.choice.help)
    help(k, width, height);

  for (auto& [key, slot] : texts_) {
    if (!slot.used && !slot.text->getText().empty())
      slot.text->setText("");
  }
  back_.finish();
  over_.finish();
}

}  // namespace tb::client::view3d
