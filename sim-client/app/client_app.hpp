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
#include "sim-client/view/scene.hpp"

namespace tb::client {

/// Exit codes besides 0 (done) and 1 (runtime failure).
inline constexpr int kExitCannotDrive = 3;  ///< unknown vehicle, or none could be attached
inline constexpr int kExitUsage = 64;       ///< bad options or mapping file (EX_USAGE)

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
  int width = 1024, height = 768;
  double fps = 60.0;
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

 private:
  void frame();
  ViewScene scene() const;
  void take_screenshot();

  boost::asio::io_context& io_;
  AppOptions options_;
  clock::AsioRuntime runtime_;
  bool sdl_ = false;
  std::unique_ptr<SdlInput> input_;
  std::unique_ptr<UdpSink> sink_;
  std::unique_ptr<StateForwarder> forwarder_;
  std::unique_ptr<SimSession> session_;
  std::unique_ptr<TcpLink> link_;
  std::unique_ptr<Canvas> canvas_;
  std::unique_ptr<SceneRenderer> renderer_;
  clock::SteadyTime started_{};
  clock::SteadyTime last_frame_{};
  clock::TimerId frame_timer_ = 0;
  bool screenshot_done_ = false;
  bool stopped_ = false;
  int exit_code_ = 0;
  bool help_printed_ = false;
};

}  // namespace tb::client
