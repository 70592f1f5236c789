#include "sim-client/view3d/overlay.hpp"

#include <map>

#include <fmt/format.h>
#include <osg/BlendFunc>
#include <osg/LineWidth>

#include "sim-client/view3d/hud.hpp"
#include "sim-client/view3d/vehicle_node.hpp"

namespace tb::client::view3d {
namespace {

osg::ref_ptr<osg::Geometry> dynamic_geometry(osg::Vec3Array* v, osg::Vec4Array* c,
                                             osg::DrawArrays* d) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setDataVariance(osg::Object::DYNAMIC);
  g->setVertexArray(v);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(d);
  return g;
}

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

/// Text glyphs are laid out again on every setText(): only when the text changes.
void set_text(osgText::Text& t, const std::string& s) {
  if (t.getText().createUTF8EncodedString() != s)
    t.setText(s, osgText::String::ENCODING_UTF8);
}

}  // namespace

V2xOverlay::V2xOverlay()
    : root_(new osg::Group),
      geode_(new osg::Geode),
      lv_(new osg::Vec3Array),
      sv_(new osg::Vec3Array),
      lc_(new osg::Vec4Array),
      sc_(new osg::Vec4Array),
      ld_(new osg::DrawArrays(GL_LINES, 0, 0)),
      sd_(new osg::DrawArrays(GL_TRIANGLES, 0, 0)),
      font_(dejavu("DejaVuSans-Bold.ttf")) {
  root_->setNodeMask(kMaskOverlay);
  lines_ = dynamic_geometry(lv_, lc_, ld_);
  solids_ = dynamic_geometry(sv_, sc_, sd_);
  geode_->addDrawable(lines_);
  geode_->addDrawable(solids_);
  root_->addChild(geode_);
  osg::StateSet* ss = root_->getOrCreateStateSet();
  ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
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
  lv_->clear();
  lc_->clear();
  sv_->clear();
  sc_->clear();
  links_ = markers_ = denms_ = 0;
  std::map<std::string, bool> shown;
  if (in.choice.overlay && in.world) {
    std::map<std::uint32_t, osg::Vec3> at;  // station → position
    for (std::size_t i = 0; i < in.vehicles.size() && i < in.world->vehicles.size(); ++i) {
      const auto& p = in.vehicles[i].position;
      const VehicleLook& look = in.world->vehicles[i];
      at[look.station_id] =
          osg::Vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
      const std::string key = fmt::format("car{}", look.station_id);
      osgText::Text* t = label(key);
      set_text(*t, std::to_string(look.station_id));
      t->setPosition(at[look.station_id] + osg::Vec3(0, 0, look.height_m + 0.6f));
      t->setColor(osg::Vec4(1, 1, 1, 1));
      shown[key] = true;
    }
    // Links, 1.6 m up, fading from the sender (cyan) to the receiver (white).
    for (const auto& l : in.v2x.links) {
      const auto a = at.find(l.from), b = at.find(l.to);
      if (a == at.end() || b == at.end())
        continue;
      lv_->push_back(a->second + osg::Vec3(0, 0, 1.6f));
      lc_->push_back(osg::Vec4(0.1f, 0.9f, 1.0f, 0.9f));
      lv_->push_back(b->second + osg::Vec3(0, 0, 1.6f));
      lc_->push_back(osg::Vec4(1.0f, 1.0f, 1.0f, 0.6f));
      ++links_;
    }
    // A red marker over each warned car (once, however many warnings it has).
    std::map<std::uint32_t, bool> warned;
    for (const auto& a : in.v2x.alerts)
      warned[a.station] = true;
    for (std::size_t i = 0; i < in.world->vehicles.size() && i < in.vehicles.size(); ++i) {
      const VehicleLook& look = in.world->vehicles[i];
      if (!warned.contains(look.station_id))
        continue;
      pyramid(*sv_, *sc_, at[look.station_id] + osg::Vec3(0, 0, look.height_m + 2.2f), 0.6f, 1.2f,
              osg::Vec4(1.0f, 0.1f, 0.05f, 0.95f), true);
      ++markers_;
    }
    // DENM events as orange pylons with their cause code.
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
        pyramid(*sv_, *sc_, base + osg::Vec3(0, 0, 2.5f), 0.7f, 2.5f,
                osg::Vec4(1.0f, 0.5f, 0.0f, 0.95f), false);
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
  ld_->setCount(static_cast<GLsizei>(lv_->size()));
  sd_->setCount(static_cast<GLsizei>(sv_->size()));
  for (osg::Array* a : {static_cast<osg::Array*>(lv_.get()), static_cast<osg::Array*>(lc_.get()),
                        static_cast<osg::Array*>(sv_.get()), static_cast<osg::Array*>(sc_.get())})
    a->dirty();
  lines_->dirtyBound();
  solids_->dirtyBound();
}

}  // namespace tb::client::view3d
