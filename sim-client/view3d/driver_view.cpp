#include "sim-client/view3d/driver_view.hpp"

#include <algorithm>
#include <cmath>

#include <numbers>

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Fog>
#include <osg/Geode>
#include <osg/Light>
#include <osg/LightSource>
#include <osg/Material>
#include <osg/Transform>
#include <osgUtil/CullVisitor>

#include "sim-client/view3d/junction_marks.hpp"
#include "sim-client/view3d/road_objects_node.hpp"

namespace tb::client::view3d {
namespace {

// The sky: pale at the horizon (the fog's and the clear colour, so that the far world fades
// into it without a seam), deep blue overhead.
const osg::Vec4 kSky(0.74f, 0.83f, 0.93f, 1.0f);
const osg::Vec4 kZenith(0.20f, 0.40f, 0.78f, 1.0f);
// The sun: south-east, 20° up — low enough to be seen ahead in the chase camera (which sees
// about 21° above the horizon) and the cockpit, high enough to light the ground.
const osg::Vec3 kSunDirection = [] {
  constexpr double el = 20.0 * std::numbers::pi / 180, az = -45.0 * std::numbers::pi / 180;
  return osg::Vec3(static_cast<float>(std::cos(el) * std::cos(az)),
                   static_cast<float>(std::cos(el) * std::sin(az)),
                   static_cast<float>(std::sin(el)));
}();
/// Radius of the sky dome around the eye: inside every perspective camera's far plane.
constexpr float kSkyRadius = 1200.0f;

/// Keeps its children centred on the eye of the camera that draws them (the main view's or the
/// mirror's): the sky never comes nearer, so it shows no parallax.
class FollowEye : public osg::Transform {
 public:
  FollowEye() { setCullingActive(false); }
  bool computeLocalToWorldMatrix(osg::Matrix& m, osg::NodeVisitor* nv) const override {
    if (auto* cv = dynamic_cast<osgUtil::CullVisitor*>(nv))
      m.preMultTranslate(cv->getEyeLocal());
    return true;
  }
  bool computeWorldToLocalMatrix(osg::Matrix& m, osg::NodeVisitor* nv) const override {
    if (auto* cv = dynamic_cast<osgUtil::CullVisitor*>(nv))
      m.postMultTranslate(-cv->getEyeLocal());
    return true;
  }
};

osg::ref_ptr<osg::Geometry> triangles(osg::Vec3Array* v, osg::Vec4Array* c) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setVertexArray(v);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(v->size())));
  g->setCullingActive(false);
  return g;
}

/// The colour of the sky @p elevation radians above the horizon.
osg::Vec4 sky_colour(double elevation) {
  const double t = elevation <= 0.0 ? 0.0 : std::pow(std::sin(elevation), 0.6);
  return kSky * static_cast<float>(1.0 - t) + kZenith * static_cast<float>(t);
}

/// A dome of coloured rings from the horizon up and the sun's disc with a glow, drawn first,
/// unlit, without fog, depth test or depth writes: everything else draws over it. Below the
/// horizon the clear colour (the horizon's) shows where the world ends, so the dome needs no
/// skirt; and it is opaque, only the glow blends: on a software renderer every blended pixel
/// of a sky across half the screen costs.
osg::ref_ptr<osg::Node> make_sky() {
  constexpr int kSides = 32;
  constexpr double kDeg = std::numbers::pi / 180;
  const double rings[] = {0, 4, 10, 20, 35, 55, 90};
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  const auto at = [](double el, double az) {
    return osg::Vec3(static_cast<float>(std::cos(el) * std::cos(az)),
                     static_cast<float>(std::cos(el) * std::sin(az)),
                     static_cast<float>(std::sin(el))) *
           kSkyRadius;
  };
  for (std::size_t r = 0; r + 1 < std::size(rings); ++r) {
    const double e0 = rings[r] * kDeg, e1 = rings[r + 1] * kDeg;
    for (int i = 0; i < kSides; ++i) {
      const double a0 = 2 * std::numbers::pi * i / kSides;
      const double a1 = 2 * std::numbers::pi * (i + 1) / kSides;
      for (const auto& [e, a] :
           {std::pair{e0, a0}, {e0, a1}, {e1, a1}, {e0, a0}, {e1, a1}, {e1, a0}}) {
        v->push_back(at(e, a));
        c->push_back(sky_colour(e));
      }
    }
  }
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(triangles(v, c));
  v = new osg::Vec3Array;
  c = new osg::Vec4Array;
  // The sun: a disc 1.2° wide in the light's direction, in a glow that fades out over 5°.
  const osg::Vec3 sun = kSunDirection * (0.95f * kSkyRadius);
  osg::Vec3 u = kSunDirection ^ osg::Vec3(0, 0, 1);
  u.normalize();
  const osg::Vec3 w = u ^ kSunDirection;
  const float disc = 0.95f * kSkyRadius * static_cast<float>(std::tan(0.6 * kDeg));
  const float glow = 0.95f * kSkyRadius * static_cast<float>(std::tan(5.0 * kDeg));
  const osg::Vec4 white(1.0f, 0.98f, 0.88f, 1.0f), clear(1.0f, 0.96f, 0.82f, 0.0f);
  const osg::Vec4 haze(1.0f, 0.96f, 0.82f, 0.45f);
  for (int i = 0; i < kSides; ++i) {
    const double a0 = 2 * std::numbers::pi * i / kSides;
    const double a1 = 2 * std::numbers::pi * (i + 1) / kSides;
    const osg::Vec3 d0 =
        u * static_cast<float>(std::cos(a0)) + w * static_cast<float>(std::sin(a0));
    const osg::Vec3 d1 =
        u * static_cast<float>(std::cos(a1)) + w * static_cast<float>(std::sin(a1));
    for (const auto& [p, col] : {std::pair{sun + d0 * disc, haze},
                                 {sun + d0 * glow, clear},
                                 {sun + d1 * glow, clear},
                                 {sun + d0 * disc, haze},
                                 {sun + d1 * glow, clear},
                                 {sun + d1 * disc, haze},
                                 {sun, white},
                                 {sun + d0 * disc, white},
                                 {sun + d1 * disc, white}}) {
      v->push_back(p);
      c->push_back(col);
    }
  }
  osg::ref_ptr<osg::Geometry> sun_disc = triangles(v, c);
  osg::StateSet* blend = sun_disc->getOrCreateStateSet();
  blend->setMode(GL_BLEND, osg::StateAttribute::ON);
  blend->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
  // A bin nested in the dome's (-10): a positive number draws after the dome's own leaves.
  blend->setRenderBinDetails(1, "RenderBin");
  geode->addDrawable(sun_disc);
  geode->setCullingActive(false);
  osg::StateSet* ss = geode->getOrCreateStateSet();
  const auto off = osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED;
  ss->setMode(GL_LIGHTING, off);
  ss->setMode(GL_FOG, off);
  ss->setMode(GL_CULL_FACE, off);
  ss->setMode(GL_BLEND, off);
  ss->setAttributeAndModes(new osg::Depth(osg::Depth::ALWAYS, 0.0, 1.0, false));
  // Before the ground (bin -1), which is drawn without depth writes too.
  ss->setRenderBinDetails(-10, "RenderBin");
  osg::ref_ptr<FollowEye> follow = new FollowEye;
  follow->addChild(geode);
  follow->setNodeMask(kMaskWorld);
  return follow;
}

}  // namespace

/// Reads the frame back once the last camera (the HUD) has drawn.
class DriverView::Capture : public osg::Camera::DrawCallback {
 public:
  void arm(int w, int h) {
    armed_ = true;
    width_ = w;
    height_ = h;
  }
  std::optional<Image> take() {
    std::optional<Image> out = std::move(image_);
    image_.reset();
    return out;
  }
  void operator()(osg::RenderInfo&) const override {
    if (!armed_)
      return;
    armed_ = false;
    Image im;
    im.width = width_;
    im.height = height_;
    std::vector<std::uint8_t> bottom_up(static_cast<std::size_t>(width_) * height_ * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    im.rgba.resize(bottom_up.size());
    const std::size_t row = static_cast<std::size_t>(width_) * 4;
    for (int y = 0; y < height_; ++y)
      std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>((height_ - 1 - y) * row), row,
                  im.rgba.begin() + static_cast<std::ptrdiff_t>(y * row));
    image_ = std::move(im);
  }

 private:
  mutable bool armed_ = false;
  mutable std::optional<Image> image_;
  int width_ = 0, height_ = 0;
};

DriverView::DriverView(int width, int height)
    : width_(width),
      height_(height),
      viewer_(new osgViewer::Viewer),
      root_(new osg::Group),
      scene_(new osg::Group),
      roads_(new osg::Group),
      cars_(new osg::Group),
      mirror_camera_(new osg::Camera),
      capture_(new Capture),
      hud_(std::make_unique<Hud>()),
      overlay_(std::make_unique<V2xOverlay>()) {
  window_ = viewer_->setUpViewerAsEmbeddedInWindow(0, 0, width, height);
  viewer_->setThreadingModel(osgViewer::Viewer::SingleThreaded);
  viewer_->setKeyEventSetsDone(0);
  viewer_->setQuitEventSetsDone(false);
  viewer_->setReleaseContextAtEndOfFrameHint(false);
  viewer_->setLightingMode(osg::View::NO_LIGHT);
  osg::Camera* cam = viewer_->getCamera();
  // SDL's window is double-buffered and the render thread swaps: draw into the back buffer.
  cam->setDrawBuffer(GL_BACK);
  cam->setReadBuffer(GL_BACK);
  cam->setClearColor(kSky);
  cam->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);

  // The sun: a directional light from the sun's disc in the sky, placed in world coordinates
  // so that the main camera and the mirror light the world alike. Low, so the ambient part is
  // larger: flat ground gets about what it got from the former 50° sun. Specular only shows
  // on the cars' glass (the only material with a specular colour).
  osg::ref_ptr<osg::Light> sun = new osg::Light(0);
  sun->setPosition(osg::Vec4(kSunDirection, 0.0f));
  sun->setAmbient(osg::Vec4(0.62f, 0.62f, 0.64f, 1));
  sun->setDiffuse(osg::Vec4(0.90f, 0.89f, 0.84f, 1));
  sun->setSpecular(osg::Vec4(0.9f, 0.88f, 0.8f, 1));
  osg::ref_ptr<osg::LightSource> ls = new osg::LightSource;
  ls->setLight(sun);
  ls->setReferenceFrame(osg::LightSource::RELATIVE_RF);
  scene_->addChild(ls);
  osg::StateSet* ss = scene_->getOrCreateStateSet();
  ls->setStateSetModes(*ss, osg::StateAttribute::ON);
  ss->setMode(GL_LIGHTING, osg::StateAttribute::ON);
  osg::ref_ptr<osg::Material> mat = new osg::Material;
  mat->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
  ss->setAttributeAndModes(mat);
  osg::ref_ptr<osg::Fog> fog = new osg::Fog;
  fog->setMode(osg::Fog::LINEAR);
  fog->setStart(250.0f);
  fog->setEnd(2000.0f);
  fog->setColor(kSky);
  ss->setAttributeAndModes(fog);

  scene_->addChild(make_sky());
  roads_->setNodeMask(kMaskWorld);
  scene_->addChild(roads_);
  scene_->addChild(cars_);
  scene_->addChild(overlay_->node());
  root_->addChild(scene_);

  // The mirror: its own camera over the same scene, drawn after the main view into an inset.
  mirror_camera_->setReferenceFrame(osg::Transform::ABSOLUTE_RF);
  mirror_camera_->setRenderOrder(osg::Camera::POST_RENDER, 0);
  mirror_camera_->setClearMask(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  mirror_camera_->setClearColor(kSky);
  mirror_camera_->setAllowEventFocus(false);
  // Its own cull mask (not the main camera's); the draw buffer is not inherited then either.
  mirror_camera_->setInheritanceMask(osg::CullSettings::NO_VARIABLES);
  mirror_camera_->setDrawBuffer(GL_BACK);
  mirror_camera_->setReadBuffer(GL_BACK);
  mirror_camera_->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  mirror_camera_->setCullMask(kMaskWorld | kMaskVehicle);
  mirror_camera_->addChild(scene_);
  mirror_camera_->setNodeMask(0);
  root_->addChild(mirror_camera_);

  hud_->camera()->setFinalDrawCallback(capture_);
  root_->addChild(hud_->camera());
  viewer_->setSceneData(root_);
  viewer_->realize();
}

DriverView::~DriverView() = default;

void DriverView::resize(int width, int height) {
  if (width == width_ && height == height_)
    return;
  width_ = width;
  height_ = height;
  window_->resized(0, 0, width, height);
  viewer_->getCamera()->setViewport(0, 0, width, height);
}

void DriverView::build_world(const World& w) {
  roads_->removeChildren(0, roads_->getNumChildren());
  if (w.network) {
    roads_->addChild(make_road_node(*w.network, &road_stats_));
    roads_->addChild(make_junction_marks_node(*w.network));
    roads_->addChild(make_road_objects_node(*w.network));
    signal_heads_ = std::make_unique<SignalHeadsNode>(*w.network);
    roads_->addChild(signal_heads_->node());
  } else {
    signal_heads_.reset();
  }
  cars_->removeChildren(0, cars_->getNumChildren());
  vehicles_.clear();
  for (const auto& look : w.vehicles) {
    vehicles_.push_back(std::make_unique<VehicleNode>(look));
    cars_->addChild(vehicles_.back()->node());
  }
  for (auto& r : rigs_)
    if (r)
      r->reset();
}

void DriverView::render(const FrameInput& in, double dt_s) {
  if (in.world && (in.world != world_ || in.world->version != world_version_)) {
    world_ = in.world;
    world_version_ = in.world->version;
    build_world(*in.world);
  }
  const std::size_t n = std::min(vehicles_.size(), in.vehicles.size());
  for (std::size_t i = 0; i < vehicles_.size(); ++i)
    vehicles_[i]->node()->setNodeMask(i < n ? vehicles_[i]->node()->getNodeMask() : 0u);
  for (std::size_t i = 0; i < n; ++i) {
    vehicles_[i]->set_own(static_cast<int>(i) == in.own);
    vehicles_[i]->update(in.vehicles[i]);
  }
  if (signal_heads_)
    signal_heads_->update(in.signals, in.sim_time_ns);

  // Who the camera follows: the chosen target, else the own car, else the first.
  int subject = in.choice.target;
  if (subject < 0 || static_cast<std::size_t>(subject) >= n)
    subject = in.own >= 0 && static_cast<std::size_t>(in.own) < n ? in.own : (n > 0 ? 0 : -1);
  const CameraMode mode = in.choice.camera;
  auto& rig = rigs_[static_cast<std::size_t>(mode)];
  if (!rig)
    rig = make_camera(mode);
  if (mode != mode_ || subject != subject_ || first_)
    rig->reset();
  mode_ = mode;
  subject_ = subject;
  first_ = false;

  const Viewport vp{width_, height_};
  Subject sub;
  if (subject >= 0) {
    const auto& s = in.vehicles[static_cast<std::size_t>(subject)];
    const auto& look = world_->vehicles[static_cast<std::size_t>(subject)];
    sub.position.set(s.position[0], s.position[1], s.position[2]);
    sub.yaw = s.yaw;
    sub.pitch = s.pitch;
    sub.roll = s.roll;
    sub.length = look.length_m;
    sub.width = look.width_m;
    sub.height = look.height_m;
  }
  pose_ = rig->update(sub, in.choice, vp, dt_s);
  osg::Camera* cam = viewer_->getCamera();
  cam->setViewport(0, 0, width_, height_);
  cam->setViewMatrix(pose_.view);
  cam->setProjectionMatrix(pose_.projection);
  // The driver's eye is inside the own car: leave the car out of the cockpit view.
  unsigned mask = kMaskWorld | kMaskVehicle | kMaskOwnVehicle | kMaskOverlay;
  if (mode == CameraMode::kCockpit && subject == in.own)
    mask &= ~kMaskOwnVehicle;
  cam->setCullMask(mask);
  // Fog from the eye: a camera far out (orbit) must not sink the world in haze.
  if (auto* fog =
          dynamic_cast<osg::Fog*>(scene_->getStateSet()->getAttribute(osg::StateAttribute::FOG))) {
    const double reach = mode == CameraMode::kOrbit ? in.choice.orbit_distance_m : 0.0;
    fog->setStart(static_cast<float>(250.0 + reach));
    fog->setEnd(static_cast<float>(2000.0 + reach));
  }

  // The rear-view mirror while driving (chase and cockpit), top centre, 3.2:1.
  mirror_shown_ = in.own >= 0 && subject == in.own &&
                  (mode == CameraMode::kChase || mode == CameraMode::kCockpit);
  if (mirror_shown_) {
    const float k = static_cast<float>(height_) / 720.0f;
    const int mw = static_cast<int>(0.3 * width_), mh = static_cast<int>(mw / 3.2);
    mirror_rect_ = {(width_ - mw) / 2, height_ - mh - static_cast<int>(14 * k), mw, mh};
    const CameraPose mp = mirror_rig_.update(sub, in.choice, Viewport{mw, mh}, dt_s);
    mirror_camera_->setViewport(mirror_rect_.x, mirror_rect_.y, mw, mh);
    mirror_camera_->setViewMatrix(mp.view);
    mirror_camera_->setProjectionMatrix(mp.projection);
    mirror_camera_->setNodeMask(~0u);
  } else {
    mirror_camera_->setNodeMask(0);
  }

  overlay_->update(in);
  hud_->update(in, subject, width_, height_, mirror());
  viewer_->frame();
}

void DriverView::capture_next_frame() {
  capture_->arm(width_, height_);
}

std::optional<Image> DriverView::take_capture() {
  return capture_->take();
}

}  // namespace tb::client::view3d
