#pragma once
/// @file Running a piece of code inside a named network namespace (ip netns).
///
/// A socket stays in the namespace it was created in, so a process in the host namespace can
/// own sockets (a CAN_RAW socket on a station's vcan0, a UDP socket bound to a station's
/// address) in every station's namespace without moving itself.

#include <functional>
#include <string>
#include <system_error>

namespace tb::can {

/// Runs @p fn on a short-lived thread that has joined /run/netns/@p name (setns only changes
/// the calling thread). An empty name runs @p fn in the current namespace. Exceptions from
/// @p fn are passed on. Returns the error of opening or joining the namespace.
std::error_code run_in_netns(const std::string& name, const std::function<void()>& fn);

}  // namespace tb::can
