// A tiny benchmark registry: each module registers named measurements; cellform-bench runs them.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace cellform::bench {

/// One measurement: `run` performs one repetition and returns its value in `unit`.
struct Benchmark {
  std::string name;  ///< dotted and stable, e.g. "cells.step.50k.t2"
  std::string unit;  ///< e.g. "steps/s", "ms", "bytes/cell"
  std::string doc;   ///< one line for docs/benchmarks.md
  int repetitions = 5;
  std::function<double()> run;
};

/// Every registered benchmark, in registration order.
std::vector<Benchmark>& registry();

/// Registers at static-initialisation time: `static Register r{{...}};`.
struct Register {
  explicit Register(Benchmark b) { registry().push_back(std::move(b)); }
};

/// Peak resident set size of this process so far, bytes (from /proc/self/status VmHWM).
double peak_rss_bytes();
/// Current resident set size, bytes.
double current_rss_bytes();
/// CPU time used by this process (all threads), seconds.
double process_cpu_seconds();

}  // namespace cellform::bench
