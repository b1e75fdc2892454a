// Space colonisation: the checks of its parameters and of a leaf before a run starts.
#include <cmath>
#include <string>

#include "core/errors.h"
#include "venation/colonisation_impl.h"

namespace cellform::venation {

using core::InvalidInput;
using core::number_text;

namespace {

void require_distance(double v, const char* name) {
  if (!(v > 0 && std::isfinite(v)))
    throw InvalidInput(std::string("colonisation.") + name +
                       " must be a positive, finite distance in model units, got " + core::number_text(v));
}

}  // namespace

void validate(const ColonisationParams& p) {
  require_distance(p.source_birth_distance, "source_birth_distance");
  require_distance(p.vein_birth_distance, "vein_birth_distance");
  require_distance(p.kill_distance, "kill_distance");
  require_distance(p.node_distance, "node_distance");
  if (!(p.darts_per_area >= 0 && std::isfinite(p.darts_per_area)))
    throw InvalidInput("colonisation.darts_per_area must be a finite number >= 0 of darts per unit area per step");
  if (p.kill_distance < 0.5 * p.node_distance)
    throw InvalidInput("colonisation.kill_distance (" + number_text(p.kill_distance) +
                       ") must be at least half of colonisation.node_distance (" + number_text(p.node_distance) +
                       "): otherwise a vein tip can step over a source and circle around it forever");
  if (!(p.initial_scale > 0 && std::isfinite(p.initial_scale)))
    throw InvalidInput("colonisation.initial_scale must be a positive, finite scale factor");
  if (p.growth == GrowthMode::nonuniform) {
    if (p.growth_steps == 0) throw InvalidInput("colonisation.growth_steps must be at least 1 for nonuniform growth");
    for (const auto& [f, name] : {std::pair{&p.growth_x, "growth_x"}, std::pair{&p.growth_y, "growth_y"}}) {
      const std::string n = std::string("colonisation.") + name;
      if (f->y.empty() || f->y.size() != f->rate.size())
        throw InvalidInput(n + " needs as many rates as heights, at least one (a lookup table y -> REG)");
      for (std::size_t i = 0; i < f->y.size(); ++i) {
        if (!std::isfinite(f->y[i]) || !(f->rate[i] > 0 && std::isfinite(f->rate[i])))
          throw InvalidInput(n + ": entry " + std::to_string(i + 1) + " needs a finite height and a finite rate > 0");
        if (i > 0 && !(f->y[i] > f->y[i - 1]))
          throw InvalidInput(n + ".y must increase strictly (entry " + std::to_string(i + 1) +
                             " is not above the one before): the lookup table must be monotone in y");
      }
      const double top = *std::max_element(f->rate.begin(), f->rate.end());
      if (std::log(top) * static_cast<double>(p.growth_steps) > std::log(detail::kMaxNonuniformGrowth))
        throw InvalidInput(n + ": a rate of " + number_text(top) +
                           " per step over colonisation.growth_steps = " + std::to_string(p.growth_steps) +
                           " would grow the leaf more than a millionfold along that axis; use rates nearer 1 or "
                           "fewer steps");
      const double bottom = *std::min_element(f->rate.begin(), f->rate.end());
      if (-std::log(bottom) * static_cast<double>(p.growth_steps) > std::log(detail::kMaxNonuniformGrowth))
        throw InvalidInput(n + ": a rate of " + number_text(bottom) +
                           " per step over colonisation.growth_steps = " + std::to_string(p.growth_steps) +
                           " would shrink the leaf more than a millionfold along that axis; use rates nearer 1 or "
                           "fewer steps");
    }
  } else if (p.growth != GrowthMode::none) {
    if (!(p.final_scale >= p.initial_scale && std::isfinite(p.final_scale)))
      throw InvalidInput("colonisation.final_scale must be finite and at least colonisation.initial_scale");
    if (!(p.scale_step > 0 && std::isfinite(p.scale_step)))
      throw InvalidInput(
          "colonisation.scale_step must be a positive increase of the leaf size per step when the leaf grows");
    // a step below the rounding of the scale would never arrive (the run went on to max_steps, never quiet):
    // checked at the largest scale, whose rounding is the coarsest on the way; one of more than 10^7 steps, as
    // marginal growth refuses
    if (p.final_scale > p.initial_scale && !(p.final_scale + p.scale_step > p.final_scale))
      throw InvalidInput("colonisation.scale_step (" + number_text(p.scale_step) +
                         ") is too small to change the leaf's size (up to " + number_text(p.final_scale) +
                         ") in double precision: the growth would never end");
    if (p.final_scale > p.initial_scale && (p.final_scale - p.initial_scale) / p.scale_step > kMaxGrowthSteps)
      throw InvalidInput("colonisation.scale_step (" + number_text(p.scale_step) + ") is too small: growth from " +
                         number_text(p.initial_scale) + " to " + number_text(p.final_scale) +
                         " would take more than 10^7 steps");
  }
  if (p.max_steps == 0) throw InvalidInput("colonisation.max_steps must be at least 1");
  if (p.threads < 0) throw InvalidInput("colonisation.threads must be >= 0 (0 = all cores)");
  if (p.settle_steps == 0) throw InvalidInput("colonisation.settle_steps must be at least 1");
}

void validate(const Leaf& leaf) {
  validate_outline(leaf.outline, "leaf.outline");
  const OutlineIndex index(leaf.outline);
  const double size = (index.hi() - index.lo()).norm();
  auto inside = [&](const Vec2& q) {
    return index.contains(q) || distance_to_boundary(leaf.outline, q) <= 1e-6 * size;
  };
  if (!leaf.petiole.allFinite() || !inside(leaf.petiole))
    throw InvalidInput("leaf.petiole at (" + number_text(leaf.petiole.x()) + ", " + number_text(leaf.petiole.y()) +
                       ") lies outside the blade outline; it must be inside or on it");
  for (std::size_t i = 0; i < leaf.initial_nodes.size(); ++i)
    if (!leaf.initial_nodes[i].allFinite() || !inside(leaf.initial_nodes[i]))
      throw InvalidInput("leaf.initial_nodes[" + std::to_string(i + 1) + "] lies outside the blade outline");
  for (std::size_t i = 0; i < leaf.initial_sources.size(); ++i)
    if (!leaf.initial_sources[i].allFinite() || !inside(leaf.initial_sources[i]))
      throw InvalidInput("leaf.initial_sources[" + std::to_string(i + 1) + "] lies outside the blade outline");
}

}  // namespace cellform::venation
