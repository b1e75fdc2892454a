// Progress reporting for long runs: a bar on a terminal, a short line every few seconds otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>

namespace cellform::app {

/// Reports step, cells, steps per second and time left; silent when quiet.
class Progress {
 public:
  Progress(std::ostream& out, bool terminal, bool quiet, std::uint64_t first_step, std::uint64_t last_step);
  void update(std::uint64_t step, std::size_t cells);
  void finish();

 private:
  std::ostream& out_;
  bool terminal_;
  bool quiet_;
  std::uint64_t first_, last_;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool printed_ = false;
};

}  // namespace cellform::app
