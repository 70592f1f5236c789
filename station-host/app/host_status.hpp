#pragma once
/// @file station-host's --status-file: every pooled station's counters, neighbours and
/// security counts, and the host's link and state-stream counters, written atomically.

#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "common/util/snapshot_file.hpp"

#include "its-station/security/security_entity.hpp"
#include "its-station/station/station.hpp"
#include "station-host/feed/state_feed.hpp"
#include "station-host/link/host_socket.hpp"
#include "station-host/link/pooled_links.hpp"

namespace tb::host {

/// One station's entry: id, fix, CAM and DENM counts, neighbours (count and ids) and, when it
/// signs, its verification outcomes by name. Compact: a host writes hundreds every 0.5 s.
nlohmann::json station_status(const its::station::Station& station,
                              const its::security::SecurityEntity* security);

class HostStatus {
 public:
  explicit HostStatus(std::string path) : file_(std::move(path)) {}
  /// Replaces the file whole (a reader never sees half of it); a failing write is logged.
  void write(std::span<const its::station::Station* const> stations,
             std::span<const its::security::SecurityEntity* const> security,
             const DemuxCounters& link, const HostSocketStats& socket,
             const StateFeed::Counters& states);

 private:
  StatusFileWriter file_;
};

}  // namespace tb::host
