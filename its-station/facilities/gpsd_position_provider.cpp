#include "its-station/facilities/gpsd_position_provider.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

namespace tb::its::facilities {

GpsdPositionProvider::GpsdPositionProvider(boost::asio::io_context& io, clock::Runtime& runtime,
                                           Config config)
    : io_(io), runtime_(runtime), config_(std::move(config)), retry_delay_(config_.first_retry) {}

GpsdPositionProvider::~GpsdPositionProvider() {
  *alive_ = false;
  stop();
}

bool GpsdPositionProvider::start(std::string* error) {
  stopped_ = false;
  if (connect(error))
    return true;
  schedule_retry();
  return false;
}

void GpsdPositionProvider::stop() {
  stopped_ = true;
  runtime_.cancel(retry_timer_);
  runtime_.cancel(stale_timer_);
  if (socket_) {
    // The descriptor belongs to libgps, which closes it in gps_close.
    socket_->release();
    socket_.reset();
  }
  session_.reset();
}

bool GpsdPositionProvider::connect(std::string* error) {
  auto s = GpsdSession::open(config_.host, config_.port);
  if (!s) {
    if (error)
      *error = s.error();
    if (!warned_unreachable_) {
      spdlog::warn("gpsd: {}; retrying in the background", s.error());
      warned_unreachable_ = true;
    }
    return false;
  }
  session_ = std::move(*s);
  socket_ = std::make_unique<boost::asio::posix::stream_descriptor>(io_, session_->fd());
  retry_delay_ = config_.first_retry;
  warned_unreachable_ = false;
  spdlog::info("gpsd: connected to {}:{}", config_.host, config_.port);
  arm_read();
  return true;
}

void GpsdPositionProvider::arm_read() {
  socket_->async_wait(boost::asio::posix::stream_descriptor::wait_read,
                      [this, alive = alive_](const boost::system::error_code& ec) {
                        if (!*alive || ec == boost::asio::error::operation_aborted || stopped_)
                          return;
                        if (ec) {
                          disconnect_and_retry(ec.message());
                          return;
                        }
                        drain();
                      });
}

void GpsdPositionProvider::drain() {
  // gps_read takes one JSON object at a time; a datagram from gpsd may carry several.
  do {
    GpsdReport report;
    if (!session_->read(report)) {
      disconnect_and_retry("connection lost");
      return;
    }
    ++reports_;
    PositionFix fix;
    switch (assembler_.on_report(report, runtime_.steady_now(), fix)) {
      case FixAssembler::Outcome::kFix:
        rearm_stale_timer();
        publish(fix);
        break;
      case FixAssembler::Outcome::kLoss:
        runtime_.cancel(stale_timer_);
        publish_loss();
        break;
      case FixAssembler::Outcome::kNone:
        break;
    }
    if (!session_)  // a listener stopped us
      return;
  } while (session_->waiting());
  arm_read();
}

void GpsdPositionProvider::disconnect_and_retry(const std::string& why) {
  spdlog::warn("gpsd: {}: {}; reconnecting", config_.host + ":" + config_.port, why);
  if (socket_) {
    socket_->cancel();
    socket_->release();
    socket_.reset();
  }
  session_.reset();
  runtime_.cancel(stale_timer_);
  publish_loss();
  ++reconnects_;
  schedule_retry();
}

void GpsdPositionProvider::schedule_retry() {
  if (stopped_)
    return;
  runtime_.cancel(retry_timer_);
  retry_timer_ = runtime_.schedule_in(retry_delay_, [this, alive = alive_] {
    if (!*alive || stopped_)
      return;
    if (!connect(nullptr))
      schedule_retry();
  });
  retry_delay_ = std::min<clock::Duration>(retry_delay_ * 2, config_.max_retry);
}

void GpsdPositionProvider::rearm_stale_timer() {
  runtime_.cancel(stale_timer_);
  stale_timer_ = runtime_.schedule_in(config_.stale_after, [this, alive = alive_] {
    if (!*alive)
      return;
    if (current())
      spdlog::warn(
          "gpsd: no report for {} ms; fix considered lost",
          std::chrono::duration_cast<std::chrono::milliseconds>(config_.stale_after).count());
    publish_loss();
  });
}

}  // namespace tb::its::facilities
