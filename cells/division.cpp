// Cell proliferation (section "Cell Proliferation"): triggers, split directions, daughters.
#include <Eigen/Geometry>  // cross products
#include <algorithm>
#include <cmath>
#include <string>

#include "cells/simulation.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "core/random.h"

namespace cellform::cells {

namespace {

// Degenerate field directions (a cell within 1e-12 rest lengths of the centre or the axis) fall back to a
// random one.
Vec3 normalised_or_random(const Vec3& v, double rest_length, core::StreamRng& rng) {
  const double n = v.norm();
  if (n > 1e-12 * rest_length && std::isfinite(n)) return v / n;
  return rng.unit_vector();
}

// A split axis has no sign: the daughter goes to either side of its mother with equal chance, so a field
// of axes (one axis, radial, circumferential, the auxin flow, a rule's) stretches the form both ways instead
// of pushing it along.
Vec3 either_way(const Vec3& axis, core::StreamRng& rng) { return rng.uniform() < 0.5 ? Vec3(-axis) : axis; }

Vec3 split_axis(const Cells& cells, const Params& params, const Rules& rules, Index i, core::StreamRng& rng) {
  const DivisionParams& d = params.division;
  switch (d.direction) {
    case SplitDirection::random:
      return rng.unit_vector();
    case SplitDirection::tangent:
      return random_tangent(cells, i, rng);
    case SplitDirection::axis:
      return d.axis.normalized();
    case SplitDirection::radial:
      return normalised_or_random(cells.position[i] - d.centre, params.rest_length, rng);
    case SplitDirection::circumferential:  // (the axis as a unit vector: any length is allowed)
      return normalised_or_random(d.axis.normalized().cross(cells.position[i] - d.centre), params.rest_length, rng);
    case SplitDirection::rule: {
      if (!rules.split_direction)
        throw core::InvalidInput("cells.division.direction is 'rule' but no split direction rule is set");
      const Vec3 v = rules.split_direction(cells, i);
      const double n = v.norm();
      if (!(n > 0) || !std::isfinite(n))
        throw core::InvalidInput("the split direction rule returned a zero or non-finite vector for cell " +
                                 std::to_string(cells.id[i]));
      return v / n;
    }
  }
  return rng.unit_vector();
}

Vec3 split_direction(const Cells& cells, const Params& params, const Rules& rules, Index i, core::StreamRng& rng) {
  const Vec3 axis = split_axis(cells, params, rules, i, rng);
  const SplitDirection mode = params.division.direction;
  return mode == SplitDirection::random || mode == SplitDirection::tangent ? axis : either_way(axis, rng);
}

}  // namespace

Vec3 random_tangent(const Cells& cells, Index i, core::StreamRng& rng) {
  const Vec3 r = rng.unit_vector();
  const Index* l = cells.links.data() + static_cast<std::size_t>(i) * static_cast<std::size_t>(cells.link_stride);
  if (cells.link_stride < 3 || l[0] == kNoIndex || l[1] == kNoIndex || l[2] == kNoIndex) return r;
  const Vec3 e1 = cells.position[l[1]] - cells.position[l[0]], e2 = cells.position[l[2]] - cells.position[l[0]];
  const Vec3 n = e1.cross(e2);
  const double len = n.norm();
  if (!(len > 1e-12 * e1.norm() * e2.norm())) return r;  // (relative: any unit of length)
  return normalised_or_random(r - r.dot(n / len) * (n / len), 1.0, rng);
}

std::size_t divide(Cells& cells, const Params& params, const Rules& rules, std::uint64_t seed, std::uint64_t step,
                   const core::PointGrid& grid, int threads) {
  const DivisionParams& d = params.division;
  const std::size_t n = cells.size();
  for (auto& a : cells.age) ++a;
  if (!rules.divides && d.trigger == DivisionTrigger::none) return 0;
  if (n >= d.max_cells) return 0;

  // The built-in triggers depend only on the state before this pass, so they are evaluated in
  // parallel; the rule (possibly impure) and the divisions themselves run serially in index order.
  thread_local std::vector<std::uint8_t> fires_storage;  // reused between steps
  std::vector<std::uint8_t>& fires = fires_storage;      // the caller's copy, also inside worker threads
  fires.assign(n, 0);
  // A count over a radius many grid cells wide visits every grid cell of its box (about (2 r / cell)^3): a
  // grid of cells half the radius wide visits 125 (the counts are exact with either).
  const core::PointGrid* count_grid = &grid;
  thread_local core::PointGrid wide_storage;
  if (!rules.divides && d.trigger == DivisionTrigger::neighbours && d.radius > 2 * grid.cell_size()) {
    wide_storage.build(cells.position, d.radius / 2);
    count_grid = &wide_storage;
  }
  if (!rules.divides) {
    core::parallel_for(n, threads, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t age = cells.age[i];
        if (age < d.min_age) continue;
        if (d.trigger == DivisionTrigger::age) {
          fires[i] = age >= d.division_age;
        } else {
          fires[i] = count_grid->count_within(cells.position[i], d.radius, static_cast<Index>(i), d.min_neighbours) <
                     d.min_neighbours;
        }
        // the chance, drawn here in parallel (a cell's stream depends only on the seed, the step and its id),
        // so the serial pass below sets up a stream only for the cells that divide
        if (fires[i] && d.probability < 1)
          fires[i] = core::StreamRng(core::stream_key(seed, step, cells.id[i])).uniform() < d.probability;
      }
    });
  }

  // the mothers, in index order (a rule sees only its own cell, so calling it for every cell first decides
  // as calling it between divisions did)
  thread_local std::vector<Index> mothers_storage;
  std::vector<Index>& mothers = mothers_storage;
  mothers.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const auto mother = static_cast<Index>(i);
    if (cells.age[i] < d.min_age) continue;  // a rule replaces the trigger, not the wait after a division
    if (rules.divides ? !rules.divides(cells, mother) : !fires[i]) continue;
    if (rules.divides && d.probability < 1 &&
        !(core::StreamRng(core::stream_key(seed, step, cells.id[i])).uniform() < d.probability))
      continue;  // (else decided above)
    mothers.push_back(mother);
  }
  // More than max_cells leaves room for: a seeded choice among them, not the first in memory order (the
  // cells are sorted along a space-filling curve: those lay in one corner of the form)
  const std::size_t room = static_cast<std::size_t>(d.max_cells - n);
  if (mothers.size() > room) {
    auto rank = [&](Index i) {
      return std::pair(core::mix64(core::stream_key(seed, step, cells.id[i]) ^ 0xc0ffee), i);
    };
    std::nth_element(mothers.begin(), mothers.begin() + static_cast<std::ptrdiff_t>(room), mothers.end(),
                     [&](Index a, Index b) { return rank(a) < rank(b); });
    mothers.resize(room);
    std::sort(mothers.begin(), mothers.end());
  }

  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  std::size_t divisions = 0;
  for (const Index mother : mothers) {
    const std::size_t i = mother;
    core::StreamRng rng(core::stream_key(seed, step, cells.id[i]));
    rng.uniform();  // the chance's draw, taken always, so directions do not depend on the probability
    const Vec3 dir = split_direction(cells, params, rules, mother, rng);

    Vec3 pos = cells.position[i] + (0.5 * params.rest_length) * dir;
    if (rules.place) pos = rules.place(cells, mother, pos);
    cells.position.push_back(pos);
    cells.velocity.push_back(Vec3(cells.velocity[i]));
    cells.acceleration.push_back(Vec3(cells.acceleration[i]));
    cells.age[i] = 0;
    cells.age.push_back(0);
    cells.generation[i] += 1;
    cells.generation.push_back(cells.generation[i]);
    cells.type.push_back(CellType::general);
    cells.fixed.push_back(0);
    cells.id.push_back(cells.next_id++);
    cells.vein_parent.push_back(kNoIndex);
    for (std::size_t j = 0; j < stride; ++j) cells.links.push_back(cells.links[i * stride + j]);
    for (auto& [name, values] : cells.attributes) values.push_back(values[i]);
    ++divisions;
  }
  return divisions;
}

}  // namespace cellform::cells
