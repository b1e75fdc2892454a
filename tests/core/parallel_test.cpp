// Tests of core/parallel.cpp: the cores counted are those the process may run on; with_threads caps TBB.
#include "core/parallel.h"

#include <sched.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <stdexcept>
#include <thread>
#include <vector>

TEST_CASE("hardware_threads counts the cores this process may use, and effective_threads caps at them", "[parallel]") {
  using cellform::core::effective_threads;
  using cellform::core::hardware_threads;
  cpu_set_t all;
  CPU_ZERO(&all);
  REQUIRE(::sched_getaffinity(0, sizeof all, &all) == 0);
  CHECK(hardware_threads() == CPU_COUNT(&all));
  CHECK(hardware_threads() <= static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  // as under `taskset -c N`: one core allowed (this thread's affinity, which the call reads)
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  REQUIRE(::sched_setaffinity(0, sizeof one, &one) == 0);
  const int under_taskset = hardware_threads(), capped = effective_threads(8), all_cores = effective_threads(0);
  REQUIRE(::sched_setaffinity(0, sizeof all, &all) == 0);  // put back before checking
  CHECK(under_taskset == 1);
  CHECK(capped == 1);
  CHECK(all_cores == 1);
  // and a loop asked for more threads still covers every index once
  std::vector<int> hits(10000, 0);
  cellform::core::parallel_for(
      hits.size(), 8,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) ++hits[i];
      },
      64);
  CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
}

TEST_CASE("with_threads runs TBB algorithms on at most the threads asked for, and passes exceptions on", "[parallel]") {
  using cellform::core::effective_threads;
  using cellform::core::with_threads;
  for (int t : {1, 2, 0, 64}) {
    int concurrency = -1;
    with_threads(t, [&] { concurrency = tbb::this_task_arena::max_concurrency(); });
    CHECK(concurrency == effective_threads(t));
  }
  // one thread: a TBB loop inside runs on the calling thread alone
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> elsewhere{0};
  with_threads(1, [&] {
    tbb::parallel_for(0, 100000, [&](int) {
      if (std::this_thread::get_id() != caller) ++elsewhere;
    });
  });
  CHECK(elsewhere == 0);
  CHECK_THROWS_WITH(with_threads(2, [] { throw std::runtime_error("out of memory for the grid"); }),
                    "out of memory for the grid");
}
