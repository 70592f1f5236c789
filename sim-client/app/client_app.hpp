#pragma once
/// @file The sim-client program as a class: wires input, the sim-server session, state
/// forwarding and the view to an Asio event loop. main() only parses the command line.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "common/clock/asio_runtime.hpp"
#include "sim-client/input/sdl_input.hpp"
#include "sim-client/net/forwarder.hpp"
#include "sim-client/net/session.hpp"
#include "sim-client/net/tcp_link.hpp"
#include "sim-client/v2x/monitor.hpp"
#include "sim-client/v2x/subscriber.hpp"
#include "sim-client/v2x/warning_sound.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/feed.hpp"
#include "sim-client/view3d/render_loop.hpp"
#include "sim-client/view3d/view_controls.hpp"

namespace tb::client {

/// Exit codes besides 0 (done) and 1 (runtime failure).
inline constexpr int kExitCannotDrive = 3;  ///< unknown vehicle, or none could be attached
inline constexpr int kExitUsage = 64;       ///< bad options or mapping file (EX_USAGE)

/// Which view draws: the 3D view (OpenSceneGraph) or the 2D top-down diagram (SDL renderer).
enum class ViewKind { kAuto, k3d, kTopdown };
/// "3d", "topdown"; kAuto: 3D when a display is there, else top-down.
std::optional<ViewKind> parse_view(std::string_view text);
/// Whether an X11 (or Wayland) display is there to open windows on.
bool display_available();

struct AppOptions {
  std::string server = "127.0.0.1:2000";  ///< HOST[:PORT]
  std::string emulator = "127.0.0.1:4700";
  bool forward = true;
  SessionOptions session;
  std::optional<std::string> mapping;  ///< controller mapping file
  bool headless = false;
  std::optional<std::string> screenshot;
  double screenshot_after_s = 1.0;
  std::optional<double> duration_s;  ///< quit after this long (tests, demos)
  int width = 1280, height = 720;
  double fps = 60.0;
  ViewKind view = ViewKind::kAuto;
  std::optional<view3d::CameraMode> camera;  ///< default chase; orbit when watching
  /// The 3D view's car at start (scenario id), as if picked with [ ]: a watcher sees its HUD
  /// (signal panel, warnings), which measurements of a scripted car's HUD need.
  std::optional<std::string> follow;
  double fov_deg = 90.0;  ///< horizontal field of view, 3D view
  bool fullscreen = false;
  bool vsync = true;
  std::optional<std::string> mqtt;  ///< HOST[:PORT] of the broker, read as mqtt_user
  std::string mqtt_user = "hmi";
  std::string mqtt_password = "hmi";
  /// Called in the render thread after every 3D frame (benchmarks, tests).
  view3d::RenderLoop::FrameObserver frame_observer;
};

class ClientApp {
 public:
  /// @throws MappingError, std::invalid_argument, std::runtime_error for unusable options.
  ClientApp(boost::asio::io_context& io, AppOptions options);
  ~ClientApp();

  /// Starts connecting and the frame loop; the io_context's run() then drives everything.
  void start();
  void stop(int exit_code);
  bool stopped() const { return stopped_; }
  int exit_code() const { return exit_code_; }
  /// Runs the io_context until stop(); returns the exit code.
  int run();

  const SimSession& session() const { return *session_; }
  const SdlInput& input() const { return *input_; }
  /// The view that draws (k3d or kTopdown; kAuto only before the constructor decided).
  ViewKind view() const { return view_; }
  /// The 3D view's render thread; null with the top-down view or no view at all.
  view3d::RenderLoop* render_loop() const { return render_.get(); }
  const view3d::ViewControls& view_controls() const { return controls_; }
  const v2x::V2xMonitor* v2x() const { return monitor_.get(); }

 private:
  void frame();
  ViewScene scene() const;
  int own_vehicle() const;
  void take_screenshot();
  void start_3d(bool window);
  void feed_3d();
  void check_screenshot();
  void update_title();
  /// The scenario finished: a window says so and waits to be closed; without one, exits 0.
  void on_finished();

  boost::asio::io_context& io_;
  AppOptions options_;
  clock::AsioRuntime runtime_;
  bool sdl_ = false;
  std::unique_ptr<SdlInput> input_;
  std::unique_ptr<UdpSink> sink_;
  std::unique_ptr<StateForwarder> forwarder_;
  std::unique_ptr<UdpSink> signal_sink_;  ///< the emulator's state port + 1 (issue 34)
  std::unique_ptr<SignalForwarder> signal_forwarder_;
  std::unique_ptr<SimSession> session_;
  std::unique_ptr<TcpLink> link_;
  std::unique_ptr<Canvas> canvas_;
  std::unique_ptr<SceneRenderer> renderer_;
  ViewKind view_ = ViewKind::kAuto;
  SDL_Window* gl_window_ = nullptr;
  std::unique_ptr<v2x::V2xMonitor> monitor_;
  std::unique_ptr<v2x::V2xSubscriber> subscriber_;
  std::unique_ptr<v2x::WarningSound> sound_;
  std::unique_ptr<view3d::ViewFeed> feed_;
  std::unique_ptr<view3d::RenderLoop> render_;
  view3d::ViewControls controls_;
  std::shared_ptr<const view3d::World> world_;
  std::uint64_t signals_fed_ = 0;  ///< the session's signal_updates() last handed to the view
  bool screenshot_pending_ = false;
  clock::SteadyTime started_{};
  clock::SteadyTime last_frame_{};
  clock::TimerId frame_timer_ = 0;
  bool screenshot_done_ = false;
  bool stopped_ = false;
  int exit_code_ = 0;
  bool help_printed_ = false;
  std::string title_;
  bool finished_ = false;
  bool followed_ = false;  ///< --follow resolved against the first Welcome
};

/// The window's title for the vehicles it drives: "red - station 101" (the first human-driven
/// one, else the first driven), "watching" when it drives none, before a Welcome "sim-client".
std::string window_title(const wire::sim::Welcome* welcome, int own);

}  // namespace tb::client
