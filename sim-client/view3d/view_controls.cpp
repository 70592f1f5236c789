#include "sim-client/view3d/view_controls.hpp"

#include <algorithm>

namespace tb::client::view3d {

void ViewControls::zoom(double factor) {
  choice_.orbit_distance_m = std::clamp(choice_.orbit_distance_m * factor, 3.0, 2000.0);
  choice_.top_zoom = std::clamp(choice_.top_zoom / factor, 0.05, 20.0);
}

bool ViewControls::handle(const SDL_Event& e) {
  switch (e.type) {
    case SDL_KEYDOWN: {
      const bool repeat = e.key.repeat != 0;
      switch (e.key.keysym.scancode) {
        case SDL_SCANCODE_TAB:
          if (!repeat)
            choice_.camera =
                static_cast<CameraMode>((static_cast<int>(choice_.camera) + 1) % kCameraModes);
          return true;
        case SDL_SCANCODE_LEFTBRACKET:
        case SDL_SCANCODE_RIGHTBRACKET:
          if (vehicles_ > 0) {
            const int step = e.key.keysym.scancode == SDL_SCANCODE_RIGHTBRACKET ? 1 : -1;
            const int from = choice_.target >= 0 && choice_.target < vehicles_ ? choice_.target
                                                                               : std::max(0, own_);
            choice_.target = ((from + step) % vehicles_ + vehicles_) % vehicles_;
          }
          return true;
        case SDL_SCANCODE_PAGEUP:
          zoom(1.0 / 1.25);
          return true;
        case SDL_SCANCODE_PAGEDOWN:
          zoom(1.25);
          return true;
        case SDL_SCANCODE_N:
          if (!repeat)
            choice_.overlay = !choice_.overlay;
          return true;
        case SDL_SCANCODE_F1:
          if (!repeat)
            choice_.show_fps = !choice_.show_fps;
          return true;
        default:
          return false;
      }
    }
    case SDL_MOUSEWHEEL:
      zoom(e.wheel.y > 0 ? 1.0 / 1.15 : (e.wheel.y < 0 ? 1.15 : 1.0));
      return true;
    case SDL_MOUSEMOTION:
      if ((e.motion.state & SDL_BUTTON_LMASK) == 0)
        return false;
      // Dragging right turns the view right: the camera moves the other way round the car.
      choice_.orbit_azimuth_deg -= 0.3 * e.motion.xrel;
      choice_.orbit_elevation_deg =
          std::clamp(choice_.orbit_elevation_deg + 0.3 * e.motion.yrel, 2.0, 89.0);
      return true;
    default:
      return false;
  }
}

}  // namespace tb::client::view3d
