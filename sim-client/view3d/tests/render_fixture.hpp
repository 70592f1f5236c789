#pragma once
/// @file What the 3D view's render tests share: an Xvfb this suite starts with one hidden SDL
/// window and GL context in it (Mesa's llvmpipe), a DriverView per test, frames read back and
/// left in build/…/Testing/Temporary/view3d/ for a person to look at, and the pixel a world
/// point projects to under a camera pose (checks are of colours where the geometry says, not of
/// golden images).

#include <gtest/gtest.h>

#include <SDL.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/tests/xvfb.hpp"

namespace tb::client::view3d {

inline constexpr int kW = 1280, kH = 720;

/// Testing/Temporary/view3d/ of the build (TESTBED_BIN is its bin/).
inline std::filesystem::path log_dir() {
  const char* bin = std::getenv("TESTBED_BIN");
  std::filesystem::path d = std::filesystem::path(bin != nullptr ? bin : "build/bin") / ".." /
                            "Testing" / "Temporary" / "view3d";
  std::filesystem::create_directories(d);
  return d;
}

/// The shipped maps (scenarios/maps under TESTBED_ROOT).
inline std::filesystem::path maps_dir() {
  const char* root = std::getenv("TESTBED_ROOT");
  return std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps";
}

struct Rgb {
  int r, g, b;
};

inline Rgb pixel(const Image& im, int x, int y) {
  const auto* p = &im.rgba[(static_cast<std::size_t>(y) * im.width + x) * 4];
  return {p[0], p[1], p[2]};
}

/// A world point to window pixels (origin top left) under a camera pose.
inline osg::Vec2d project(const CameraPose& pose, const osg::Vec3d& w, int width = kW,
                          int height = kH) {
  const osg::Vec3d n = w * pose.view * pose.projection;
  return {(n.x() + 1.0) / 2.0 * width, (1.0 - n.y()) / 2.0 * height};
}

/// The suite's Xvfb, window and context; a DriverView of kW x kH for each test.
class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    xvfb_ = std::make_unique<testing::Xvfb>();
    if (!xvfb_->running() || SDL_Init(SDL_INIT_VIDEO | SDL_INIT_EVENTS) != 0)
      return;
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    window_ = SDL_CreateWindow("view3d test", 0, 0, kW, kH, SDL_WINDOW_OPENGL | SDL_WINDOW_HIDDEN);
    if (window_ != nullptr)
      context_ = SDL_GL_CreateContext(window_);
  }
  static void TearDownTestSuite() {
    if (context_ != nullptr)
      SDL_GL_DeleteContext(context_);
    if (window_ != nullptr)
      SDL_DestroyWindow(window_);
    context_ = nullptr;
    window_ = nullptr;
    SDL_Quit();
    xvfb_.reset();
  }
  void SetUp() override {
    if (!xvfb_ || !xvfb_->running())
      GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
    ASSERT_NE(context_, nullptr) << SDL_GetError();
    ASSERT_EQ(SDL_GL_MakeCurrent(window_, context_), 0) << SDL_GetError();
    view_ = std::make_unique<DriverView>(kW, kH);
  }
  void TearDown() override { view_.reset(); }

  /// Renders @p in (twice: the second frame is the one read back) and saves it as @p name.
  Image shoot(const FrameInput& in, const std::string& name) {
    view_->render(in, 0.0);
    view_->capture_next_frame();
    view_->render(in, 1.0 / 60);
    auto im = view_->take_capture();
    EXPECT_TRUE(im.has_value());
    if (!im)
      return {};
    EXPECT_EQ(write_png((log_dir() / (name + ".png")).string(), im->width, im->height, im->rgba),
              "");
    return *im;
  }

  static inline std::unique_ptr<testing::Xvfb> xvfb_;
  static inline SDL_Window* window_ = nullptr;
  static inline SDL_GLContext context_ = nullptr;
  std::unique_ptr<DriverView> view_;
};

}  // namespace tb::client::view3d
