#include "its-station/facilities/transport.hpp"

namespace tb::its::facilities {

std::string_view to_string(SendResult r) {
  switch (r) {
    case SendResult::kSent:
      return "sent";
    case SendResult::kNoPosition:
      return "no position vector yet";
    case SendResult::kTooLarge:
      return "packet too large";
    case SendResult::kLinkError:
      return "link error";
  }
  return "?";
}

}  // namespace tb::its::facilities
