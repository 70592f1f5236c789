#pragma once
/// @file One client connection to gpsd through libgps, streaming JSON reports.

#include <memory>
#include <string>

#include "common/util/expected.hpp"
#include "its-station/facilities/gpsd_report.hpp"

namespace tb::its::facilities {

class GpsdSession {
 public:
  /// Connects to gpsd and enables streaming (WATCH_ENABLE | WATCH_JSON).
  /// @returns the session, or a message saying what failed and why.
  static Expected<std::unique_ptr<GpsdSession>, std::string> open(const std::string& host,
                                                                  const std::string& port);
  ~GpsdSession();
  GpsdSession(const GpsdSession&) = delete;
  GpsdSession& operator=(const GpsdSession&) = delete;

  /// The socket, for waiting on readability (the session keeps owning it).
  int fd() const;
  /// True when a report is buffered or the socket is readable; never blocks.
  bool waiting();
  /// Reads one report. @returns false when the connection is broken (reconnect).
  bool read(GpsdReport& out);

 private:
  struct Impl;
  explicit GpsdSession(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace tb::its::facilities
