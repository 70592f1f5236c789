#include "station-host/link/pooled_links.hpp"

#include <algorithm>
#include <cstring>

#include "common/wire/pooled_delivery.hpp"
#include "common/wire/station_mac.hpp"

namespace tb::host {

namespace link = its::link;

link::MacAddress pooled_station_mac(std::uint32_t id) {
  return wire::station_mac(id);
}

namespace {

constexpr std::size_t kHeader = wire::kEthernetHeaderSize;

bool is_group(const link::MacAddress& mac) {
  return (mac[0] & 0x01) != 0;  // IEEE 802: the I/G bit of the first octet
}

/// The Ethernet header of @p frame (at least kHeader bytes) as a ReceivedFrame.
link::ReceivedFrame parse_ethernet(std::span<const std::uint8_t> frame, clock::WallTime rx_time) {
  link::ReceivedFrame f;
  std::memcpy(f.destination.data(), frame.data(), 6);
  std::memcpy(f.source.data(), frame.data() + 6, 6);
  f.ethertype = static_cast<std::uint16_t>(frame[12] << 8 | frame[13]);
  f.payload = frame.subspan(kHeader);
  f.rx_time = rx_time;
  return f;
}

}  // namespace

class PooledLinks::StationLink final : public link::LinkLayer {
 public:
  StationLink(PooledLinks& owner, std::uint32_t id)
      : owner_(owner), id_(id), mac_(pooled_station_mac(id)) {}
  link::MacAddress address() const override { return mac_; }
  std::error_code send(const link::MacAddress& destination, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) override {
    return owner_.send(*this, destination, ethertype, payload);
  }
  void set_receive_handler(link::ReceiveHandler handler) override { handler_ = std::move(handler); }
  void deliver(const link::ReceivedFrame& f) const {
    if (handler_)
      handler_(f);
  }
  std::uint32_t id() const { return id_; }

 private:
  PooledLinks& owner_;
  std::uint32_t id_;
  link::MacAddress mac_;
  link::ReceiveHandler handler_;
};

PooledLinks::PooledLinks(FrameOutput& output, const clock::Clock& clock, bool loop_back,
                         std::function<void()> request_flush)
    : output_(output),
      clock_(clock),
      loop_back_(loop_back),
      request_flush_(std::move(request_flush)) {
  tx_buffer_.reserve(kHeader + link::kMaxPayload);
}

PooledLinks::~PooledLinks() = default;

link::LinkLayer& PooledLinks::link(std::uint32_t station_id) {
  auto& slot = stations_[station_id];
  if (!slot) {
    slot = std::make_unique<StationLink>(*this, station_id);
    order_.push_back(slot.get());
  }
  return *slot;
}

PooledLinks::StationLink* PooledLinks::find(std::uint32_t station_id) const {
  const auto it = stations_.find(station_id);
  return it == stations_.end() ? nullptr : it->second.get();
}

PooledLinks::StationLink* PooledLinks::find(const link::MacAddress& mac) const {
  if (mac[0] != 0x02 || mac[1] != 0x00)
    return nullptr;
  return find(std::uint32_t{mac[2]} << 24 | std::uint32_t{mac[3]} << 16 |
              std::uint32_t{mac[4]} << 8 | std::uint32_t{mac[5]});
}

std::error_code PooledLinks::send(StationLink& from, const link::MacAddress& destination,
                                  std::uint16_t ethertype, std::span<const std::uint8_t> payload) {
  if (payload.size() > link::kMaxPayload)
    return std::make_error_code(std::errc::message_size);
  tx_buffer_.resize(kHeader + payload.size());
  std::memcpy(tx_buffer_.data(), destination.data(), 6);
  const link::MacAddress src = from.address();
  std::memcpy(tx_buffer_.data() + 6, src.data(), 6);
  tx_buffer_[12] = static_cast<std::uint8_t>(ethertype >> 8);
  tx_buffer_[13] = static_cast<std::uint8_t>(ethertype);
  std::memcpy(tx_buffer_.data() + kHeader, payload.data(), payload.size());
  const std::error_code ec = output_.send_frame(tx_buffer_);
  if (ec) {
    ++counters_.send_errors;
    return ec;
  }
  ++counters_.sent;
  if (loop_back_ && order_.size() > 1) {
    // One copy per transmission (the sender's buffer is reused at once), none per receiver.
    pending_.push_back(Pending{from.id(), tx_buffer_, clock_.wall_now()});
    if (!flush_requested_ && request_flush_) {
      flush_requested_ = true;
      request_flush_();
    }
  }
  return {};
}

void PooledLinks::flush() {
  flush_requested_ = false;
  // Stations may send while receiving: what they send now waits for the next flush.
  flushing_.swap(pending_);
  for (const Pending& p : flushing_) {
    const link::ReceivedFrame f = parse_ethernet(p.frame, p.time);
    if (f.ethertype != link::kEtherTypeGeoNetworking) {
      ++counters_.not_for_us;
      continue;
    }
    const std::uint64_t before = counters_.deliveries;
    deliver_plain(f, find(p.sender));
    counters_.looped_back += counters_.deliveries - before;
  }
  flushing_.clear();
}

void PooledLinks::deliver_plain(const link::ReceivedFrame& f, const StationLink* except) {
  if (!is_group(f.destination)) {
    StationLink* to = find(f.destination);
    if (to == nullptr || to == except) {
      ++counters_.not_for_us;
      return;
    }
    ++counters_.deliveries;
    to->deliver(f);
    return;
  }
  for (const StationLink* s : order_) {
    if (s == except)
      continue;
    ++counters_.deliveries;
    s->deliver(f);
  }
}

void PooledLinks::on_frame(std::span<const std::uint8_t> frame, clock::WallTime rx_time) {
  ++counters_.frames;
  if (frame.size() < kHeader) {
    ++counters_.not_for_us;
    return;
  }
  const link::ReceivedFrame outer = parse_ethernet(frame, rx_time);
  if (outer.ethertype == link::kEtherTypeGeoNetworking) {
    ++counters_.plain;
    deliver_plain(outer, find(outer.source));
    return;
  }
  if (outer.ethertype != wire::kEthertypePooledDelivery) {
    ++counters_.not_for_us;
    return;
  }
  const auto delivery = wire::parse_pooled_delivery(outer.payload);
  if (!delivery) {
    ++counters_.malformed_pooled;
    return;
  }
  const link::ReceivedFrame inner = parse_ethernet(delivery->inner_frame, rx_time);
  // The medium forwards the stations' GN frames only; anything else in a TBPD is not ours to
  // hand up (a full station's socket would not have received it either).
  if (inner.ethertype != link::kEtherTypeGeoNetworking) {
    ++counters_.malformed_pooled;
    return;
  }
  ++counters_.pooled;
  const std::size_t n = delivery->receiver_count();
  for (std::size_t i = 0; i < n; ++i) {
    const StationLink* to = find(delivery->receiver(i));
    if (to == nullptr) {
      ++counters_.foreign_receivers;
      continue;
    }
    ++counters_.deliveries;
    to->deliver(inner);
  }
}

}  // namespace tb::host
