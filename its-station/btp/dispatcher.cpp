#include "its-station/btp/dispatcher.hpp"

namespace tb::its::btp {

std::string to_string(DropReason r) {
  switch (r) {
    case DropReason::kNotBtp:
      return "GN payload is not BTP";
    case DropReason::kTruncatedHeader:
      return "truncated BTP header";
    case DropReason::kNoPortHandler:
      return "no handler for the destination port";
    case DropReason::kItsAidMismatch:
      return "signed for another service than the port's";
    case DropReason::kCount:
      break;
  }
  return "unknown";
}

std::uint64_t its_aid_of(std::uint16_t port) {
  // TS 103 248 ports, TS 102 965 ITS-AIDs.
  switch (port) {
    case kPortCam:
      return 36;
    case kPortDenm:
      return 37;
    case kPortMapem:
      return 138;  // RLT (road and lane topology)
    case kPortSpatem:
      return 137;  // TLM (traffic light manoeuvre)
    default:
      return 0;
  }
}

Dispatcher::Dispatcher(geonet::Router& router) : router_(router) {
  router_.set_indication_handler(
      [this](const geonet::DataIndication& gn, std::span<const std::uint8_t> bytes) {
        on_indication(gn, bytes);
      });
}

Dispatcher::~Dispatcher() {
  router_.set_indication_handler({});
}

bool Dispatcher::register_port(std::uint16_t port, PortHandler handler) {
  return handlers_.try_emplace(port, std::move(handler)).second;
}

void Dispatcher::unregister_port(std::uint16_t port) {
  handlers_.erase(port);
}

geonet::DataConfirm Dispatcher::send_b(geonet::DataRequest gn, std::uint16_t destination_port,
                                       std::uint16_t destination_port_info,
                                       std::span<const std::uint8_t> payload) {
  if (payload.size() > tx_.size() - kHeaderSize)
    return geonet::DataConfirm::kMaxSduSizeExceeded;
  ByteWriter w{tx_};
  write_header(w, HeaderB{destination_port, destination_port_info});
  w.write(payload);
  gn.upper_protocol = geonet::UpperProtocol::kBtpB;
  // The ITS-AID the security entity signs for: the service of the well-known port (TS 103 248
  // ports, TS 102 965 ITS-AIDs) unless the caller named one.
  if (gn.its_aid == 0)
    gn.its_aid = its_aid_of(destination_port);
  return router_.request(gn, std::span(tx_).first(w.position()));
}

geonet::DataConfirm Dispatcher::send_a(geonet::DataRequest gn, std::uint16_t destination_port,
                                       std::uint16_t source_port,
                                       std::span<const std::uint8_t> payload) {
  if (payload.size() > tx_.size() - kHeaderSize)
    return geonet::DataConfirm::kMaxSduSizeExceeded;
  ByteWriter w{tx_};
  write_header(w, HeaderA{destination_port, source_port});
  w.write(payload);
  gn.upper_protocol = geonet::UpperProtocol::kBtpA;
  return router_.request(gn, std::span(tx_).first(w.position()));
}

void Dispatcher::drop(DropReason r) {
  ++stats_.drops[static_cast<std::size_t>(r)];
  if (drop_hook_)
    drop_hook_(r);
}

void Dispatcher::on_indication(const geonet::DataIndication& gn,
                               std::span<const std::uint8_t> bytes) {
  Indication ind;
  ind.type = gn.upper_protocol;
  ind.gn = &gn;
  if (gn.upper_protocol == geonet::UpperProtocol::kBtpB) {
    const auto h = parse_header_b(bytes);
    if (!h) {
      drop(DropReason::kTruncatedHeader);
      return;
    }
    ind.destination_port = h->destination_port;
    ind.destination_port_info = h->destination_port_info;
  } else if (gn.upper_protocol == geonet::UpperProtocol::kBtpA) {
    const auto h = parse_header_a(bytes);
    if (!h) {
      drop(DropReason::kTruncatedHeader);
      return;
    }
    ind.destination_port = h->destination_port;
    ind.source_port = h->source_port;
  } else {
    drop(DropReason::kNotBtp);
    return;
  }
  // A secured packet's ITS-AID must be the port's service: a CAM port payload signed for DENM
  // (or anything else) would pass verification under permissions it does not have.
  if (gn.security_report && its_aid_of(ind.destination_port) != 0 &&
      gn.its_aid != its_aid_of(ind.destination_port)) {
    drop(DropReason::kItsAidMismatch);
    return;
  }
  const auto it = handlers_.find(ind.destination_port);
  if (it == handlers_.end()) {
    drop(DropReason::kNoPortHandler);
    return;
  }
  ++stats_.delivered;
  it->second(ind, bytes.subspan(kHeaderSize));
}

}  // namespace tb::its::btp
