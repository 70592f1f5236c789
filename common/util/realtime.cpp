#include "common/util/realtime.hpp"

#include <sched.h>

#include <cerrno>
#include <cstring>

namespace tb {

namespace {

std::string policy_name(int policy) {
  switch (policy & ~SCHED_RESET_ON_FORK) {
    case SCHED_OTHER:
      return "SCHED_OTHER";
    case SCHED_FIFO:
      return "SCHED_FIFO";
    case SCHED_RR:
      return "SCHED_RR";
    case SCHED_BATCH:
      return "SCHED_BATCH";
    case SCHED_IDLE:
      return "SCHED_IDLE";
    default:
      return "policy " + std::to_string(policy);
  }
}

}  // namespace

SchedulingReport current_scheduling() {
  sched_param p{};
  const int policy = sched_getscheduler(0);
  sched_getparam(0, &p);
  return {policy < 0 ? "unknown" : policy_name(policy), p.sched_priority};
}

Expected<SchedulingReport, std::string> run_at_realtime_priority(int priority) {
  const int lo = sched_get_priority_min(SCHED_FIFO);
  const int hi = sched_get_priority_max(SCHED_FIFO);
  if (priority < lo || priority > hi)
    return Unexpected{"real-time priority " + std::to_string(priority) + " is not in " +
                      std::to_string(lo) + ".." + std::to_string(hi)};
  sched_param p{};
  p.sched_priority = priority;
  // On Linux sched_setscheduler(0, ...) changes the calling thread, not the whole process.
  if (sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &p) != 0) {
    const int e = errno;
    std::string why =
        "SCHED_FIFO at priority " + std::to_string(priority) + ": " + std::strerror(e);
    if (e == EPERM)
      why +=
          " (needs CAP_SYS_NICE, in a container cap_add SYS_NICE; where the kernel schedules "
          "real time by cgroup (cpu.rt_runtime_us) also a real-time budget in the process's "
          "cpu cgroup)";
    return Unexpected{why};
  }
  return current_scheduling();
}

}  // namespace tb
