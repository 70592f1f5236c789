#pragma once
/// @file PositionProvider fed by the station's gpsd, event-driven on the io_context.

#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "common/clock/runtime.hpp"
#include "its-station/facilities/gpsd_report.hpp"
#include "its-station/facilities/gpsd_session.hpp"
#include "its-station/facilities/position.hpp"

namespace tb::its::facilities {

/// Waits on gpsd's socket with Asio and hands every TPV with a fix to the listeners at once.
/// A broken connection (or none yet) is retried with exponential backoff; a fix that gets no
/// newer TPV within the stale timeout counts as lost, so a dead gpsd stops the CAMs.
class GpsdPositionProvider final : public PositionProvider {
 public:
  struct Config {
    std::string host = "127.0.0.1";
    std::string port = "2947";
    clock::Duration stale_after = std::chrono::seconds{2};
    clock::Duration first_retry = std::chrono::milliseconds{200};
    clock::Duration max_retry = std::chrono::seconds{5};
  };

  GpsdPositionProvider(boost::asio::io_context& io, clock::Runtime& runtime, Config config);
  ~GpsdPositionProvider() override;

  /// Connects (or starts retrying). @returns false and the reason in @p error when the first
  /// attempt failed; the provider keeps retrying in the background either way.
  bool start(std::string* error = nullptr);
  void stop();

  bool connected() const { return session_ != nullptr; }
  std::uint64_t reports() const { return reports_; }
  std::uint64_t reconnects() const { return reconnects_; }

 private:
  bool connect(std::string* error);
  void arm_read();
  void drain();
  void disconnect_and_retry(const std::string& why);
  void schedule_retry();
  void rearm_stale_timer();

  boost::asio::io_context& io_;
  clock::Runtime& runtime_;
  Config config_;
  std::unique_ptr<GpsdSession> session_;
  std::unique_ptr<boost::asio::posix::stream_descriptor> socket_;
  FixAssembler assembler_;
  clock::Duration retry_delay_;
  clock::TimerId retry_timer_ = 0;
  clock::TimerId stale_timer_ = 0;
  bool stopped_ = false;
  bool warned_unreachable_ = false;
  std::uint64_t reports_ = 0;
  std::uint64_t reconnects_ = 0;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace tb::its::facilities
