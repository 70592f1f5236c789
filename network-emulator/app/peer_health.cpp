#include "network-emulator/app/peer_health.hpp"

namespace tb::emu {

bool PeerHealth::is_transient(std::error_code ec) {
  return ec == std::errc::operation_would_block ||
         ec == std::errc::resource_unavailable_try_again || ec == std::errc::no_buffer_space ||
         ec == std::errc::interrupted;
}

bool PeerHealth::should_send() {
  if (state_ == State::kPaused) {
    if (clock_.steady_now() < retry_at_) {
      ++skipped_;
      return false;
    }
    state_ = State::kProbing;
    probe_successes_ = 0;
  }
  return true;
}

PeerHealth::Change PeerHealth::record(std::error_code ec) {
  if (!ec) {
    if (state_ == State::kProbing && ++probe_successes_ >= 2) {
      state_ = State::kHealthy;
      return Change::kResumed;
    }
    return Change::kNone;
  }
  if (is_transient(ec))
    return Change::kNone;
  last_error_ = ec;
  const bool was_healthy = state_ == State::kHealthy;
  state_ = State::kPaused;
  retry_at_ = clock_.steady_now() + retry_;
  return was_healthy ? Change::kPaused : Change::kNone;
}

}  // namespace tb::emu
