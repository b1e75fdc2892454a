// Progress bar and periodic progress lines.
#include "app/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace cellform::app {

std::string extent_text(const std::vector<core::Vec3>& points) {
  if (points.empty()) return "";
  core::Vec3 lo = points.front(), hi = lo;
  for (const core::Vec3& p : points) {
    if (!p.allFinite()) return "";
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const core::Vec3 size = hi - lo;
  // three significant digits of the largest side, in fixed notation (%g wrote a 1,500 mm form as 1.5e+03)
  const double largest = size.maxCoeff();
  if (!std::isfinite(largest)) return "";  // (sides past 1.8e308)
  char buf[160];
  if (largest >= 1e15) {  // (fixed notation would take hundreds of digits)
    std::snprintf(buf, sizeof buf, " across %.3g x %.3g x %.3g model units", size.x(), size.y(), size.z());
    return buf;
  }
  const int decimals = largest > 0 ? std::clamp(2 - static_cast<int>(std::floor(std::log10(largest))), 0, 12) : 0;
  std::snprintf(buf, sizeof buf, " across %.*f x %.*f x %.*f model units", decimals, size.x(), decimals, size.y(),
                decimals, size.z());
  return buf;
}

std::string duration_text(double s) {
  char buf[32];
  if (!std::isfinite(s) || s < 0) return "?";
  if (s >= 3.6e8) return ">99999h";  // (and an int holds the hours)
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600, static_cast<int>(s) / 60 % 60);
  return buf;
}

double projected_cell_steps(double step, double last, double cells, double p, double cap) {
  if (!(last > step)) return 0;
  if (cap > 0 && cells >= cap) return (last - step) * cells;  // (a cap lowered on resume: the cells stay)
  if (!(p > 0) || !(step > 0)) return (last - step) * cells;
  // the cap is reached at step * (cap / cells)^(1/p)
  const double full = cap > 0 ? step * std::pow(cap / cells, 1 / p) : INFINITY;
  const double upto = std::min(last, full);
  const double growing = cells * step / (p + 1) * (std::pow(upto / step, p + 1) - 1);
  return growing + (last > upto ? (last - upto) * cap : 0.0);
}

Progress::Progress(std::ostream& out, bool terminal, bool quiet, std::uint64_t first_step, std::uint64_t last_step,
                   std::string then, std::size_t max_cells)
    : out_(out),
      terminal_(terminal),
      quiet_(quiet),
      first_(first_step),
      last_(last_step),
      then_(std::move(then)),
      cap_(max_cells) {
  start_ = last_print_ = std::chrono::steady_clock::now();
}

void Progress::update(std::uint64_t step, std::size_t cells) {
  if (quiet_) return;
  cell_steps_ += static_cast<double>(std::max<std::size_t>(cells, 1));
  if (samples_.empty() || static_cast<double>(step) >= 1.05 * static_cast<double>(samples_.back().first) + 1)
    samples_.emplace_back(step, cells);
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (since < (terminal_ ? 0.1 : 5.0) && step != last_) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double done = static_cast<double>(step - first_);
  const double rate = elapsed > 0 ? done / elapsed : 0;
  // the growth since half the steps so far (of this command: a resume has no samples before its start), as
  // a power of the step: 1 to 2 under marginal growth, rising while every cell divides
  double p = 0;
  const auto half = std::lower_bound(samples_.begin(), samples_.end(), std::make_pair(step / 2, std::size_t{0}));
  if (half != samples_.end() && half->first > 0 && half->second > 0 &&
      static_cast<double>(step) >= 1.1 * static_cast<double>(half->first))
    p = std::clamp(std::log(static_cast<double>(cells) / static_cast<double>(half->second)) /
                       std::log(static_cast<double>(step) / static_cast<double>(half->first)),
                   0.0, 8.0);
  // (at least one cell: a form that lost all its cells still has its steps to go)
  const double left =
      cell_steps_ > 0 && elapsed > 0
          ? projected_cell_steps(static_cast<double>(step), static_cast<double>(last_),
                                 static_cast<double>(std::max<std::size_t>(cells, 1)), p, static_cast<double>(cap_)) *
                elapsed / cell_steps_
          : NAN;
  // of the whole run, as "step N/last" beside it reads (a resume starts part of the way)
  const double frac = last_ > 0 ? static_cast<double>(step) / static_cast<double>(last_) : 1.0;
  const std::string then = then_.empty() ? std::string() : ", then " + then_;
  char buf[200];
  if (terminal_) {
    const int width = 30;
    const int fill = static_cast<int>(frac * width);
    std::string bar(static_cast<std::size_t>(fill), '#');
    bar.resize(width, '.');
    std::snprintf(buf, sizeof buf, "\r[%s] step %llu/%llu  %zu cells  %.1f steps/s  %s left%s   ", bar.c_str(),
                  static_cast<unsigned long long>(step), static_cast<unsigned long long>(last_), cells, rate,
                  duration_text(left).c_str(), then.c_str());
    out_ << buf << std::flush;
    open_ = true;
  } else {
    std::snprintf(buf, sizeof buf, "step %llu/%llu (%.0f%%), %zu cells, %.1f steps/s, %s left%s\n",
                  static_cast<unsigned long long>(step), static_cast<unsigned long long>(last_), 100 * frac, cells,
                  rate, duration_text(left).c_str(), then.c_str());
    out_ << buf << std::flush;
  }
}

void Progress::finish() { break_line(); }

void Progress::break_line() {
  if (open_) out_ << "\n" << std::flush;
  open_ = false;
}

}  // namespace cellform::app
