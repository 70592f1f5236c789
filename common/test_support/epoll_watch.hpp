#pragma once
/// @file For tests that check a descriptor left (or joined) the process's epoll sets: how many
/// descriptors they watch, from the "tfd:" lines of each epoll descriptor's /proc fdinfo
/// (proc(5)).

#include <cstddef>

namespace tb::test_support {

std::size_t epoll_watched_descriptors();

}  // namespace tb::test_support
