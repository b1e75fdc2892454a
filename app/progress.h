// Progress reporting for long runs: a bar on a terminal, a short line every few seconds otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/types.h"

namespace cellform::app {

/// Reports step, cells, steps per second and time left; silent when quiet.
class Progress {
 public:
  /// `then`: what follows the steps, said after the time left ("13s left, then the print"), which is the
  /// steps' alone (a print of a large form can take longer than its steps); empty: nothing said.
  /// `max_cells`: growth stops at this many cells (division.max_cells); 0: no cap known.
  Progress(std::ostream& out, bool terminal, bool quiet, std::uint64_t first_step, std::uint64_t last_step,
           std::string then = {}, std::size_t max_cells = 0);
  /// Called after every step with the cells then: the time left assumes a cell costs what it did so far,
  /// and that the cells go on growing as they did since half the steps so far (as a power of the step,
  /// never shrinking, up to the cap `max_cells`): a step rate alone said "0s left", and the present
  /// count alone a half to a quarter of the time a dividing form took.
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
  std::size_t cap_ = 0;
  std::vector<std::pair<std::uint64_t, std::size_t>> samples_;  // (step, cells), steps ~5% apart
};

/// "42s", "3m05s", "2h07m" ("?" if not a time).
std::string duration_text(double seconds);

/// " across 31.0 x 32.2 x 8.2 model units": the sides of the points' bounding box, to three significant digits of
/// the largest, for the line
/// that ends a run (a designer reads the form's size there before opening a file); "" for no point, or one
/// not finite.
std::string extent_text(const std::vector<core::Vec3>& points);

/// Cell-steps of the steps after `step` up to `last` for a form of `cells` cells at `step` whose count goes
/// as step^p (p >= 0) up to `cap` cells (0: no cap): the integral of min(cap, cells * (s / step)^p) ds.
double projected_cell_steps(double step, double last, double cells, double p, double cap);

}  // namespace cellform::app
