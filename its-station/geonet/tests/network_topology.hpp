#pragma once
// An in-memory radio medium connecting several routers, for multi-hop tests without sockets.
// All routers share one ManualRuntime; frames sent during a step are delivered after it to every
// station in range (or explicitly linked), unicast frames only to their addressee.

#include <deque>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"

namespace tb::its::geonet::testing {

class NetworkTopology {
 public:
  struct Received {
    DataIndication indication;
    Bytes payload;
  };
  struct Station {
    std::uint8_t id;
    GeoPoint where;
    std::unique_ptr<link::TestLink> link;
    StaticPositionProvider position;
    std::unique_ptr<Router> router;
    std::vector<Received> received;
    std::vector<DropEvent> drops;
    std::size_t dropped(DropReason r) const {
      std::size_t n = 0;
      for (const auto& d : drops)
        n += d.reason == r;
      return n;
    }
  };

  explicit NetworkTopology(double range_m) : range_m_(range_m) {}

  Station& add_station(std::uint8_t id, const GeoPoint& where, RouterConfig config = {}) {
    auto& s = stations_[id];
    s.id = id;
    s.where = where;
    s.link = std::make_unique<link::TestLink>(mac(id));
    s.link->keeps_sent_frames = false;
    s.link->set_send_observer([this, id](const link::TestLink::SentFrame& f) {
      pending_.push_back({id, f});
      ++frames_sent_;
    });
    refresh_position(s);
    s.router = std::make_unique<Router>(runtime_, *s.link, s.position, config);
    s.router->set_indication_handler([&s](const DataIndication& ind, auto payload) {
      s.received.push_back({ind, Bytes(payload.begin(), payload.end())});
    });
    s.router->set_drop_hook([&s](const DropEvent& e) { s.drops.push_back(e); });
    return s;
  }

  Station& station(std::uint8_t id) { return stations_.at(id); }
  clock::ManualRuntime& runtime() { return runtime_; }
  std::size_t frames_sent() const { return frames_sent_; }

  /// Cuts (or restores) the radio link between two stations regardless of range.
  void set_blocked(std::uint8_t a, std::uint8_t b, bool blocked) {
    if (blocked) {
      blocked_.insert({a, b});
      blocked_.insert({b, a});
    } else {
      blocked_.erase({a, b});
      blocked_.erase({b, a});
    }
  }

  bool reachable(std::uint8_t from, std::uint8_t to) const {
    if (from == to || blocked_.count({from, to}))
      return false;
    return distance_m(stations_.at(from).where, stations_.at(to).where) <= range_m_;
  }

  /// Moves time in @p step increments; every station gets a fresh fix (a 100 Hz receiver) and
  /// the frames sent in a step reach their receivers at its end.
  void advance_time(clock::Duration d, clock::Duration step = std::chrono::milliseconds{10}) {
    const auto end = runtime_.steady_now() + d;
    while (runtime_.steady_now() < end) {
      runtime_.advance(std::min<clock::Duration>(step, end - runtime_.steady_now()));
      for (auto& [id, s] : stations_)
        refresh_position(s);
      dispatch();
    }
  }

  /// Delivers queued frames, and the frames their delivery makes, until the medium is quiet.
  void dispatch() {
    while (!pending_.empty()) {
      auto [from, frame] = std::move(pending_.front());
      pending_.pop_front();
      for (auto& [id, s] : stations_) {
        if (!reachable(from, id))
          continue;
        if (frame.destination != link::kBroadcastMac && frame.destination != mac(id))
          continue;
        s.link->inject(mac(from), frame.destination, frame.ethertype, frame.payload,
                       runtime_.wall_now());
      }
    }
  }

 private:
  void refresh_position(Station& s) {
    s.position.set(
        {runtime_.wall_now(), s.where.latitude_deg, s.where.longitude_deg, 0.0, 0.0, true});
  }

  double range_m_;
  clock::ManualRuntime runtime_;
  std::map<std::uint8_t, Station> stations_;
  std::deque<std::pair<std::uint8_t, link::TestLink::SentFrame>> pending_;
  std::set<std::pair<std::uint8_t, std::uint8_t>> blocked_;
  std::size_t frames_sent_ = 0;
};

}  // namespace tb::its::geonet::testing
