#pragma once
/// @file The render thread. One window, one GL context: SDL made the window (and keeps its
/// events, so the input path and its timing stay as they were); this thread makes the window's
/// GL context, draws the DriverView into it at the display rate and swaps. The program's
/// thread never waits for a frame: a slow software renderer cannot delay the controls sent to
/// the server (t1) or the states forwarded to the emulator (t2). The thread runs at a lower
/// priority (nice +5, inherited by the renderer's own worker threads, as llvmpipe's) so that
/// on a loaded machine the program's thread is served first.

#include <SDL.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common/clock/clock.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-client/v2x/signal_panel.hpp"
#include "sim-client/view3d/feed.hpp"

namespace tb::client::view3d {

struct RenderOptions {
  int width = 1280, height = 720;
  double fps = 60.0;       ///< at most this many frames a second
  bool continuous = true;  ///< draw and swap every frame (a window); false: only screenshots
  bool vsync = true;       ///< swap on the display's refresh (where the driver offers it)
  int nice = 5;            ///< added to the render thread's nice value
};

/// One drawn frame, for the frame-rate line, benchmarks and tests.
struct FrameStats {
  std::uint64_t frame = 0;
  clock::SteadyTime started{};   ///< when the frame's input was sampled
  clock::SteadyTime finished{};  ///< after the swap (the frame is on its way to the screen)
  double render_ms = 0.0;        ///< scene update and draw, without the swap
  std::int64_t sim_time_ns = 0;  ///< the instant drawn
  CameraMode camera = CameraMode::kChase;
  int subject = -1;
  wire::Controls subject_controls;  ///< as drawn (the HUD's bars)
  std::string banner;               ///< the V2X warning banner's text; empty: none shown
  std::string rlvw_banner;          ///< the red-light warning banner's text; empty: none shown
  /// The signal panel as drawn; empty: none.
  std::optional<v2x::SignalPanel> signal;
};

class RenderLoop {
 public:
  using FrameObserver = std::function<void(const FrameStats&)>;

  RenderLoop(SDL_Window* window, ViewFeed& feed, RenderOptions options);
  ~RenderLoop();
  RenderLoop(const RenderLoop&) = delete;
  RenderLoop& operator=(const RenderLoop&) = delete;

  /// Starts the thread and waits until it has made the GL context and the scene.
  /// @throws std::runtime_error with the reason when either fails.
  void start();
  void stop();

  void resize(int width, int height);
  /// Writes the next frame as a PNG to @p path; screenshot_result() says when it is done.
  void request_screenshot(std::string path);
  /// nullopt while pending (or none asked); then "" on success or the error.
  std::optional<std::string> screenshot_result();
  /// Why the render thread stopped, empty while it runs.
  std::string error() const;
  double fps() const { return fps_.load(); }
  /// The OpenGL renderer's name (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  std::string renderer() const;
  /// Called in the render thread after every frame; set before start().
  void set_frame_observer(FrameObserver f) { observer_ = std::move(f); }

 private:
  void run();
  void fail(std::string why);

  SDL_Window* window_;
  ViewFeed& feed_;
  RenderOptions options_;
  FrameObserver observer_;
  std::thread thread_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  bool ready_ = false;
  bool stopping_ = false;
  std::string error_;
  std::string renderer_;
  std::optional<std::string> screenshot_path_;
  std::optional<std::string> screenshot_result_;
  int new_width_ = 0, new_height_ = 0;
  std::atomic<double> fps_{0.0};
};

}  // namespace tb::client::view3d
