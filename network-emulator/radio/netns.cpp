#include "network-emulator/radio/netns.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace tb::emu::radio {

NetnsFd NetnsFd::open(const std::string& spec) {
  NetnsFd ns;
  ns.path_ = spec.starts_with('/') ? spec : "/run/netns/" + spec;
  ns.fd_ = ::open(ns.path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (ns.fd_ < 0)
    throw std::system_error(
        errno, std::generic_category(),
        "cannot open network namespace " + ns.path_ + " (make it first, e.g. `ip netns add NAME`)");
  return ns;
}

std::pair<unsigned long, unsigned long> NetnsFd::identity() const {
  struct stat st {};
  if (::fstat(fd_, &st) != 0)
    throw std::system_error(errno, std::generic_category(), "cannot stat " + path_);
  return {static_cast<unsigned long>(st.st_dev), static_cast<unsigned long>(st.st_ino)};
}

NetnsFd NetnsFd::current() {
  return open("/proc/thread-self/ns/net");
}

NetnsFd::~NetnsFd() {
  if (fd_ >= 0)
    ::close(fd_);
}

NetnsFd& NetnsFd::operator=(NetnsFd&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0)
      ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
  }
  return *this;
}

void enter_netns(const NetnsFd& ns) {
  if (::setns(ns.fd(), CLONE_NEWNET) != 0)
    throw std::system_error(errno, std::generic_category(),
                            "cannot enter network namespace " + ns.path());
}

}  // namespace tb::emu::radio
