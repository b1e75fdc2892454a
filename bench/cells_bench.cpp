// Benchmarks of the cell system: steps per second at fixed populations, memory per cell, growth time.
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "core/random.h"

#include "bench/bench.h"
#include "cells/simulation.h"
#include "forms/shapes.h"

namespace cellform::bench {

namespace {

using core::Vec3;

/// A flat hexagonal sheet of about n cells, slightly perturbed so forces are not all zero.
std::unique_ptr<cells::Simulation> sheet(std::size_t n, bool grow) {
  cells::Params p;
  p.weights[0].separation = 0.05;
  p.drag = Vec3(0.9, 0.9, 0.6);
  p.division.trigger = grow ? cells::DivisionTrigger::age : cells::DivisionTrigger::none;
  p.division.division_age = 8;
  p.division.max_cells = grow ? 20000 : n * 2;
  auto sim = std::make_unique<cells::Simulation>(p, 7);
  const double radius = std::sqrt(static_cast<double>(n) * std::sqrt(3.0) / 2.0 / M_PI);
  core::Rng rng(3);
  for (const Vec3& q : forms::hex_disc(Vec3::Zero(), Vec3::UnitZ(), radius, 1.0))
    cells::add_cell(sim->cells(), q + 0.05 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
  return sim;
}

double steps_per_second(std::size_t n, int threads, int steps) {
  static std::map<std::size_t, std::unique_ptr<cells::Simulation>> cache;
  auto& sim = cache[n];
  if (!sim) {
    sim = sheet(n, false);
    sim->set_threads(2);
    for (int i = 0; i < 3; ++i) sim->step();  // warm up: links, memory order
  }
  sim->set_threads(threads);
  const auto a = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) sim->step();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  return steps / s;
}

const Register r1{{"cells.step.50k.t1", "steps/s", "steps per second, 50,000 cells, fixed population, 1 thread", 5,
                   [] { return steps_per_second(50000, 1, 20); }}};
const Register r2{{"cells.step.50k.t2", "steps/s", "steps per second, 50,000 cells, fixed population, 2 threads", 5,
                   [] { return steps_per_second(50000, 2, 20); }}};
const Register r3{{"cells.step.1m.t1", "steps/s", "steps per second, 1,000,000 cells, fixed population, 1 thread", 3,
                   [] { return steps_per_second(1000000, 1, 2); }}};
const Register r4{{"cells.step.1m.t2", "steps/s", "steps per second, 1,000,000 cells, fixed population, 2 threads", 3,
                   [] { return steps_per_second(1000000, 2, 3); }}};
const Register r5{{"cells.memory.1m", "bytes/cell",
                   "resident memory added by a 1,000,000-cell simulation after 3 steps, per cell", 1, [] {
                     const double before = current_rss_bytes();
                     auto sim = sheet(1000000, false);
                     for (int i = 0; i < 3; ++i) sim->step();
                     const double peak = peak_rss_bytes();
                     const double after = current_rss_bytes();
                     (void)peak;
                     return (after - before) / static_cast<double>(sim->cells().size());
                   }}};
const Register r6{
    {"cells.grow.20k", "s CPU", "CPU time to grow a disc of about 160 cells to 20,000 (division by age)", 3, [] {
       auto sim = sheet(160, true);
       const double a = process_cpu_seconds();
       while (sim->cells().size() < 20000) sim->step();
       return process_cpu_seconds() - a;
     }}};

}  // namespace

}  // namespace cellform::bench
