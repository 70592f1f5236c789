#include "its-station/btp/header.hpp"

namespace tb::its::btp {

std::string to_string(ParseError e) {
  switch (e) {
    case ParseError::kTruncatedHeader:
      return "BTP header shorter than 4 bytes";
  }
  return "unknown BTP parse error";
}

Expected<HeaderA, ParseError> parse_header_a(std::span<const std::uint8_t> bytes) {
  ByteReader r{bytes};
  HeaderA h;
  h.destination_port = r.be<std::uint16_t>();
  h.source_port = r.be<std::uint16_t>();
  if (!r.ok())
    return Unexpected{ParseError::kTruncatedHeader};
  return h;
}

Expected<HeaderB, ParseError> parse_header_b(std::span<const std::uint8_t> bytes) {
  ByteReader r{bytes};
  HeaderB h;
  h.destination_port = r.be<std::uint16_t>();
  h.destination_port_info = r.be<std::uint16_t>();
  if (!r.ok())
    return Unexpected{ParseError::kTruncatedHeader};
  return h;
}

void write_header(ByteWriter& w, const HeaderA& h) {
  w.be<std::uint16_t>(h.destination_port);
  w.be<std::uint16_t>(h.source_port);
}

void write_header(ByteWriter& w, const HeaderB& h) {
  w.be<std::uint16_t>(h.destination_port);
  w.be<std::uint16_t>(h.destination_port_info);
}

}  // namespace tb::its::btp
