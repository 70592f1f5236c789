#pragma once
/// @file The kernel's receive stamp of a datagram or frame (SO_TIMESTAMPNS), read from the
/// control messages of recvmsg/recvmmsg: the one parser of SCM_TIMESTAMPNS for every socket of
/// the testbed that dates what it receives.

#include <sys/socket.h>

#include <cstdint>
#include <cstring>
#include <ctime>
#include <optional>

namespace tb {

/// Nanoseconds since the Unix epoch at which the kernel received the message, or nullopt when
/// @p m carries no SCM_TIMESTAMPNS (the socket has no SO_TIMESTAMPNS, or the control buffer was
/// too small).
inline std::optional<std::int64_t> kernel_rx_unix_ns(const msghdr& m) {
  auto& mm = const_cast<msghdr&>(m);  // the CMSG macros take non-const pointers; nothing is written
  for (cmsghdr* c = CMSG_FIRSTHDR(&mm); c != nullptr; c = CMSG_NXTHDR(&mm, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec ts;
      std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
      return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
    }
  }
  return std::nullopt;
}

}  // namespace tb
