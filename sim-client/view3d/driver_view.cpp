#include "sim-client/view3d/driver_view.hpp"

#include <algorithm>
#include <cmath>

#include <osg/Fog>
#include <osg/Light>
#include <osg/LightSource>
#include <osg/Material>

#include "sim-client/view3d/junction_marks.hpp"
#include "sim-client/view3d/road_objects_node.hpp"

namespace tb::client::view3d {
namespace {

const osg::Vec4 kSky(0.66f, 0.78f, 0.92f, 1.0f);

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

  // The sun: a directional light from the south-east, 50° up, placed in world coordinates so
  // that the main camera and the mirror light the world alike.
  osg::ref_ptr<osg::Light> sun = new osg::Light(0);
  sun->setPosition(osg::Vec4(0.45f, -0.45f, 0.77f, 0.0f));
  sun->setAmbient(osg::Vec4(0.45f, 0.45f, 0.47f, 1));
  sun->setDiffuse(osg::Vec4(0.72f, 0.72f, 0.68f, 1));
  sun->setSpecular(osg::Vec4(0, 0, 0, 1));
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
