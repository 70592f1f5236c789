#include "common/test_support/stale_netns.hpp"

#include <signal.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace tb::test_support {

namespace {
constexpr const char* kNetnsDir = "/run/netns";
}  // namespace

std::optional<pid_t> creator_pid(std::string_view name, std::string_view prefix) {
  if (!name.starts_with(prefix))
    return std::nullopt;
  const std::string_view rest = name.substr(prefix.size());
  pid_t pid = 0;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), pid);
  // from_chars takes no sign, but a leading '+' or space would not be ours either.
  if (ec != std::errc{} || end == rest.data() || pid <= 0)
    return std::nullopt;
  return pid;
}

bool process_alive(pid_t pid) {
  return ::kill(pid, 0) == 0 || errno == EPERM;
}

std::vector<StaleNetns> stale_names(const std::vector<std::string>& names,
                                    const std::vector<std::string>& prefixes,
                                    const std::function<bool(pid_t)>& alive) {
  std::vector<StaleNetns> out;
  for (const std::string& name : names) {
    for (const std::string& prefix : prefixes) {
      const auto pid = creator_pid(name, prefix);
      if (pid && !alive(*pid)) {
        out.push_back({name, *pid});
        break;
      }
    }
  }
  return out;
}

std::vector<std::string> named_netns() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(kNetnsDir, ec))
    names.push_back(e.path().filename().string());
  return names;
}

std::vector<std::string> remove_stale_netns(const std::vector<std::string>& prefixes) {
  std::vector<std::string> removed;
  for (const auto& [name, pid] : stale_names(named_netns(), prefixes, process_alive)) {
    const std::string path = std::string(kNetnsDir) + "/" + name;
    // What `ip netns del` does. EINVAL: not a mount point (a bare file left by a failed add).
    // ENOENT: a run sweeping at the same time removed it first, and reports it.
    if (::umount2(path.c_str(), MNT_DETACH) != 0 && errno != EINVAL) {
      if (errno != ENOENT)
        std::fprintf(stderr, "stale network namespace %s (pid %d is gone): cannot unmount: %s\n",
                     name.c_str(), static_cast<int>(pid), std::strerror(errno));
      continue;
    }
    if (::unlink(path.c_str()) != 0) {
      if (errno != ENOENT)
        std::fprintf(stderr, "stale network namespace %s (pid %d is gone): cannot remove %s: %s\n",
                     name.c_str(), static_cast<int>(pid), path.c_str(), std::strerror(errno));
      continue;
    }
    std::fprintf(stderr, "removed stale network namespace %s (pid %d, which made it, is gone)\n",
                 name.c_str(), static_cast<int>(pid));
    removed.push_back(name);
  }
  return removed;
}

}  // namespace tb::test_support
