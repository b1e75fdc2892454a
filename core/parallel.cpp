// parallel_for over TBB task arenas.
#include "core/parallel.h"

#include <sched.h>
#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace cellform::core {

namespace {

// One arena per thread count, created on first use and kept: constructing and initialising an arena
// per call costs more than a small loop. Arenas are thread-safe, so callers may share them.
tbb::task_arena& arena_for(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<tbb::task_arena>& arena = arenas[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  return *arena;
}

}  // namespace

int hardware_threads() {
  // the cores this process may run on (taskset, a container's cpuset; its main thread's mask, whichever thread
  // asks), not all the machine has: TBB warns when asked for more workers than those (a system call, about a µs)
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(::getpid(), sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

int effective_threads(int threads) { return threads <= 0 ? hardware_threads() : std::min(threads, hardware_threads()); }

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body,
                  std::size_t grain) {
  if (n == 0) return;
  if (threads == 1 || n <= grain) {
    body(0, n);
    return;
  }
  // more threads than cores cannot help, and TBB warns on stderr when asked for them; results do not
  // depend on the count
  const int t = effective_threads(threads);
  arena_for(t).execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  });
}

void with_threads(int threads, const std::function<void()>& body) {
  arena_for(effective_threads(threads)).execute(body);
}

}  // namespace cellform::core
