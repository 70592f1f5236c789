#include "station-host/app/host_status.hpp"

namespace tb::host {

nlohmann::json station_status(const its::station::Station& s,
                              const its::security::SecurityEntity* security) {
  nlohmann::json j;
  j["station_id"] = s.config().station_id;
  j["fix"] = s.position().current().has_value();
  j["cams_sent"] = s.ca().counters().sent;
  j["cams_received"] = s.ca().counters().received;
  j["denms_sent"] = s.den().counters().sent;
  j["denms_received"] = s.den().counters().received;
  const auto& neighbours = s.ldm().neighbours();
  j["neighbours"] = neighbours.size();
  nlohmann::json ids = nlohmann::json::array();
  for (const auto& [id, n] : neighbours)
    ids.push_back(id);
  j["neighbour_ids"] = std::move(ids);
  if (security != nullptr) {
    nlohmann::json v = nlohmann::json::object();
    const auto& counts = security->verifier().counts();
    for (std::size_t i = 0; i < counts.size(); ++i)
      if (counts[i] != 0)
        v[std::string(its::security::to_string(static_cast<its::security::VerifyResult>(i)))] =
            counts[i];
    j["security"] = {{"mode", its::security::to_string(security->mode())},
                     {"verify_policy", its::security::to_string(security->verify_policy())},
                     {"verify", std::move(v)},
                     {"passed_unverified", security->passed_unverified()},
                     {"held", security->held()}};
  }
  return j;
}

void HostStatus::write(std::span<const its::station::Station* const> stations,
                       std::span<const its::security::SecurityEntity* const> security,
                       const DemuxCounters& link, const HostSocketStats& socket,
                       const StateFeed::Counters& states) {
  nlohmann::json j;
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < stations.size(); ++i)
    list.push_back(station_status(*stations[i], i < security.size() ? security[i] : nullptr));
  j["stations"] = std::move(list);
  j["link"] = {{"frames", link.frames},
               {"plain", link.plain},
               {"pooled", link.pooled},
               {"malformed_pooled", link.malformed_pooled},
               {"foreign_receivers", link.foreign_receivers},
               {"not_for_us", link.not_for_us},
               {"deliveries", link.deliveries},
               {"looped_back", link.looped_back},
               {"sent", link.sent},
               {"send_errors", link.send_errors},
               {"wakeups", socket.wakeups},
               {"truncated", socket.truncated},
               {"receive_errors", socket.receive_errors}};
  j["states"] = {{"datagrams", states.datagrams},
                 {"malformed", states.malformed},
                 {"states", states.states},
                 {"other_station", states.other_station}};
  file_.write(j.dump() + "\n");
}

}  // namespace tb::host
