#pragma once
/// @file The heads-up display over the 3D view, in window pixels, text in DejaVu through
/// osgText: speed, gear, throttle/brake/steer bars, indicators and lights, connection status,
/// sim time, frame rate (toggle), the V2X warning banner, the own lane's signal and the
/// red-light warning banner (issue 34), the key map, and in the cockpit a simple dashboard
/// (speedometer and rev counter).

#include <array>
#include <map>
#include <optional>
#include <string>

#include <osg/Camera>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/ref_ptr>
#include <osgText/Font>
#include <osgText/Text>

#include "sim-client/v2x/signal_panel.hpp"
#include "sim-client/view3d/frame_input.hpp"

namespace tb::client::view3d {

/// Where the DejaVu fonts are (Debian's fonts-dejavu-core).
inline constexpr const char* kFontDir = "/usr/share/fonts/truetype/dejavu";

/// A DejaVu font of kFontDir. @throws std::runtime_error naming the file when it is missing.
osg::ref_ptr<osgText::Font> dejavu(const char* file);

struct Rect {
  int x = 0, y = 0, w = 0, h = 0;  ///< window pixels, origin bottom left
};

/// Triangles in window pixels, rebuilt every frame (a few dozen quads).
class Shapes2D {
 public:
  Shapes2D();
  osg::Geometry* geometry() const { return geometry_.get(); }
  void clear();
  void rect(float x, float y, float w, float h, const osg::Vec4& c);
  void line(float x0, float y0, float x1, float y1, float width, const osg::Vec4& c);
  void frame(float x, float y, float w, float h, float width, const osg::Vec4& c);
  /// A filled circle of @p segments triangles.
  void disc(float cx, float cy, float r, const osg::Vec4& c, int segments = 32);
  void finish();

 private:
  osg::ref_ptr<osg::Geometry> geometry_;
  osg::ref_ptr<osg::Vec3Array> v_;
  osg::ref_ptr<osg::Vec4Array> c_;
  osg::ref_ptr<osg::DrawArrays> draw_;
};

class Hud {
 public:
  /// @throws std::runtime_error naming the font file when DejaVu is not installed.
  Hud();
  osg::Camera* camera() const { return camera_.get(); }

  /// Lays the HUD out for this frame: the instruments show @p subject (the car the camera
  /// follows); the warning banner the own car's warnings (the subject's when watching).
  /// @p mirror is the rear-view inset (framed), if shown.
  void update(const FrameInput& in, int subject, int width, int height, const Rect* mirror);

  /// What the banner says now; empty when none is shown (tests).
  const std::string& banner() const { return banner_; }
  /// Where the banner is (valid while banner() is not empty).
  const Rect& banner_rect() const { return banner_rect_; }
  /// The red-light warning banner's text; empty when none is shown.
  const std::string& rlvw_banner() const { return rlvw_banner_; }
  const Rect& rlvw_banner_rect() const { return rlvw_banner_rect_; }
  /// The signal panel as drawn; empty when none is shown.
  const std::optional<v2x::SignalPanel>& signal() const { return signal_; }
  /// Where the panel is (valid while signal() is set).
  const Rect& signal_rect() const { return signal_rect_; }
  struct Lamp {
    float x = 0, y = 0, r = 0;  ///< centre and radius, window pixels, origin bottom left
  };
  /// The traffic-light icon's lamps: red (top), amber, green (bottom).
  const std::array<Lamp, 3>& signal_lamps() const { return lamps_; }

 private:
  enum class Font { kRegular, kBold };
  void text(const std::string& key, const std::string& s, float x, float y, float size,
            const osg::Vec4& colour, osgText::Text::AlignmentType align, Font f = Font::kRegular,
            bool over = false);
  void telemetry(const FrameInput& in, const wire::VehicleState& s, float k);
  void dashboard(const wire::VehicleState& s, float k, int width);
  void warning(const FrameInput& in, int subject, float k, int width, int height,
               const Rect* mirror);
  void help(float k, int width, int height);
  /// The station whose warnings the driver sees: the own car's, the followed car's when
  /// watching; empty when neither is known.
  std::optional<std::uint32_t> warned_station(const FrameInput& in, int subject) const;
  void signal_panel(const FrameInput& in, int subject, float k, int width, int height);
  void rlvw(const FrameInput& in, int subject, float k, int width, int height, const Rect* mirror);

  osg::ref_ptr<osg::Camera> camera_;
  osg::ref_ptr<osgText::Font> regular_, bold_;
  Shapes2D back_;  ///< panels and bars, under the text
  Shapes2D over_;  ///< the key map's panel, over everything else
  osg::ref_ptr<osg::Geode> text_geode_, over_text_geode_;
  struct Slot {
    osg::ref_ptr<osgText::Text> text;
    bool used = false;
  };
  std::map<std::string, Slot> texts_;
  std::string banner_;
  Rect banner_rect_;
  std::string rlvw_banner_;
  Rect rlvw_banner_rect_;
  std::optional<v2x::SignalPanel> signal_;
  Rect signal_rect_;
  std::array<Lamp, 3> lamps_{};
};

}  // namespace tb::client::view3d
