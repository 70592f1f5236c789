#pragma once
/// @file Reading a descriptor whenever it becomes readable, on the io_context's thread: the
/// receive loop of the medium's AF_PACKET sockets.

#include <functional>

#include <boost/asio/posix/stream_descriptor.hpp>

namespace tb::emu::radio {

/// Calls @p drain each time @p descriptor becomes readable, until its wait is cancelled (at
/// shutdown). @p drain must read what is there, or the next wait returns at once.
inline void drain_when_readable(boost::asio::posix::stream_descriptor& descriptor,
                                std::function<void()> drain) {
  descriptor.async_wait(
      boost::asio::posix::stream_descriptor::wait_read,
      [&descriptor, drain = std::move(drain)](const boost::system::error_code& ec) {
        if (ec)
          return;  // cancelled at shutdown
        drain();
        drain_when_readable(descriptor, drain);
      });
}

}  // namespace tb::emu::radio
