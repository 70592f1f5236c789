#pragma once
/// @file The 3D view as one object: an OpenSceneGraph viewer drawing into the GL context that
/// is current on the calling thread (osgViewer::GraphicsWindowEmbedded: the window and its
/// context belong to SDL), with the world, the vehicles, the V2X overlay, the rear-view mirror
/// and the HUD. render() draws one frame from a FrameInput; a screenshot is a final-draw
/// callback on the last camera drawn (the HUD's), not a mode of its own.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <osg/Camera>
#include <osg/Group>
#include <osg/ref_ptr>
#include <osgViewer/Viewer>

#include "sim-client/view3d/cameras.hpp"
#include "sim-client/view3d/frame_input.hpp"
#include "sim-client/view3d/hud.hpp"
#include "sim-client/view3d/overlay.hpp"
#include "sim-client/view3d/road_node.hpp"
#include "sim-client/view3d/signal_heads_node.hpp"
#include "sim-client/view3d/vehicle_node.hpp"

namespace tb::client::view3d {

/// A frame read back: RGBA, rows from the top.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
};

class DriverView {
 public:
  /// The GL context must be current on this thread for as long as the view lives.
  /// @throws std::runtime_error when the fonts are missing.
  DriverView(int width, int height);
  ~DriverView();
  DriverView(const DriverView&) = delete;
  DriverView& operator=(const DriverView&) = delete;

  void resize(int width, int height);
  /// Draws one frame into the current context's back buffer. @p dt_s: time since the last.
  void render(const FrameInput& in, double dt_s);
  /// Reads the next rendered frame back (HUD included).
  void capture_next_frame();
  std::optional<Image> take_capture();

  // What the last frame drew (tests, the frame statistics).
  const CameraPose& pose() const { return pose_; }
  CameraMode camera() const { return mode_; }
  int subject() const { return subject_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// The mirror inset, when the last frame showed it.
  const Rect* mirror() const { return mirror_shown_ ? &mirror_rect_ : nullptr; }
  const Hud& hud() const { return *hud_; }
  const V2xOverlay& overlay() const { return *overlay_; }
  const std::vector<std::unique_ptr<VehicleNode>>& vehicles() const { return vehicles_; }
  const RoadNodeStats& road_stats() const { return road_stats_; }
  /// The traffic lights of the world drawn last; null before a world with a network.
  const SignalHeadsNode* signal_heads() const { return signal_heads_.get(); }

 private:
  class Capture;
  void build_world(const World& w);

  int width_, height_;
  osg::ref_ptr<osgViewer::Viewer> viewer_;
  osg::ref_ptr<osgViewer::GraphicsWindowEmbedded> window_;
  osg::ref_ptr<osg::Group> root_;
  osg::ref_ptr<osg::Group> scene_;  ///< what the main camera and the mirror both draw
  osg::ref_ptr<osg::Group> roads_;
  osg::ref_ptr<osg::Group> cars_;
  osg::ref_ptr<osg::Camera> mirror_camera_;
  osg::ref_ptr<Capture> capture_;
  std::unique_ptr<Hud> hud_;
  std::unique_ptr<V2xOverlay> overlay_;
  std::vector<std::unique_ptr<VehicleNode>> vehicles_;
  std::unique_ptr<SignalHeadsNode> signal_heads_;
  std::array<std::unique_ptr<CameraRig>, kCameraModes> rigs_;
  MirrorCamera mirror_rig_;
  RoadNodeStats road_stats_;
  std::uint64_t world_version_ = 0;
  std::shared_ptr<const World> world_;
  CameraPose pose_;
  CameraMode mode_ = CameraMode::kChase;
  int subject_ = -1;
  bool first_ = true;
  Rect mirror_rect_;
  bool mirror_shown_ = false;
};

}  // namespace tb::client::view3d
