// Progress reporting for long runs: a bar on a terminal, a short line every few seconds otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>

namespace cellform::app {

/// Reports step, cells, steps per second and time left; silent when quiet.
class Progress {
 public:
  /// `then`: what follows the steps, said after the time left ("13s left, then the print"), which is the
  /// steps' alone (a print of a large form can take longer than its steps); empty: nothing said.
  Progress(std::ostream& out, bool terminal, bool quiet, std::uint64_t first_step, std::uint64_t last_step,
           std::string then = {});
  /// Called after every step with the cells then: the time left assumes a cell costs what it did so far,
  /// and at least as many cells as now (a growing form slows down; a step rate alone said "0s left").
  void update(std::uint64_t step, std::size_t cells);
  void finish();
  /// Ends the bar's line in a terminal (before another line is written there); the next update draws the bar
  /// anew below it.
  void break_line();

 private:
  std::ostream& out_;
  bool terminal_;
  bool quiet_;
  std::uint64_t first_, last_;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool open_ = false;      // a terminal bar is on the current line
  double cell_steps_ = 0;  // cells summed over the steps reported: time left scales with the cells
  std::string then_;
};

}  // namespace cellform::app
