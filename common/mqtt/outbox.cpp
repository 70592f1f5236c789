#include "common/mqtt/outbox.hpp"

namespace tb::mqtt {

bool Outbox::push(OutMessage m) {
  bool dropped = false;
  while (q_.size() >= capacity_) {
    q_.pop_front();
    ++dropped_;
    dropped = true;
  }
  q_.push_back(std::move(m));
  return dropped;
}

std::optional<OutMessage> Outbox::pop() {
  if (q_.empty()) {
    return std::nullopt;
  }
  OutMessage m = std::move(q_.front());
  q_.pop_front();
  return m;
}

}  // namespace tb::mqtt
