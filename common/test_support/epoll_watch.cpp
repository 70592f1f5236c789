#include "common/test_support/epoll_watch.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace tb::test_support {

std::size_t epoll_watched_descriptors() {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) {
    std::error_code ec;
    const auto target = std::filesystem::read_symlink(e.path(), ec);
    if (ec || target.string() != "anon_inode:[eventpoll]")
      continue;
    std::ifstream info("/proc/self/fdinfo/" + e.path().filename().string());
    for (std::string line; std::getline(info, line);)
      n += line.starts_with("tfd:") ? 1 : 0;
  }
  return n;
}

}  // namespace tb::test_support
