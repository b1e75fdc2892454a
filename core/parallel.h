// One parallel-for over TBB with a serial fallback; callers write only their own slots.
#pragma once

#include <cstddef>
#include <functional>

namespace cellform::core {

/// Calls body(begin, end) on disjoint sub-ranges of [0, n), using at most `threads` threads
/// (0 = all cores, 1 = serial on the calling thread). Ranges below `grain` items run serially.
/// Results are deterministic as long as body writes only to slots of its own range.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t grain = 2048);

/// Runs body with the TBB algorithms it starts (OpenVDB's tools, tbb::parallel_sort, parallel_for) on at most
/// `threads` threads (0 = all cores), in the arena parallel_for uses. Exceptions pass through.
void with_threads(int threads, const std::function<void()>& body);

/// Number of hardware threads this process may run on (its CPU affinity: taskset, a container's cpuset).
int hardware_threads();

/// The worker threads a `threads` setting comes to here: 0 or less = all cores; more than the cores cannot
/// help, so at most that many (what parallel_for uses).
int effective_threads(int threads);

}  // namespace cellform::core
