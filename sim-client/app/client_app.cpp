#include "sim-client/app/client_app.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/scenario/channel_range.hpp"

namespace tb::client {
namespace {

constexpr double kInputPollHz = 250.0;

}  // namespace

std::optional<ViewKind> parse_view(std::string_view text) {
  if (text == "3d")
    return ViewKind::k3d;
  if (text == "topdown")
    return ViewKind::kTopdown;
  if (text == "auto")
    return ViewKind::kAuto;
  return std::nullopt;
}

// ASCII only: SDL 2.26 converts a title to the locale's multibyte text for WM_NAME before it
// sets _NET_WM_NAME, and in the C locale (a launcher's environment) a dash beyond ASCII fails
// that conversion, which leaves the title the window was made with.
std::string window_title(const wire::sim::Welcome* welcome, int own) {
  if (welcome == nullptr)
    return "sim-client";
  if (own < 0 || static_cast<std::size_t>(own) >= welcome->vehicles.size())
    return fmt::format("sim-client - watching {}", welcome->server_name);
  const auto& v = welcome->vehicles[static_cast<std::size_t>(own)];
  return fmt::format("{} - station {}", v.id, v.station_id);
}

bool display_available() {
  for (const char* var : {"DISPLAY", "WAYLAND_DISPLAY"}) {
    const char* v = std::getenv(var);
    if (v != nullptr && *v != '\0')
      return true;
  }
  return false;
}

ClientApp::ClientApp(boost::asio::io_context& io, AppOptions options)
    : io_(io), options_(std::move(options)), runtime_(io) {
  std::optional<ControllerMapping> mapping;
  if (options_.mapping)
    mapping = load_mapping(*options_.mapping);
  if (options_.fps <= 0.0 || options_.fps > 1000.0)
    throw std::invalid_argument(fmt::format("--fps {}: must be in (0, 1000]", options_.fps));
  if (options_.width < 64 || options_.height < 64)
    throw std::invalid_argument("--size: the view needs at least 64×64 pixels");

  if (!(options_.fov_deg >= 20.0 && options_.fov_deg <= 160.0))
    throw std::invalid_argument(fmt::format(
        "--fov {}: the horizontal field of view must be in [20, 160] degrees", options_.fov_deg));

  // Which view: none when nothing is to be drawn (headless without a screenshot, --list);
  // else the 3D view where a display is there, the 2D diagram otherwise or when asked.
  const bool window = !options_.headless && !options_.session.list_only;
  const bool draws = window || (options_.screenshot.has_value() && !options_.session.list_only);
  if (draws) {
    view_ = options_.view;
    if (view_ == ViewKind::kAuto)
      view_ = display_available() ? ViewKind::k3d : ViewKind::kTopdown;
    if (view_ == ViewKind::k3d && !display_available())
      throw std::runtime_error(
          "the 3D view needs a display (X11): set DISPLAY, run under xvfb-run, or use "
          "--view topdown");
  }
  // SDL video: the 2D window or the 3D view's GL window (hidden when headless); otherwise the
  // dummy driver, which keeps events (and injected keys) working without a display.
  if (!window && view_ != ViewKind::k3d)
    SDL_SetHint(SDL_HINT_VIDEODRIVER, "dummy");
  else
    SDL_ResetHint(SDL_HINT_VIDEODRIVER);  // a headless app before us in this process set it
  Uint32 flags = SDL_INIT_EVENTS | SDL_INIT_VIDEO;
  if (mapping)
    flags |= SDL_INIT_JOYSTICK | SDL_INIT_GAMECONTROLLER;
  if (SDL_Init(flags) != 0)
    throw std::runtime_error(std::string("cannot initialise SDL: ") + SDL_GetError());
  sdl_ = true;
  if (window) {
    // SDL falls back to its off-screen driver when the display cannot be opened: a window
    // nobody sees, with a car that follows no one's keys.
    const std::string driver =
        SDL_GetCurrentVideoDriver() != nullptr ? SDL_GetCurrentVideoDriver() : "";
    if (driver == "offscreen" || driver == "dummy") {
      const char* d = std::getenv("DISPLAY");
      const char* wl = std::getenv("WAYLAND_DISPLAY");
      throw std::runtime_error(fmt::format(
          "cannot open a window: the display (DISPLAY={}, WAYLAND_DISPLAY={}) does not answer "
          "(SDL fell back to its {} driver); check it, or use --headless",
          d != nullptr ? d : "", wl != nullptr ? wl : "", driver));
    }
  }
  input_ = std::make_unique<SdlInput>(std::move(mapping));
  if (view_ == ViewKind::kTopdown) {
    if (window)
      canvas_ = Canvas::window(options_.width, options_.height, "sim-client");
    else
      canvas_ = Canvas::offscreen(options_.width, options_.height);
    renderer_ =
        std::make_unique<SceneRenderer>(canvas_->renderer(), canvas_->width(), canvas_->height());
  }

  if (options_.mqtt && !options_.session.list_only) {
    const auto [mhost, mport] = split_host_port(*options_.mqtt, 1883);
    monitor_ = std::make_unique<v2x::V2xMonitor>();
    subscriber_ = std::make_unique<v2x::V2xSubscriber>(
        runtime_, *monitor_,
        v2x::SubscriberOptions{mhost, mport, options_.mqtt_user, options_.mqtt_password});
    if (window)
      sound_ = std::make_unique<v2x::WarningSound>();
  }
  if (view_ == ViewKind::k3d)
    start_3d(window);

  if (options_.forward && !options_.session.list_only) {
    sink_ = std::make_unique<UdpSink>(io_, options_.emulator);
    forwarder_ = std::make_unique<StateForwarder>(runtime_, *sink_);
    signal_sink_ = std::make_unique<UdpSink>(io_, signal_feed_address(options_.emulator));
    signal_forwarder_ = std::make_unique<SignalForwarder>(*signal_sink_);
  }
  session_ = std::make_unique<SimSession>(
      options_.session, [this](std::vector<std::uint8_t> b) { link_->send(std::move(b)); },
      forwarder_.get(), trace::global(), &runtime_);
  session_->set_signal_forwarder(signal_forwarder_.get());
  const auto [host, port] = split_host_port(options_.server, 2000);
  link_ = std::make_unique<TcpLink>(io_, runtime_, host, port, *session_);
  if (feed_) {
    session_->set_frame_observer(
        [this](const wire::sim::StateFrame& f) { feed_->push_frame(f, runtime_.steady_now()); });
  }
}

void ClientApp::start_3d(bool window) {
  view3d::ViewChoice initial;
  initial.hfov_deg = options_.fov_deg;
  initial.overlay = monitor_ != nullptr && options_.session.vehicles.empty();
  const bool watching = options_.session.vehicles.empty() && !options_.session.scripted;
  initial.camera =
      options_.camera.value_or(watching ? view3d::CameraMode::kOrbit : view3d::CameraMode::kChase);
  controls_ = view3d::ViewControls(initial);
  // One window, one GL context: SDL makes the window and keeps its events (the input path
  // stays as it was); the render thread makes the context and draws into it.
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  SDL_GL_SetAttribute(SDL_GL_RED_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_GREEN_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_BLUE_SIZE, 8);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_COMPATIBILITY);
  Uint32 wflags = SDL_WINDOW_OPENGL | (window ? SDL_WINDOW_RESIZABLE : SDL_WINDOW_HIDDEN);
  if (window && options_.fullscreen)
    wflags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
  gl_window_ = SDL_CreateWindow("sim-client", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                options_.width, options_.height, wflags);
  if (gl_window_ == nullptr)
    throw std::runtime_error(fmt::format("cannot open the 3D view's window: {}", SDL_GetError()));
  int w = options_.width, h = options_.height;
  SDL_GL_GetDrawableSize(gl_window_, &w, &h);
  feed_ = std::make_unique<view3d::ViewFeed>(monitor_.get());
  view3d::RenderOptions ro;
  ro.width = w;
  ro.height = h;
  ro.fps = options_.fps;
  ro.continuous = window;
  ro.vsync = options_.vsync;
  render_ = std::make_unique<view3d::RenderLoop>(gl_window_, *feed_, ro);
  // Whether a driver saw the warning: the banner's appearance, its severity or case changing,
  // and its disappearance are traced (client.banner) and logged, from the frames the render
  // thread actually drew; not its TTC and distance, which change every frame.
  render_->set_frame_observer([next = options_.frame_observer, shown = std::string(),
                               red_light = std::string(),
                               light = std::string()](const view3d::FrameStats& st) mutable {
    // Likewise the red-light banner (without its countdown and distance) and every change of
    // the signal panel's light: the end of "light change in the sim → state at the driver's
    // HUD" (issue 34's figure).
    const std::string rlvw_headline = st.rlvw_banner.substr(0, st.rlvw_banner.find(" · "));
    if (rlvw_headline != red_light) {
      red_light = rlvw_headline;
      trace::global().record("client.rlvw_banner", {{"text", st.rlvw_banner}, {"frame", st.frame}});
      if (red_light.empty())
        spdlog::info("red-light banner gone");
      else
        spdlog::info("red-light banner: {}", st.rlvw_banner);
    }
    const std::string now_light =
        st.signal ? fmt::format("{}/{}/{}/{}", st.signal->station, st.signal->intersection_id,
                                st.signal->signal_group, v2x::to_string(st.signal->light))
                  : std::string();
    if (now_light != light) {
      light = now_light;
      if (st.signal) {
        trace::global().record("client.signal", {{"station", st.signal->station},
                                                 {"intersection_id", st.signal->intersection_id},
                                                 {"signal_group", st.signal->signal_group},
                                                 {"light", v2x::to_string(st.signal->light)},
                                                 {"frame", st.frame}});
      } else {
        trace::global().record("client.signal", {{"light", ""}, {"frame", st.frame}});
      }
    }
    const std::string headline = st.banner.substr(0, st.banner.find(" · TTC"));
    if (headline != shown) {
      shown = headline;
      trace::global().record("client.banner", {{"text", st.banner}, {"frame", st.frame}});
      if (shown.empty())
        spdlog::info("warning banner gone");
      else
        spdlog::info("warning banner: {}", st.banner);
    }
    if (next)
      next(st);
  });
  render_->start();
}

int ClientApp::own_vehicle() const {
  // The camera follows the first human-driven vehicle, else the first driven one.
  const auto driven = session_->driven();
  for (const auto i : driven)
    if (session_->human_driven(i))
      return i;
  return driven.empty() ? -1 : driven.front();
}

void ClientApp::feed_3d() {
  // The world: rebuilt when the server's vehicles or map change (a new Welcome).
  if (const auto* w = session_->welcome()) {
    auto looks = std::vector<view3d::VehicleLook>();
    looks.reserve(w->vehicles.size());
    for (const auto& v : w->vehicles) {
      view3d::VehicleLook l;
      l.id = v.id;
      l.station_id = v.station_id;
      const SDL_Color c = parse_colour(v.color).value_or(SDL_Color{200, 200, 200, 255});
      l.colour = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f};
      l.length_m = v.length_m;
      l.width_m = v.width_m;
      l.height_m = v.height_m;
      l.wheelbase_m = v.wheelbase_m;
      l.track_m = v.track_m;
      l.wheel_radius_m = v.wheel_radius_m;
      looks.push_back(std::move(l));
    }
    const auto net = session_->shared_network();
    // The scenario came with the Welcome: its channel model gives the range the radio medium
    // enforces, so the operator's view needs nothing more on the wire.
    std::optional<double> range;
    if (const auto* sc = session_->scenario())
      range = scenario::max_range_m(sc->channel);
    if (!world_ || world_->network != net || world_->vehicles != looks ||
        world_->radio_range_m != range) {
      auto world = std::make_shared<view3d::World>();
      world->network = net;
      world->radio_range_m = range;
      world->vehicles = std::move(looks);
      if (const auto* m = session_->map(); m != nullptr && m->origin().origin) {
        try {
          world->frame.emplace(*m->origin().origin);
        } catch (const std::invalid_argument&) {
          // An origin the scenario loader let through but the frame refuses: no DENM marks.
        }
      }
      world->version = world_ ? world_->version + 1 : 1;
      world_ = world;
      feed_->set_world(world_);
      controls_.set_vehicle_count(static_cast<int>(world_->vehicles.size()));
      if (options_.follow && !followed_) {
        followed_ = true;
        const auto& vs = world_->vehicles;
        const auto it = std::find_if(vs.begin(), vs.end(),
                                     [&](const auto& v) { return v.id == *options_.follow; });
        if (it == vs.end()) {
          std::string ids;
          for (const auto& v : vs)
            ids += (ids.empty() ? "" : ", ") + v.id;
          spdlog::error("--follow {}: the scenario has no such vehicle (its vehicles: {})",
                        *options_.follow, ids);
          stop(kExitUsage);
          return;
        }
        controls_.follow(static_cast<int>(it - vs.begin()));
      }
    }
  }
  if (session_->signal_updates() != signals_fed_) {
    signals_fed_ = session_->signal_updates();
    feed_->set_signals(session_->signal_groups());
  }
  const int own = own_vehicle();
  controls_.set_own(own);
  controls_.set_help(input_->help_shown());
  view3d::HudStatus st;
  st.connection = link_->status();
  st.input = input_->status();
  if (subscriber_)
    st.mqtt = subscriber_->status();
  st.watching = own < 0;
  st.finished = finished_;
  feed_->set_view(own, controls_.choice(), st);
}

void ClientApp::check_screenshot() {
  if (!screenshot_pending_)
    return;
  const auto r = render_->screenshot_result();
  if (!r)
    return;
  screenshot_pending_ = false;
  if (!r->empty()) {
    spdlog::error("screenshot: {}", *r);
    stop(1);
    return;
  }
  spdlog::info("screenshot written to {}", *options_.screenshot);
}

ClientApp::~ClientApp() {
  link_.reset();
  render_.reset();
  feed_.reset();
  if (gl_window_ != nullptr)
    SDL_DestroyWindow(gl_window_);
  subscriber_.reset();
  sound_.reset();
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
  if (subscriber_)
    subscriber_->start();
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
  if (subscriber_)
    subscriber_->stop();
  if (sound_)
    sound_->set(v2x::Alarm::kOff);
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
  s.signals = session_->signal_groups();
  const auto* w = session_->welcome();
  const auto* f = session_->latest();
  if (w == nullptr || f == nullptr)
    return s;
  const int own = own_vehicle();
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

void ClientApp::update_title() {
  SDL_Window* w = gl_window_ != nullptr ? gl_window_ : (canvas_ ? canvas_->sdl_window() : nullptr);
  if (w == nullptr)
    return;
  std::string t = window_title(session_->welcome(), own_vehicle());
  if (finished_)
    t += " - scenario finished";
  if (t != title_) {
    title_ = t;
    SDL_SetWindowTitle(w, title_.c_str());
  }
}

void ClientApp::on_finished() {
  if (finished_)
    return;
  finished_ = true;
  const bool window = !options_.headless;
  spdlog::info("the scenario finished{}", window ? "; the window stays until it is closed" : "");
  if (!window && !screenshot_pending_)
    stop(0);
}

void ClientApp::frame() {
  frame_timer_ = 0;
  if (stopped_)
    return;
  const clock::SteadyTime now = runtime_.steady_now();
  const clock::Duration dt = now - last_frame_;
  last_frame_ = now;

  SDL_Event e;
  while (SDL_PollEvent(&e) != 0) {
    input_->handle(e);
    if (render_) {
      controls_.handle(e);
      if (e.type == SDL_WINDOWEVENT && e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED) {
        int w = 0, h = 0;
        SDL_GL_GetDrawableSize(gl_window_, &w, &h);
        render_->resize(w, h);
      }
    }
  }
  // Dated when the controller was read (start of t1, docs/tracing.md).
  session_->set_human_command(input_->update(dt), runtime_.wall_now());
  if (input_->help_shown() && !help_printed_ && options_.headless) {
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
    case SimSession::Phase::kFinished:
      on_finished();
      if (stopped_)
        return;
      break;
    default:
      break;
  }
  update_title();
  if (options_.session.list_only && !link_->connected() &&
      link_->status().find("retry") != std::string::npos) {
    spdlog::error("--list: {}", link_->status());
    stop(1);
    return;
  }

  if (render_) {
    if (const std::string err = render_->error(); !err.empty()) {
      spdlog::error("{}", err);
      stop(1);
      return;
    }
    feed_3d();
    check_screenshot();
    if (stopped_)
      return;
  }
  if (monitor_ && sound_) {
    // The sound lasts as long as the own station's warnings, LCRW and RLVW (none when watching).
    const int own = own_vehicle();
    v2x::Alarm alarm = v2x::Alarm::kOff;
    if (const auto* w = session_->welcome(); w != nullptr && own >= 0) {
      alarm = v2x::alarm_for(monitor_->picture(now),
                             w->vehicles[static_cast<std::size_t>(own)].station_id);
    }
    sound_->set(alarm);
  }

  const double elapsed = std::chrono::duration<double>(now - started_).count();
  if (options_.screenshot && !screenshot_done_ && elapsed >= options_.screenshot_after_s) {
    screenshot_done_ = true;
    if (render_) {
      render_->request_screenshot(*options_.screenshot);
      screenshot_pending_ = true;
    } else {
      take_screenshot();
      if (stopped_)
        return;
    }
  }
  if (canvas_ && canvas_->has_window()) {
    renderer_->draw(scene());
    canvas_->present();
  }
  // --duration and the end of the scenario wait for a screenshot on its way (software
  // rendering can take a while).
  if (finished_ && options_.headless && !screenshot_pending_) {
    stop(0);
    return;
  }
  if (options_.duration_s && elapsed >= *options_.duration_s && !screenshot_pending_) {
    stop(0);
    return;
  }
  // With the 3D view the frames are the render thread's: this loop only reads the input, and
  // does so at 250 Hz, so that a key waits 2 ms on average to be read rather than half a frame.
  const double rate = render_ ? std::max(options_.fps, kInputPollHz) : options_.fps;
  const auto period =
      std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(1.0 / rate));
  frame_timer_ = runtime_.schedule_at(now + period, [this] { frame(); });
}

}  // namespace tb::client
