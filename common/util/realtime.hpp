#pragma once
/// @file Real-time scheduling for the one thread of a program whose wake-up is its latency (the
/// radio medium: a frame waits in a socket until its thread runs).

#include <string>

#include "common/util/expected.hpp"

namespace tb {

/// What the calling thread runs at after run_at_realtime_priority: the policy's name and the
/// priority as the kernel reports them.
struct SchedulingReport {
  std::string policy;
  int priority = 0;
};

/// Puts the calling thread under SCHED_FIFO at @p priority (1..99), with SCHED_RESET_ON_FORK so
/// that a child it starts runs at normal priority again.
///
/// Why it can be refused, and what the error then says: the thread needs CAP_SYS_NICE (a
/// container: cap_add SYS_NICE); on a kernel with CONFIG_RT_GROUP_SCHED (cgroup v1
/// cpu.rt_runtime_us exists) also a real-time budget in its cpu cgroup, which a container has
/// only when its runtime or entry point gave it one (docs/scale-out.md). The kernel's throttling
/// (sched_rt_runtime_us, or the group's budget) keeps a runaway real-time thread from starving
/// the machine.
/// @returns the scheduling read back from the kernel, or why it was not changed (the value and
/// the kernel's error named).
Expected<SchedulingReport, std::string> run_at_realtime_priority(int priority);

/// The calling thread's scheduling as the kernel has it now.
SchedulingReport current_scheduling();

}  // namespace tb
