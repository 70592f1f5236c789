#pragma once
/// @file The view's own keys and mouse (listed with the driving keys in key_map_help()):
/// Tab cycles the cameras, [ and ] pick the car to follow, PgUp/PgDn and the wheel zoom the
/// orbit and top cameras, a left-button drag turns the orbit camera, N toggles the V2X
/// overlay, F1 the frame rate. Pure state: SDL events in, a ViewChoice out.

#include <SDL.h>

#include "sim-client/view3d/frame_input.hpp"

namespace tb::client::view3d {

class ViewControls {
 public:
  explicit ViewControls(ViewChoice initial = {}) : choice_(initial) {}
  /// Returns true when @p e was one of the view's keys or mouse actions.
  bool handle(const SDL_Event& e);
  /// How many vehicles [ and ] cycle through.
  void set_vehicle_count(int n) { vehicles_ = n; }
  void set_help(bool shown) { choice_.help = shown; }
  /// The car this client drives (-1 when watching): the cameras follow it until [ or ] picks
  /// another, and the picking starts from it.
  void set_own(int index) { own_ = index; }
  /// Follow the car of Welcome index @p index, as [ and ] would pick it.
  void follow(int index) { choice_.target = index; }
  const ViewChoice& choice() const { return choice_; }

 private:
  void zoom(double factor);
  ViewChoice choice_;
  int vehicles_ = 0;
  int own_ = -1;
};

}  // namespace tb::client::view3d
