#include "its-station/facilities/position.hpp"

namespace tb::its::facilities {

void PositionProvider::publish(const PositionFix& fix) {
  const bool regained = !current_.has_value();
  current_ = fix;
  if (regained) {
    for (auto& l : availability_listeners_)
      l(true);
  }
  for (auto& l : fix_listeners_)
    l(fix);
}

void PositionProvider::publish_loss() {
  if (!current_)
    return;
  current_.reset();
  for (auto& l : availability_listeners_)
    l(false);
}

}  // namespace tb::its::facilities
