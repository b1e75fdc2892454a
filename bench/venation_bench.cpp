// Benchmarks of auxin canalisation: time per step at fixed populations, and its share of a cell step.
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "bench/bench.h"
#include "cells/simulation.h"
#include "forms/shapes.h"
#include "venation/canalisation.h"

namespace cellform::bench {

namespace {

struct Sheet {
  std::unique_ptr<cells::Simulation> sim;
  venation::Workspace ws;
  venation::Params params;
};

/// A flat disc of about n cells with links computed by one cell step, a petiole at its rim, and
/// veins grown for 40 steps so both phases have work.
Sheet& sheet(std::size_t n) {
  static std::map<std::size_t, Sheet> cache;
  Sheet& s = cache[n];
  if (s.sim) return s;
  cells::Params p;
  p.division.trigger = cells::DivisionTrigger::none;
  p.division.max_cells = n * 2;
  s.sim = std::make_unique<cells::Simulation>(p, 1);
  const double radius = std::sqrt(static_cast<double>(n) * std::sqrt(3.0) / 2.0 / M_PI);
  for (const core::Vec3& q : forms::hex_disc(core::Vec3::Zero(), core::Vec3::UnitZ(), radius, 1.0))
    cells::add_cell(s.sim->cells(), q);
  s.sim->cells().type[0] = cells::CellType::petiole;
  s.sim->set_threads(2);
  s.sim->step();
  s.params.threshold = 40;
  for (int i = 0; i < 40; ++i) venation::canalise(s.sim->cells(), s.params, {}, s.ws, 2);
  return s;
}

double canalise_ms(std::size_t n, int steps) {
  Sheet& s = sheet(n);
  venation::Params frozen = s.params;
  frozen.threshold = 1e18;  // measure flow without changing the vein pattern between repetitions
  const auto a = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) venation::canalise(s.sim->cells(), frozen, {}, s.ws, 2);
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count() / steps;
}

double cell_step_ms(std::size_t n, int steps) {
  Sheet& s = sheet(n);
  const auto a = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) s.sim->step();
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count() / steps;
}

const Register r1{{"venation.canalise.50k", "ms",
                   "one canalisation step (both phases and promotion, 2 threads), 50,000 cells", 5,
                   [] { return canalise_ms(50000, 20); }}};
const Register r2{{"venation.canalise.1m", "ms", "one canalisation step (2 threads), 1,000,000 cells", 3,
                   [] { return canalise_ms(1000000, 2); }}};
const Register r3{{"venation.share.50k", "ratio", "canalisation time / cell step time, both on 2 threads, 50,000 cells",
                   5, [] { return canalise_ms(50000, 10) / cell_step_ms(50000, 10); }}};
const Register r4{{"venation.share.1m", "ratio",
                   "canalisation time / cell step time, both on 2 threads, 1,000,000 cells", 3,
                   [] { return canalise_ms(1000000, 2) / cell_step_ms(1000000, 2); }}};

}  // namespace

}  // namespace cellform::bench
