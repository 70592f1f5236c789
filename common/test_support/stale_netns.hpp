#pragma once
/// @file Named network namespaces left behind by test runs that were killed before their
/// clean-up ran, found by name and removed.
///
/// Tests name their namespaces <prefix><pid><rest> (the pid of the process that made them, so
/// that parallel runs do not collide). A namespace of a prefix whose pid is no longer alive can
/// belong to no running test: it is stale. One whose pid is alive may be another run's in
/// progress and is never touched. (A pid reused since by an unrelated process keeps a stale
/// namespace until that process ends: removing too little is safe, too much is not.)

#include <sys/types.h>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tb::test_support {

/// The pid a namespace @p name of scheme @p prefix was made by: the decimal digits right after
/// the prefix. nullopt when @p name does not start with @p prefix followed by a digit, or the
/// digits do not fit a pid.
std::optional<pid_t> creator_pid(std::string_view name, std::string_view prefix);

/// Whether process @p pid exists (kill(pid, 0), which EPERM also answers with yes).
bool process_alive(pid_t pid);

struct StaleNetns {
  std::string name;
  pid_t creator;
  bool operator==(const StaleNetns&) const = default;
};

/// Of @p names, those of one of @p prefixes whose creator is not alive according to @p alive.
std::vector<StaleNetns> stale_names(const std::vector<std::string>& names,
                                    const std::vector<std::string>& prefixes,
                                    const std::function<bool(pid_t)>& alive);

/// The names under /run/netns (what `ip netns list` shows); none when the folder is missing.
std::vector<std::string> named_netns();

/// Removes the stale namespaces of @p prefixes as `ip netns del` does (detach the bind mount,
/// unlink the file; the namespace, and the interfaces in it, go when nothing else holds it).
/// Writes one line per namespace removed, or failed to remove, to stderr. Returns those removed.
std::vector<std::string> remove_stale_netns(const std::vector<std::string>& prefixes);

}  // namespace tb::test_support
