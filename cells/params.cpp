// Parameter checks with messages that name the script parameter and the allowed range.
#include "cells/params.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "cells/cells.h"
#include "core/errors.h"

namespace cellform::cells {

namespace {

std::string str(double v) { return core::number_text(v); }

std::string str(const Vec3& v) { return core::point_text(v.x(), v.y(), v.z()); }

[[noreturn]] void fail(const std::string& name, const std::string& allowed, const std::string& got) {
  throw core::InvalidInput(name + " must be " + allowed + ", got " + got);
}

void check_weight(const std::string& name, double v) {
  if (!(v >= 0) || !std::isfinite(v)) fail(name, "a finite number >= 0", str(v));
}

const char* const kTypeNames[3] = {"general", "petiole", "vein"};

// How a script names cell type t's force weights: cells.spring for general cells, cells.vein.spring for veins.
std::string weight_prefix(std::size_t t) { return t == 0 ? "cells." : std::string("cells.") + kTypeNames[t] + "."; }

// The Gershgorin bound of one cell type's linearised force field (1/time^2), and the script's name of its
// largest term. A spring or planar weight w contributes at most 2w (the cell and its neighbours moving in
// opposition); cohesion has stiffness w / r^2 beyond a rest length and w / rest^2 within it (it is linear
// there), separation w / r^2, counted at r = rest length (it acts on the second ring, farther away).
// Cells in a vein tree add the straightening terms (counted for every type: scripts may set types), when
// vein trees can form.
struct Stiffness {
  double lambda = 0;
  double largest = -1;
  std::string term;
};

Stiffness stiffness(const Params& p, std::size_t t) {
  const ForceWeights& w = p.weights[t];
  const double d2 = p.rest_length * p.rest_length;
  const std::string base = weight_prefix(t);
  const double vein = p.vein_trees ? 1.0 : 0.0;
  const std::pair<double, std::string> terms[] = {
      {2 * w.spring, base + "spring " + str(w.spring)},
      {2 * w.planar, base + "planar " + str(w.planar)},
      {2 * w.cohesion / d2, base + "cohesion " + str(w.cohesion)},
      {2 * w.separation / d2, base + "separation " + str(w.separation)},
      {vein * 2 * w.cohesion * p.vein_cohesion_factor / d2,
       base + "cohesion " + str(w.cohesion) + " times cells.vein_cohesion " + str(p.vein_cohesion_factor)},
      {vein * 2 * w.separation * p.vein_separation_factor / d2,
       base + "separation " + str(w.separation) + " times cells.vein_separation " + str(p.vein_separation_factor)}};
  Stiffness s;
  for (const auto& [l, name] : terms) {
    s.lambda += l;
    if (l > s.largest) {
      s.largest = l;
      s.term = name;
    }
  }
  return s;
}

// The largest stable step for a stiffness bound lambda (1/time^2).
double stable_step(double lambda, Integrator integrator) {
  if (!(lambda > 0)) return std::numeric_limits<double>::infinity();
  // semi-implicit Euler on x'' = -lambda x is stable for dt^2 lambda < 4 (drag <= 1 only helps);
  // velocity-only (x' = -lambda x, explicit Euler) needs dt lambda < 2
  if (integrator == Integrator::velocity_acceleration) return 2.0 / std::sqrt(lambda);
  return 2.0 / lambda;
}

// The largest bound over the cell types, with the largest single term of any type (the general weights
// first: per-type weights default to them, and a tie names the one the script most likely set).
Stiffness stiffest(const Params& p) {
  Stiffness best;
  for (std::size_t t = 0; t < p.weights.size(); ++t) {
    // vein cells come only from canalisation: without it their weights bound nothing (they refused a run in
    // millimetres for cells.vein.cohesion, a default of a section the script never wrote)
    if (t == static_cast<std::size_t>(CellType::vein) && !p.vein_trees) continue;
    Stiffness s = stiffness(p, t);
    best.lambda = std::max(best.lambda, s.lambda);
    if (s.largest > best.largest) {
      best.largest = s.largest;
      best.term = std::move(s.term);
    }
  }
  return best;
}

}  // namespace

double stable_time_step(const Params& params) { return stable_step(stiffest(params).lambda, params.integrator); }

void validate(const Params& params) {
  const Params& p = params;
  if (!(p.rest_length > 0) || !std::isfinite(p.rest_length))
    fail("cells.rest_length", "positive and finite (model units)", str(p.rest_length));
  if (p.neighbours < 3 || p.neighbours > 32)
    fail("cells.neighbours", "an integer from 3 to 32", std::to_string(p.neighbours));
  if (!(p.link_range == 0 || (p.link_range >= 1 && std::isfinite(p.link_range))))
    fail("cells.link_range", "0 (no limit) or a number >= 1 (rest lengths)", str(p.link_range));
  if (p.integrator != Integrator::velocity && p.integrator != Integrator::velocity_acceleration)
    fail("cells.integrator", "'velocity' or 'velocity_acceleration'", std::to_string(static_cast<int>(p.integrator)));
  if (!(p.time_step > 0) || !std::isfinite(p.time_step))
    fail("cells.time_step", "positive and finite (time units per step)", str(p.time_step));
  for (std::size_t t = 0; t < p.weights.size(); ++t) {
    const std::string base = weight_prefix(t);
    check_weight(base + "spring", p.weights[t].spring);
    check_weight(base + "planar", p.weights[t].planar);
    check_weight(base + "cohesion", p.weights[t].cohesion);
    check_weight(base + "separation", p.weights[t].separation);
  }
  if (!p.unary.allFinite()) fail("cells.unary", "a finite vector", str(p.unary));
  for (int a = 0; a < 3; ++a)
    if (!(p.drag[a] >= 0 && p.drag[a] <= 1)) fail("cells.drag", "factors in [0, 1] for each axis", str(p.drag));
  check_weight("cells.vein_cohesion", p.vein_cohesion_factor);
  check_weight("cells.vein_separation", p.vein_separation_factor);
  if (!(p.max_speed > 0)) fail("cells.max_speed", "positive (model units per time unit)", str(p.max_speed));

  const Stiffness stiff = stiffest(p);
  const double stable = stable_step(stiff.lambda, p.integrator);
  if (p.time_step > stable)
    throw core::InvalidInput(
        "cells.time_step " + str(p.time_step) + " is above the stable limit " + str(stable) +
        " for these force weights (" + (p.integrator == Integrator::velocity ? "velocity" : "velocity_acceleration") +
        " integrator; the largest term is " + stiff.term + "); use at most " + str(stable) + " or lower the weights");

  const DivisionParams& d = p.division;
  if (d.trigger != DivisionTrigger::none && d.trigger != DivisionTrigger::age &&
      d.trigger != DivisionTrigger::neighbours)
    fail("cells.division.trigger", "'none', 'age' or 'neighbours'", std::to_string(static_cast<int>(d.trigger)));
  if (!(d.probability > 0 && d.probability <= 1)) fail("cells.division.probability", "in (0, 1]", str(d.probability));
  if (!(d.radius > 0) || !std::isfinite(d.radius))
    fail("cells.division.radius", "positive and finite (model units)", str(d.radius));
  if (d.min_neighbours < 1) fail("cells.division.min_neighbours", "at least 1", std::to_string(d.min_neighbours));
  if (d.max_cells < 1) fail("cells.division.max_cells", "at least 1", std::to_string(d.max_cells));
  if (d.max_cells > core::kNoIndex - 1)
    fail("cells.division.max_cells", "at most " + std::to_string(core::kNoIndex - 1), std::to_string(d.max_cells));
  if (!d.centre.allFinite()) fail("cells.division.centre", "a finite point", str(d.centre));
  const bool needs_axis = d.direction == SplitDirection::axis || d.direction == SplitDirection::circumferential;
  if (needs_axis && (!d.axis.allFinite() || !(d.axis.squaredNorm() > 0)))
    fail("cells.division.axis", "a finite non-zero vector", str(d.axis));
}

}  // namespace cellform::cells
