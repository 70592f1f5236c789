#include "its-station/asn1/error.hpp"

namespace tb::its::asn1 {

std::string_view to_string(Error e) {
  switch (e) {
    case Error::kTruncated:
      return "input truncated";
    case Error::kValueOutOfRange:
      return "value out of range";
    case Error::kSizeOutOfRange:
      return "size out of range";
    case Error::kUnknownExtension:
      return "unknown extension";
    case Error::kUnsupported:
      return "not supported";
    case Error::kWrongMessageId:
      return "wrong messageID";
    case Error::kUnsupportedVersion:
      return "unsupported protocolVersion";
    case Error::kBufferTooSmall:
      return "output buffer too small";
    case Error::kTrailingData:
      return "trailing data after the message";
  }
  return "unknown error";
}

std::string to_string(const CodecError& e) {
  std::string s(to_string(e.code));
  s += ": ";
  s += (e.field != nullptr && *e.field != '\0') ? e.field : "(message)";
  s += " = ";
  s += std::to_string(e.value);
  s += " (bit ";
  s += std::to_string(e.bit_offset);
  s += ')';
  return s;
}

}  // namespace tb::its::asn1
