// Parameter checks with messages that name the script parameter and the allowed range.
#include "cells/params.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/errors.h"

namespace cellform::cells {

namespace {

std::string str(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string str(const Vec3& v) {
  std::ostringstream s;  // not "(" + ...: GCC 12 warns falsely (-Wrestrict) on that concatenation
  s.precision(6);
  s << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return s.str();
}

[[noreturn]] void fail(const std::string& name, const std::string& allowed, const std::string& got) {
  throw core::InvalidInput(name + " must be " + allowed + ", got " + got);
}

void check_weight(const std::string& name, double v) {
  if (!(v >= 0) || !std::isfinite(v)) fail(name, "a finite number >= 0", str(v));
}

const char* const kTypeNames[3] = {"general", "petiole", "vein"};

}  // namespace

double stable_time_step(const Params& params) {
  // Largest eigenvalue of the linearised force field, bounded row-wise (Gershgorin): a spring or
  // planar weight w contributes at most 2w (the cell and its neighbours moving in opposition);
  // the 1/r kernels (cohesion, separation) have stiffness w / r^2, bounded at r = rest length.
  const double d2 = params.rest_length * params.rest_length;
  double lambda = 0;
  for (std::size_t t = 0; t < params.weights.size(); ++t) {
    const ForceWeights& w = params.weights[t];
    double l = 2 * (w.spring + w.planar) + 2 * (w.cohesion + w.separation) / d2;
    // vein cells (and the roots of vein trees) add the straightening terms
    l += 2 * (w.cohesion * params.vein_cohesion_factor + w.separation * params.vein_separation_factor) / d2;
    lambda = std::max(lambda, l);
  }
  if (!(lambda > 0)) return std::numeric_limits<double>::infinity();
  // semi-implicit Euler on x'' = -lambda x is stable for dt^2 lambda < 4 (drag <= 1 only helps);
  // velocity-only (x' = -lambda x, explicit Euler) needs dt lambda < 2
  if (params.integrator == Integrator::velocity_acceleration) return 2.0 / std::sqrt(lambda);
  return 2.0 / lambda;
}

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
    const std::string base = std::string("cells.weights.") + kTypeNames[t] + ".";
    check_weight(base + "spring", p.weights[t].spring);
    check_weight(base + "planar", p.weights[t].planar);
    check_weight(base + "cohesion", p.weights[t].cohesion);
    check_weight(base + "separation", p.weights[t].separation);
  }
  if (!p.unary.allFinite()) fail("cells.unary", "a finite vector", str(p.unary));
  for (int a = 0; a < 3; ++a)
    if (!(p.drag[a] >= 0 && p.drag[a] <= 1)) fail("cells.drag", "factors in [0, 1] for each axis", str(p.drag));
  check_weight("cells.vein_cohesion_factor", p.vein_cohesion_factor);
  check_weight("cells.vein_separation_factor", p.vein_separation_factor);
  if (!(p.max_speed > 0)) fail("cells.max_speed", "positive (model units per time unit)", str(p.max_speed));

  const double stable = stable_time_step(p);
  if (p.time_step > stable)
    throw core::InvalidInput("cells.time_step " + str(p.time_step) + " is above the stable limit " + str(stable) +
                             " for these force weights (" +
                             (p.integrator == Integrator::velocity ? "velocity" : "velocity_acceleration") +
                             " integrator); use at most " + str(stable) + " or lower the weights");

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
