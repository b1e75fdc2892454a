// Benchmarks of the cell system: steps per second at fixed populations, memory per cell, growth time.
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "core/random.h"

#include "bench/bench.h"
#include "cells/simulation.h"
#include "cells/surface.h"
#include "forms/shapes.h"

namespace cellform::bench {

namespace {

using core::Vec3;

/// A flat hexagonal sheet of about n cells, slightly perturbed so forces are not all zero.
/// `division`, if given, replaces the division parameters.
std::unique_ptr<cells::Simulation> sheet(std::size_t n, bool grow, const cells::DivisionParams* division = nullptr) {
  cells::Params p;
  p.weights[0].separation = 0.05;
  p.drag = Vec3(0.9, 0.9, 0.6);
  p.division.trigger = grow ? cells::DivisionTrigger::age : cells::DivisionTrigger::none;
  p.division.division_age = 8;
  p.division.max_cells = grow ? 20000 : n * 2;
  if (division) p.division = *division;
  auto sim = std::make_unique<cells::Simulation>(p, 7);
  const double radius = std::sqrt(static_cast<double>(n) * std::sqrt(3.0) / 2.0 / M_PI);
  core::Rng rng(3);
  for (const Vec3& q : forms::hex_disc(Vec3::Zero(), Vec3::UnitZ(), radius, 1.0)) {
    const double z = rng.uniform(-1, 1), y = rng.uniform(-1, 1), x = rng.uniform(-1, 1);  // in this order
    cells::add_cell(sim->cells(), q + 0.05 * Vec3(x, y, z));
  }
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
/// Steps per second of a 50,000-cell sheet whose every cell counts its neighbours within `radius` each step
/// (division by neighbours, min_neighbours 1000, so no count stops early; no cell divides: probability ~0).
double room_steps_per_second(double radius, int steps) {
  cells::DivisionParams d;
  d.trigger = cells::DivisionTrigger::neighbours;
  d.radius = radius;
  d.min_neighbours = 1000;
  d.min_age = 0;
  d.probability = 1e-12;
  d.max_cells = 100000;
  auto sim = sheet(50000, false, &d);
  sim->set_threads(2);
  for (int i = 0; i < 3; ++i) sim->step();
  const auto a = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) sim->step();
  return steps / std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

const Register r5a{
    {"cells.step.50k.room.1.5", "steps/s",
     "steps per second, 50,000 cells each counting the cells within 1.5 (division by neighbours), 2 threads", 3,
     [] { return room_steps_per_second(1.5, 10); }}};
const Register r5b{{"cells.step.50k.room.10", "steps/s",
                    "the same counting within 10 model units (about 360 cells each)", 3,
                    [] { return room_steps_per_second(10, 3); }}};
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

/// Seconds to triangulate a sheet of about n cells with k links per cell (link_range 0 with k > 6: every
/// cell links its k nearest, the dense case), after three steps; one layer (files) or every clique (shells).
double surface_seconds(std::size_t n, int k, bool one_layer) {
  static std::map<std::pair<std::size_t, int>, std::unique_ptr<cells::Simulation>> cache;
  auto& sim = cache[{n, k}];
  if (!sim) {
    sim = sheet(n, false);
    cells::Params p = sim->params();
    p.neighbours = k;
    p.link_range = k > 6 ? 0 : p.link_range;
    auto dense = std::make_unique<cells::Simulation>(p, 7);
    for (std::size_t i = 0; i < sim->cells().size(); ++i) cells::add_cell(dense->cells(), sim->cells().position[i]);
    dense->set_threads(2);
    for (int i = 0; i < 3; ++i) dense->step();
    sim = std::move(dense);
  }
  const auto a = std::chrono::steady_clock::now();
  const cells::Surface s = cells::triangulate(sim->cells(), one_layer);
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  if (s.triangles.empty()) throw std::runtime_error("the triangulation made no triangles");  // no time to report
  return t;
}

/// Seconds to triangulate a square lattice of n x n cells `spacing` model units apart, linked to their four
/// lattice neighbours only (every square is a quad to close), beside one small triangle of side 2 (its
/// sides must not be taken for the typical side: every quad's triangles would be "long").
double quad_lattice_seconds(int n, double spacing) {
  cells::Cells c;
  c.link_stride = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      cells::add_cell(c, core::Vec3(i * spacing, j * spacing, 0.01 * spacing * ((i * 7 + j * 3) % 5)));
  c.links.assign(c.size() * 4, core::kNoIndex);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto a = static_cast<std::size_t>(i * n + j);
      int k = 0;
      for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{-1, 0}, std::pair{0, -1}})
        if (i + di >= 0 && i + di < n && j + dj >= 0 && j + dj < n)
          c.links[a * 4 + static_cast<std::size_t>(k++)] = static_cast<core::Index>((i + di) * n + j + dj);
    }
  const auto first = static_cast<core::Index>(c.size());
  for (const core::Vec3& p : {core::Vec3(-100, 0, 0), core::Vec3(-98, 0, 0), core::Vec3(-99, 1.7, 0)}) {
    cells::add_cell(c, p);
    c.links.resize(c.size() * 4, core::kNoIndex);
  }
  for (core::Index k = 0; k < 3; ++k) {
    c.links[(first + k) * 4] = first + (k + 1) % 3;
    c.links[(first + k) * 4 + 1] = first + (k + 2) % 3;
  }
  const auto a = std::chrono::steady_clock::now();
  const cells::Surface s = cells::triangulate(c, true);
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  if (s.triangles.size() != static_cast<std::size_t>(2 * (n - 1) * (n - 1) + 1))
    throw std::runtime_error("the lattice gave " + std::to_string(s.triangles.size()) + " triangles, not " +
                             std::to_string(2 * (n - 1) * (n - 1) + 1));
  return t;
}

const Register r7{{"cells.surface.1m", "s", "triangulate 1,000,000 cells in one layer (cells.ply, cells.obj)", 3,
                   [] { return surface_seconds(1000000, 6, true); }}};
const Register r8{{"cells.surface.1m.cliques", "s", "the same keeping every 3-clique (printed shells)", 3,
                   [] { return surface_seconds(1000000, 6, false); }}};
const Register r9{{"cells.surface.20k.k32", "s", "one layer, 20,000 cells with their 32 nearest links each", 3,
                   [] { return surface_seconds(20000, 32, true); }}};
const Register r10{{"cells.surface.20k.k32.cliques", "s", "every clique, 20,000 cells with 32 nearest links each", 3,
                    [] { return surface_seconds(20000, 32, false); }}};
const Register r11{{"cells.surface.quads.40k.s10", "s",
                    "one layer, a 200 x 200 lattice of quads 10 units apart (closing every quad), and a small triangle",
                    3, [] { return quad_lattice_seconds(200, 10); }}};

}  // namespace

}  // namespace cellform::bench
