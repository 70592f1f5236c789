#include "sim-client/view3d/overlay.hpp"

#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>
#include <osg/BlendColor>
#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/LineWidth>
#include <osg/PolygonOffset>

#include "sim-client/view3d/hud.hpp"
#include "sim-client/view3d/vehicle_node.hpp"

namespace tb::client::view3d {
namespace {

/// Ring and disc resolution: 96 sides keep a 300 m ring within 0.2 m of the circle.
constexpr int kCircleSides = 96;

/// An upside-down pyramid with its tip at @p tip: a marker pointing at what it marks.
void pyramid(osg::Vec3Array& v, osg::Vec4Array& c, const osg::Vec3& tip, float size, float height,
             const osg::Vec4& colour, bool upside_down) {
  const float top = upside_down ? height : -height;
  const osg::Vec3 base[4] = {tip + osg::Vec3(-size, -size, top), tip + osg::Vec3(size, -size, top),
                             tip + osg::Vec3(size, size, top), tip + osg::Vec3(-size, size, top)};
  for (int i = 0; i < 4; ++i) {
    const osg::Vec4 shade = colour * (0.75f + 0.08f * static_cast<float>(i));
    for (const auto& p : {tip, base[i], base[(i + 1) % 4]}) {
      v.push_back(p);
      c.push_back(osg::Vec4(shade.r(), shade.g(), shade.b(), colour.a()));
    }
  }
  for (const auto& p : {base[0], base[2], base[1], base[0], base[3], base[2]}) {
    v.push_back(p);
    c.push_back(colour);
  }
}

osg::Vec3 on_circle(const osg::Vec3& centre, double r, int i) {
  const double a = 2.0 * std::numbers::pi * i / kCircleSides;
  return centre +
         osg::Vec3(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)), 0.0f);
}

/// A horizontal circle as line segments.
void ring(osg::Vec3Array& v, osg::Vec4Array& c, const osg::Vec3& centre, double r,
          const osg::Vec4& colour) {
  for (int i = 0; i < kCircleSides; ++i) {
    v.push_back(on_circle(centre, r, i));
    v.push_back(on_circle(centre, r, i + 1));
    c.push_back(colour);
    c.push_back(colour);
  }
}

/// A horizontal disc as a triangle fan, paler in the middle so that the rim reads as the edge.
void disc(osg::Vec3Array& v, osg::Vec4Array& c, const osg::Vec3& centre, double r,
          const osg::Vec4& rim) {
  const osg::Vec4 middle(rim.r(), rim.g(), rim.b(), rim.a() * 0.5f);
  for (int i = 0; i < kCircleSides; ++i) {
    v.push_back(centre);
    v.push_back(on_circle(centre, r, i));
    v.push_back(on_circle(centre, r, i + 1));
    c.push_back(middle);
    c.push_back(rim);
    c.push_back(rim);
  }
}

/// An arrow head at @p tip pointing along @p dir (horizontal unit vector): two crossed
/// triangles (one flat, one upright), so that it reads from above and from the side.
void arrow_head(osg::Vec3Array& v, osg::Vec4Array& c, const osg::Vec3& tip, const osg::Vec3& dir,
                const osg::Vec4& colour) {
  const float len = 1.4f, half = 0.55f;
  const osg::Vec3 back = tip - dir * len;
  const osg::Vec3 side(-dir.y(), dir.x(), 0.0f);
  for (const auto& p : {tip, back + side * half, back - side * half, tip,
                        back + osg::Vec3(0, 0, half), back - osg::Vec3(0, 0, half)}) {
    v.push_back(p);
    c.push_back(colour);
  }
}

/// Text glyphs are laid out again on every setText(): only when the text changes.
void set_text(osgText::Text& t, const std::string& s) {
  if (t.getText().createUTF8EncodedString() != s)
    t.setText(s, osgText::String::ENCODING_UTF8);
}

/// Depth-tested, no depth writes, pulled towards the eye: over the road and the ground, never
/// fighting them, and hidden by what stands in front.
void ground_state(osg::StateSet& ss) {
  ss.setAttributeAndModes(new osg::Depth(osg::Depth::LEQUAL, 0.0, 1.0, false));
  ss.setAttributeAndModes(new osg::PolygonOffset(-2.0f, -8.0f));
}

}  // namespace

V2xOverlay::Layer::Layer(GLenum mode)
    : v(new osg::Vec3Array),
      c(new osg::Vec4Array),
      d(new osg::DrawArrays(mode, 0, 0)),
      g(new osg::Geometry) {
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setDataVariance(osg::Object::DYNAMIC);
  g->setVertexArray(v);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(d);
}

void V2xOverlay::Layer::clear() {
  v->clear();
  c->clear();
}

void V2xOverlay::Layer::commit() {
  d->setCount(static_cast<GLsizei>(v->size()));
  v->dirty();
  c->dirty();
  g->dirtyBound();
}

V2xOverlay::V2xOverlay()
    : root_(new osg::Group),
      geode_(new osg::Geode),
      lines_(GL_LINES),
      solids_(GL_TRIANGLES),
      warn_(GL_LINES),
      rings_(GL_LINES),
      areas_(GL_TRIANGLES),
      font_(dejavu("DejaVuSans-Bold.ttf")) {
  root_->setNodeMask(kMaskOverlay);
  geode_->addDrawable(lines_.g);
  geode_->addDrawable(solids_.g);
  geode_->addDrawable(warn_.g);
  warn_.g->getOrCreateStateSet()->setAttributeAndModes(new osg::LineWidth(5.0f));
  root_->addChild(geode_);

  // The ground shapes, and the rings once more without depth test and faint: what a hill or a
  // car hides of a range still shows.
  osg::ref_ptr<osg::Geode> ground = new osg::Geode;
  ground->addDrawable(areas_.g);
  ground->addDrawable(rings_.g);
  ground_state(*ground->getOrCreateStateSet());
  ground->getOrCreateStateSet()->setAttributeAndModes(new osg::LineWidth(2.0f));
  root_->addChild(ground);
  osg::ref_ptr<osg::Geode> ghost = new osg::Geode;
  ghost->addDrawable(rings_.g);
  osg::StateSet* gs = ghost->getOrCreateStateSet();
  gs->setAttributeAndModes(new osg::Depth(osg::Depth::ALWAYS, 0.0, 1.0, false));
  gs->setAttributeAndModes(new osg::BlendColor(osg::Vec4(0, 0, 0, 0.3f)));
  gs->setAttributeAndModes(new osg::BlendFunc(GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA));
  gs->setAttributeAndModes(new osg::LineWidth(1.0f));
  root_->addChild(ghost);

  osg::StateSet* ss = root_->getOrCreateStateSet();
  ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  // The world's fog would grey a ring 300 m away into the haze it is meant to outline.
  ss->setMode(GL_FOG, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  ss->setMode(GL_BLEND, osg::StateAttribute::ON);
  ss->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
  ss->setAttributeAndModes(new osg::LineWidth(3.0f));
  ss->setRenderingHint(osg::StateSet::TRANSPARENT_BIN);
}

osgText::Text* V2xOverlay::label(const std::string& key) {
  auto& t = labels_[key];
  if (!t) {
    t = new osgText::Text;
    t->setDataVariance(osg::Object::DYNAMIC);
    t->setFont(font_);
    t->setFontResolution(32, 32);
    t->setAxisAlignment(osgText::Text::SCREEN);
    t->setCharacterSizeMode(osgText::Text::SCREEN_COORDS);
    t->setCharacterSize(15.0f);
    t->setAlignment(osgText::Text::CENTER_BOTTOM);
    t->setBackdropType(osgText::Text::OUTLINE);
    t->setBackdropColor(osg::Vec4(0, 0, 0, 0.8f));
    geode_->addDrawable(t);
  }
  return t.get();
}

void V2xOverlay::update(const FrameInput& in) {
  for (Layer* l : {&lines_, &solids_, &warn_, &rings_, &areas_})
    l->clear();
  links_ = markers_ = denms_ = rings_n_ = warnings_ = areas_n_ = 0;
  std::map<std::string, bool> shown;
  if (in.choice.overlay && in.world) {
    std::map<std::uint32_t, osg::Vec3> at;  // station → position
    std::map<std::uint32_t, float> roof;    // station → height of the car
    for (std::size_t i = 0; i < in.vehicles.size() && i < in.world->vehicles.size(); ++i) {
      const auto& p = in.vehicles[i].position;
      const VehicleLook& look = in.world->vehicles[i];
      at[look.station_id] =
          osg::Vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
      roof[look.station_id] = look.height_m;
      const std::string key = fmt::format("car{}", look.station_id);
      osgText::Text* t = label(key);
      set_text(*t, std::to_string(look.station_id));
      t->setPosition(at[look.station_id] + osg::Vec3(0, 0, look.height_m + 0.6f));
      t->setColor(osg::Vec4(1, 1, 1, 1));
      shown[key] = true;
    }
    // Each station's communication range (none for the ideal channel: it has no limit).
    if (in.world->radio_range_m && *in.world->radio_range_m > 0.0) {
      for (const auto& [sid, p] : at) {
        ring(*rings_.v, *rings_.c, p + osg::Vec3(0, 0, kGroundLift), *in.world->radio_range_m,
             osg::Vec4(0.35f, 1.0f, 0.45f, 0.85f));
        ++rings_n_;
      }
    }
    // Links, 1.6 m up, fading from the sender (cyan) to the receiver (white).
    for (const auto& l : in.v2x.links) {
      const auto a = at.find(l.from), b = at.find(l.to);
      if (a == at.end() || b == at.end())
        continue;
      lines_.v->push_back(a->second + osg::Vec3(0, 0, 1.6f));
      lines_.c->push_back(osg::Vec4(0.1f, 0.9f, 1.0f, 0.9f));
      lines_.v->push_back(b->second + osg::Vec3(0, 0, 1.6f));
      lines_.c->push_back(osg::Vec4(1.0f, 1.0f, 1.0f, 0.6f));
      ++links_;
    }
    // A red marker over each warned car (once, however many warnings it has), and a yellow
    // arrow over the roofs from it to every car it is warned about.
    std::map<std::uint32_t, bool> warned;
    const osg::Vec4 yellow(1.0f, 0.88f, 0.0f, 1.0f);
    for (const auto& a : in.v2x.alerts) {
      warned[a.station] = true;
      const auto from = at.find(a.station), to = at.find(a.other);
      if (from == at.end() || to == at.end() || a.station == a.other)
        continue;
      const osg::Vec3 p = from->second + osg::Vec3(0, 0, roof[a.station] + kWarningOverRoof);
      const osg::Vec3 q = to->second + osg::Vec3(0, 0, roof[a.other] + kWarningOverRoof);
      osg::Vec3 dir = q - p;
      dir.z() = 0.0f;
      if (dir.length() < 0.5f)
        continue;
      dir.normalize();
      warn_.v->push_back(p);
      warn_.v->push_back(q);
      warn_.c->push_back(yellow);
      warn_.c->push_back(yellow);
      arrow_head(*solids_.v, *solids_.c, q - dir * 1.0f, dir, yellow);
      ++warnings_;
    }
    for (std::size_t i = 0; i < in.world->vehicles.size() && i < in.vehicles.size(); ++i) {
      const VehicleLook& look = in.world->vehicles[i];
      if (!warned.contains(look.station_id))
        continue;
      pyramid(*solids_.v, *solids_.c, at[look.station_id] + osg::Vec3(0, 0, look.height_m + 2.2f),
              0.6f, 1.2f, osg::Vec4(1.0f, 0.1f, 0.05f, 0.95f), true);
      ++markers_;
    }
    // DENM events as orange pylons with their cause code, on a translucent disc as wide as
    // their relevance area.
    if (in.world->frame) {
      for (const auto& d : in.v2x.denms) {
        const geodesy::Enu e = in.world->frame->to_enu({d.latitude_deg, d.longitude_deg, 0.0});
        // The event's altitude is not in the DENM: stand it on the ground of the nearest car.
        osg::Vec3 base(static_cast<float>(e.east), static_cast<float>(e.north), 0.0f);
        float best = -1.0f;
        for (const auto& [sid, p] : at) {
          const float d2 = (osg::Vec2(p.x(), p.y()) - osg::Vec2(base.x(), base.y())).length2();
          if (best < 0.0f || d2 < best) {
            best = d2;
            base.z() = p.z();
          }
        }
        pyramid(*solids_.v, *solids_.c, base + osg::Vec3(0, 0, 2.5f), 0.7f, 2.5f,
                osg::Vec4(1.0f, 0.5f, 0.0f, 0.95f), false);
        if (d.relevance_radius_m) {
          const osg::Vec3 c = base + osg::Vec3(0, 0, kGroundLift);
          disc(*areas_.v, *areas_.c, c, *d.relevance_radius_m, osg::Vec4(1.0f, 0.45f, 0.0f, 0.28f));
          ring(*rings_.v, *rings_.c, c, *d.relevance_radius_m, osg::Vec4(1.0f, 0.55f, 0.1f, 0.9f));
          ++areas_n_;
        }
        const std::string key = fmt::format("denm{}/{}", d.originator, d.sequence);
        osgText::Text* t = label(key);
        set_text(*t, fmt::format("DENM {}/{}", d.cause, d.subcause));
        t->setPosition(base + osg::Vec3(0, 0, 2.9f));
        t->setColor(osg::Vec4(1.0f, 0.7f, 0.2f, 1));
        shown[key] = true;
        ++denms_;
      }
    }
  }
  for (auto& [key, t] : labels_)
    if (!shown.contains(key))
      set_text(*t, "");
  for (Layer* l : {&lines_, &solids_, &warn_, &rings_, &areas_})
    l->commit();
}

}  // namespace tb::client::view3d
