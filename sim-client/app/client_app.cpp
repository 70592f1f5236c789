#include "sim-client/app/client_app.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tb::client {

ClientApp::ClientApp(boost::asio::io_context& io, AppOptions options)
    : io_(io), options_(std::move(options)), runtime_(io) {
  std::optional<ControllerMapping> mapping;
  if (options_.mapping)
    mapping = load_mapping(*options_.mapping);
  if (options_.fps <= 0.0 || options_.fps > 1000.0)
    throw std::invalid_argument(fmt::format("--fps {}: must be in (0, 1000]", options_.fps));
  if (options_.width < 64 || options_.height < 64)
    throw std::invalid_argument("--size: the view needs at least 64×64 pixels");

  // The window needs video; the dummy driver keeps events (and injected keys) working without.
  const bool window = !options_.headless && !options_.session.list_only;
  if (!window)
    SDL_SetHint(SDL_HINT_VIDEODRIVER, "dummy");
  Uint32 flags = SDL_INIT_EVENTS | SDL_INIT_VIDEO;
  if (mapping)
    flags |= SDL_INIT_JOYSTICK | SDL_INIT_GAMECONTROLLER;
  if (SDL_Init(flags) != 0)
    throw std::runtime_error(std::string("cannot initialise SDL: ") + SDL_GetError());
  sdl_ = true;
  input_ = std::make_unique<SdlInput>(std::move(mapping));
  if (window)
    canvas_ = Canvas::window(options_.width, options_.height, "sim-client");
  else if (options_.screenshot)
    canvas_ = Canvas::offscreen(options_.width, options_.height);
  if (canvas_)
    renderer_ =
        std::make_unique<SceneRenderer>(canvas_->renderer(), canvas_->width(), canvas_->height());

  if (options_.forward && !options_.session.list_only) {
    sink_ = std::make_unique<UdpSink>(io_, options_.emulator);
    forwarder_ = std::make_unique<StateForwarder>(runtime_, *sink_);
  }
  session_ = std::make_unique<SimSession>(
      options_.session, [this](std::vector<std::uint8_t> b) { link_->send(std::move(b)); },
      forwarder_.get(), trace::global(), &runtime_);
  const auto [host, port] = split_host_port(options_.server, 2000);
  link_ = std::make_unique<TcpLink>(io_, runtime_, host, port, *session_);
}

ClientApp::~ClientApp() {
  link_.reset();
  renderer_.reset();
  canvas_.reset();
  input_.reset();
  if (sdl_)
    SDL_Quit();
}

void ClientApp::start() {
  started_ = runtime_.steady_now();
  last_frame_ = started_;
  input_->scan();
  link_->start();
  frame_timer_ = runtime_.schedule_in(clock::Duration(0), [this] { frame(); });
}

void ClientApp::stop(int code) {
  if (stopped_)
    return;
  stopped_ = true;
  exit_code_ = code;
  if (frame_timer_ != 0)
    runtime_.cancel(frame_timer_);
  frame_timer_ = 0;
  link_->stop();
}

int ClientApp::run() {
  start();
  while (!stopped_ && !io_.stopped())
    io_.run_one();
  return exit_code_;
}

ViewScene ClientApp::scene() const {
  ViewScene s;
  s.network = session_->network();
  s.connection = link_->status();
  s.input = input_->status();
  s.help = input_->help_shown();
  const auto* w = session_->welcome();
  const auto* f = session_->latest();
  if (w == nullptr || f == nullptr)
    return s;
  const auto driven = session_->driven();
  // The camera follows the first human-driven vehicle, else the first driven one.
  int own = -1;
  for (const auto i : driven) {
    if (session_->human_driven(i)) {
      own = i;
      break;
    }
  }
  if (own < 0 && !driven.empty())
    own = driven.front();
  for (std::size_t i = 0; i < f->vehicles.size() && i < w->vehicles.size(); ++i) {
    ViewVehicle v;
    v.state = f->vehicles[i];
    v.length_m = w->vehicles[i].length_m;
    v.width_m = w->vehicles[i].width_m;
    v.color = parse_colour(w->vehicles[i].color).value_or(SDL_Color{200, 200, 200, 255});
    v.own = static_cast<int>(i) == own;
    s.vehicles.push_back(v);
  }
  return s;
}

void ClientApp::take_screenshot() {
  renderer_->draw(scene());
  const auto px = canvas_->read_rgba();
  const std::string err = write_png(*options_.screenshot, canvas_->width(), canvas_->height(), px);
  if (!err.empty()) {
    spdlog::error("screenshot: {}", err);
    stop(1);
    return;
  }
  spdlog::info("screenshot written to {}", *options_.screenshot);
}

void ClientApp::frame() {
  frame_timer_ = 0;
  if (stopped_)
    return;
  const clock::SteadyTime now = runtime_.steady_now();
  const clock::Duration dt = now - last_frame_;
  last_frame_ = now;

  SDL_Event e;
  while (SDL_PollEvent(&e) != 0)
    input_->handle(e);
  // Dated when the controller was read (start of t1, docs/tracing.md).
  session_->set_human_command(input_->update(dt), runtime_.wall_now());
  if (input_->help_shown() && !help_printed_ && !canvas_) {
    for (const auto& k : key_map_help())
      fmt::print("{:<18} {}\n", k.keys, k.action);
  }
  help_printed_ = input_->help_shown();
  if (input_->quit_requested()) {
    spdlog::info("quit");
    stop(0);
    return;
  }

  switch (session_->phase()) {
    case SimSession::Phase::kListed:
      fmt::print("{}", format_vehicle_list(*session_->welcome()));
      stop(0);
      return;
    case SimSession::Phase::kFailed:
      spdlog::error("{}", session_->fatal_error());
      stop(kExitCannotDrive);
      return;
    default:
      break;
  }
  if (options_.session.list_only && !link_->connected() &&
      link_->status().find("retry") != std::string::npos) {
    spdlog::error("--list: {}", link_->status());
    stop(1);
    return;
  }

  const double elapsed = std::chrono::duration<double>(now - started_).count();
  if (options_.screenshot && !screenshot_done_ && elapsed >= options_.screenshot_after_s) {
    screenshot_done_ = true;
    take_screenshot();
    if (stopped_)
      return;
  }
  if (canvas_ && canvas_->has_window()) {
    renderer_->draw(scene());
    canvas_->present();
  }
  if (options_.duration_s && elapsed >= *options_.duration_s) {
    stop(0);
    return;
  }
  const auto period = std::chrono::duration_cast<clock::Duration>(
      std::chrono::duration<double>(1.0 / options_.fps));
  frame_timer_ = runtime_.schedule_at(now + period, [this] { frame(); });
}

}  // namespace tb::client
