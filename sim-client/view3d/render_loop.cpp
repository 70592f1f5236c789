#include "sim-client/view3d/render_loop.hpp"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <osg/GL>

#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"

namespace tb::client::view3d {
namespace {

using Clock = std::chrono::steady_clock;

/// The GL context of the calling thread, current until destroyed.
class GlContext {
 public:
  explicit GlContext(SDL_Window* w) : window_(w), ctx_(SDL_GL_CreateContext(w)) {
    if (ctx_ == nullptr)
      throw std::runtime_error(fmt::format("cannot make an OpenGL context: {}", SDL_GetError()));
    if (SDL_GL_MakeCurrent(w, ctx_) != 0) {
      SDL_GL_DeleteContext(ctx_);
      throw std::runtime_error(fmt::format("cannot use the OpenGL context: {}", SDL_GetError()));
    }
  }
  ~GlContext() {
    SDL_GL_MakeCurrent(window_, nullptr);
    SDL_GL_DeleteContext(ctx_);
  }
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

 private:
  SDL_Window* window_;
  SDL_GLContext ctx_;
};

}  // namespace

RenderLoop::RenderLoop(SDL_Window* window, ViewFeed& feed, RenderOptions options)
    : window_(window), feed_(feed), options_(options) {}

RenderLoop::~RenderLoop() {
  stop();
}

void RenderLoop::start() {
  thread_ = std::thread([this] { run(); });
  std::unique_lock lock(mu_);
  wake_.wait(lock, [&] { return ready_ || !error_.empty(); });
  if (!error_.empty()) {
    const std::string why = error_;
    lock.unlock();
    stop();
    throw std::runtime_error(why);
  }
}

void RenderLoop::stop() {
  {
    std::lock_guard lock(mu_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable())
    thread_.join();
}

void RenderLoop::fail(std::string why) {
  std::lock_guard lock(mu_);
  if (error_.empty())
    error_ = std::move(why);
  wake_.notify_all();
}

std::string RenderLoop::error() const {
  std::lock_guard lock(mu_);
  return error_;
}

std::string RenderLoop::renderer() const {
  std::lock_guard lock(mu_);
  return renderer_;
}

void RenderLoop::resize(int width, int height) {
  std::lock_guard lock(mu_);
  new_width_ = width;
  new_height_ = height;
}

void RenderLoop::request_screenshot(std::string path) {
  {
    std::lock_guard lock(mu_);
    screenshot_path_ = std::move(path);
    screenshot_result_.reset();
  }
  wake_.notify_all();
}

std::optional<std::string> RenderLoop::screenshot_result() {
  std::lock_guard lock(mu_);
  return screenshot_result_;
}

void RenderLoop::run() {
  // Linux: the nice value is per thread, and threads started from here inherit it.
  errno = 0;
  const int tid = static_cast<int>(::syscall(SYS_gettid));
  const int nice_now = ::getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
  if (errno == 0 && options_.nice != 0)
    ::setpriority(PRIO_PROCESS, static_cast<id_t>(tid), nice_now + options_.nice);

  std::unique_ptr<GlContext> gl;
  std::unique_ptr<DriverView> view;
  try {
    gl = std::make_unique<GlContext>(window_);
    // Without vsync (or where the driver refuses it) the frame timer below paces the loop.
    SDL_GL_SetSwapInterval(options_.vsync && options_.continuous ? 1 : 0);
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    {
      std::lock_guard lock(mu_);
      renderer_ = name != nullptr ? name : "unknown";
    }
    spdlog::info("3D view: OpenGL {} on {}", version != nullptr ? version : "?",
                 name != nullptr ? name : "?");
    view = std::make_unique<DriverView>(options_.width, options_.height);
  } catch (const std::exception& e) {
    view.reset();
    gl.reset();
    fail(e.what());
    return;
  }
  {
    std::lock_guard lock(mu_);
    ready_ = true;
  }
  wake_.notify_all();

  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(1.0, options_.fps)));
  Clock::time_point next = Clock::now();
  Clock::time_point last{};
  double avg_period = 0.0;
  std::uint64_t frames = 0;
  while (true) {
    std::optional<std::string> shot;
    {
      std::unique_lock lock(mu_);
      const auto due = [&] { return stopping_ || screenshot_path_.has_value(); };
      if (options_.continuous)
        wake_.wait_until(lock, next, due);
      else
        wake_.wait(lock, due);
      if (stopping_)
        break;
      shot = std::move(screenshot_path_);
      screenshot_path_.reset();
      if (new_width_ > 0 && new_height_ > 0) {
        view->resize(new_width_, new_height_);
        new_width_ = new_height_ = 0;
      }
    }
    const auto started = Clock::now();
    const double dt =
        last == Clock::time_point{} ? 0.0 : std::chrono::duration<double>(started - last).count();
    if (last != Clock::time_point{})
      avg_period = avg_period == 0.0 ? dt : 0.9 * avg_period + 0.1 * dt;
    last = started;
    fps_.store(avg_period > 0.0 ? 1.0 / avg_period : 0.0);

    const FrameInput in = feed_.frame_at(started, fps_.load());
    if (shot)
      view->capture_next_frame();
    try {
      view->render(in, dt);
    } catch (const std::exception& e) {
      fail(fmt::format("3D view: {}", e.what()));
      break;
    }
    const auto drawn = Clock::now();
    if (shot) {
      std::string result;
      if (auto im = view->take_capture())
        result = write_png(*shot, im->width, im->height, im->rgba);
      else
        result = fmt::format("{}: the frame could not be read back", *shot);
      std::lock_guard lock(mu_);
      screenshot_result_ = result;
    }
    if (options_.continuous)
      SDL_GL_SwapWindow(window_);
    const auto finished = Clock::now();

    if (observer_) {
      FrameStats st;
      st.frame = ++frames;
      st.started = started;
      st.finished = finished;
      st.render_ms = std::chrono::duration<double, std::milli>(drawn - started).count();
      st.sim_time_ns = in.sim_time_ns;
      st.camera = view->camera();
      st.subject = view->subject();
      if (st.subject >= 0 && static_cast<std::size_t>(st.subject) < in.vehicles.size())
        st.subject_controls = in.vehicles[static_cast<std::size_t>(st.subject)].controls;
      st.banner = view->hud().banner();
      st.rlvw_banner = view->hud().rlvw_banner();
      st.signal = view->hud().signal();
      observer_(st);
    }
    next += period;
    if (next < finished)
      next = finished;  // late: start the next frame now rather than catch up in a burst
  }
  view.reset();
  gl.reset();
}

}  // namespace tb::client::view3d
