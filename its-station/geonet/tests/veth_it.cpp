// Two routers on the real AF_PACKET link: two network namespaces joined by a veth pair whose
// ends are both named wlan0, as the radio stand-in gives each station. One process opens each
// station's packet socket inside its namespace (setns on this thread, then back); the sockets
// stay bound to their namespaces, and one io_context drives both stations.

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>

#include <boost/asio/io_context.hpp>

#include "common/clock/asio_runtime.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/packet_socket_link.hpp"

namespace tb::its {
namespace {

using namespace std::chrono_literals;
using geonet::testing::at;
using Bytes = std::vector<std::uint8_t>;

int run(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

class Netns {
 public:
  explicit Netns(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  /// Runs @p fn with this thread in the namespace.
  void enter(const std::function<void()>& fn) const {
    const int self = ::open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
    const int target = ::open(("/run/netns/" + name_).c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(self, 0);
    ASSERT_GE(target, 0) << "no namespace " << name_;
    ASSERT_EQ(::setns(target, CLONE_NEWNET), 0) << std::strerror(errno);
    fn();
    EXPECT_EQ(::setns(self, CLONE_NEWNET), 0);
    ::close(target);
    ::close(self);
  }

 private:
  std::string name_;
};

class VethPair : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0)
      GTEST_SKIP() << "needs root to create network namespaces";
    const std::string id = std::to_string(::getpid());
    a_ = std::make_unique<Netns>("gnA" + id);
    b_ = std::make_unique<Netns>("gnB" + id);
    cleanup();
    ASSERT_EQ(run("ip netns add " + a_->name()), 0);
    ASSERT_EQ(run("ip netns add " + b_->name()), 0);
    ASSERT_EQ(run("ip link add gna" + id + " type veth peer name gnb" + id), 0);
    ASSERT_EQ(run("ip link set gna" + id + " netns " + a_->name()), 0);
    ASSERT_EQ(run("ip link set gnb" + id + " netns " + b_->name()), 0);
    ASSERT_EQ(run("ip -n " + a_->name() + " link set gna" + id + " name wlan0 up"), 0);
    ASSERT_EQ(run("ip -n " + b_->name() + " link set gnb" + id + " name wlan0 up"), 0);
  }
  void TearDown() override { cleanup(); }
  void cleanup() {
    // Deleting a namespace destroys the veth end inside it, and with it the pair.
    if (a_)
      run("ip netns del " + a_->name());
    if (b_)
      run("ip netns del " + b_->name());
  }
  std::unique_ptr<link::PacketSocketLink> open_in(const Netns& ns) {
    std::unique_ptr<link::PacketSocketLink> out;
    ns.enter([&] {
      auto l = link::PacketSocketLink::open(io, "wlan0");
      ASSERT_TRUE(l) << l.error().message();
      out = std::move(*l);
    });
    return out;
  }
  /// Runs the io_context until @p done or 5 s pass.
  bool run_until(const std::function<bool()>& done) {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!done() && std::chrono::steady_clock::now() < deadline)
      io.run_for(5ms);
    return done();
  }

  std::unique_ptr<Netns> a_, b_;
  boost::asio::io_context io;
};

void set_fix(geonet::StaticPositionProvider& p, const clock::Runtime& rt, geonet::GeoPoint g) {
  p.set({rt.wall_now(), g.latitude_deg, g.longitude_deg, 5.0, 45.0, true});
}

TEST_F(VethPair, TwoStationsExchangeBeaconsShbAndGbcOverAfPacket) {
  auto link_a = open_in(*a_);
  auto link_b = open_in(*b_);
  ASSERT_TRUE(link_a && link_b);
  EXPECT_NE(link_a->address(), link_b->address());
  EXPECT_EQ(link_a->driver(), "veth");
  EXPECT_EQ(link_a->interface(), "wlan0");

  clock::AsioRuntime rt{io};
  geonet::StaticPositionProvider pos_a, pos_b;
  set_fix(pos_a, rt, at(0, 0));
  set_fix(pos_b, rt, at(60, 0));
  geonet::RouterConfig fast;
  fast.beacon_interval = 100ms;
  fast.beacon_max_jitter = 20ms;
  geonet::Router router_a{rt, *link_a, pos_a, fast}, router_b{rt, *link_b, pos_b, fast};
  btp::Dispatcher btp_a{router_a}, btp_b{router_b};

  // Beacons over the wire teach each router its neighbour.
  ASSERT_TRUE(run_until([&] {
    return router_b.location_table().find(router_a.address().mid_key(), rt.steady_now()) &&
           router_a.location_table().find(router_b.address().mid_key(), rt.steady_now());
  }));
  EXPECT_GT(router_a.stats().beacons_sent, 0u);

  std::vector<Bytes> cams;
  geonet::DataIndication cam_gn;
  btp_b.register_port(btp::kPortCam, [&](const btp::Indication& i, auto payload) {
    cams.emplace_back(payload.begin(), payload.end());
    cam_gn = *i.gn;
  });
  const Bytes cam = {0x02, 0x02, 0x00, 0x00, 0x30, 0x39};
  set_fix(pos_a, rt, at(0, 0));
  const auto sent_at = rt.wall_now();
  ASSERT_EQ(btp_a.send_b(geonet::DataRequest::single_hop({}, 1s), btp::kPortCam, 0, cam),
            geonet::DataConfirm::kAccepted);
  ASSERT_TRUE(run_until([&] { return !cams.empty(); }));
  EXPECT_EQ(cams[0], cam);
  EXPECT_EQ(cam_gn.sender, link_a->address());
  EXPECT_EQ(cam_gn.source.mid, link_a->address());
  EXPECT_EQ(cam_gn.packet_type, geonet::PacketType::kSingleHopBroadcast);
  // The kernel's receive stamp lies between sending and now.
  EXPECT_GE(cam_gn.rx_time, sent_at);
  EXPECT_LE(cam_gn.rx_time, rt.wall_now());
  EXPECT_GT(cam_gn.remaining_lifetime, 500ms);

  std::vector<Bytes> denms;
  std::optional<geonet::GeoArea> denm_area;
  btp_a.register_port(btp::kPortDenm, [&](const btp::Indication& i, auto payload) {
    denms.emplace_back(payload.begin(), payload.end());
    denm_area = i.gn->destination_area;
  });
  const auto area = geonet::testing::circle_at(at(20, 0), 200);
  set_fix(pos_b, rt, at(60, 0));
  ASSERT_EQ(btp_b.send_b(geonet::DataRequest::geo_broadcast(area), btp::kPortDenm, 0, Bytes{7, 7}),
            geonet::DataConfirm::kAccepted);
  ASSERT_TRUE(run_until([&] { return !denms.empty(); }));
  EXPECT_EQ(denms[0], (Bytes{7, 7}));
  EXPECT_EQ(denm_area, area);
  // A rebroadcast the GBC inside the area; B dropped that copy of its own packet.
  ASSERT_TRUE(run_until([&] { return router_b.stats().dropped(geonet::DropReason::kOwnPacket); }));
  EXPECT_EQ(router_a.stats().forwarded, 1u);
  EXPECT_EQ(link_b->stats().delivered, router_b.stats().received);
  EXPECT_EQ(link_a->stats().truncated + link_a->stats().receive_errors, 0u);
  EXPECT_EQ(router_a.stats().dropped(geonet::DropReason::kParseError), 0u);
}

}  // namespace
}  // namespace tb::its
