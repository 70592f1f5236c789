#pragma once
/// @file Network namespaces: opening them by name or path, and running code inside one.
///
/// Stations' namespaces are made by the launcher (`ip netns add NAME`, or a container's
/// /proc/PID/ns/net); the radio code only opens and enters them.

#include <exception>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

namespace tb::emu::radio {

/// An open namespace file descriptor. Move-only.
class NetnsFd {
 public:
  NetnsFd() = default;
  /// @p spec is a name under /run/netns (as `ip netns add` makes) or an absolute path such as
  /// /proc/PID/ns/net. @throws std::system_error naming the path.
  static NetnsFd open(const std::string& spec);
  /// The namespace of the calling thread.
  static NetnsFd current();
  ~NetnsFd();
  NetnsFd(NetnsFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)), path_(std::move(o.path_)) {}
  NetnsFd& operator=(NetnsFd&& o) noexcept;

  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  /// Which namespace this is (device and inode of its nsfs file): a name that is later bound
  /// to another namespace (a station container that restarted) gives another identity.
  /// @throws std::system_error.
  std::pair<unsigned long, unsigned long> identity() const;

 private:
  int fd_ = -1;
  std::string path_;
};

/// Enters @p ns on the calling thread. @throws std::system_error.
void enter_netns(const NetnsFd& ns);

/// Runs @p f on a fresh thread that has entered @p ns, and returns its result; sockets made
/// inside stay in that namespace. The caller's own thread never changes namespace, so this
/// is safe next to an io_context. Exceptions from @p f are rethrown here.
template <typename F>
auto in_netns(const NetnsFd& ns, F&& f) -> decltype(f()) {
  using R = decltype(f());
  std::exception_ptr error;
  if constexpr (std::is_void_v<R>) {
    std::thread t([&] {
      try {
        enter_netns(ns);
        f();
      } catch (...) {
        error = std::current_exception();
      }
    });
    t.join();
    if (error)
      std::rethrow_exception(error);
  } else {
    std::optional<R> result;
    std::thread t([&] {
      try {
        enter_netns(ns);
        result.emplace(f());
      } catch (...) {
        error = std::current_exception();
      }
    });
    t.join();
    if (error)
      std::rethrow_exception(error);
    return std::move(*result);
  }
}

}  // namespace tb::emu::radio
