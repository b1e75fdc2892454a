// Auxin sources for marginal leaf growth: precomputed once by dart throwing, revealed as the margin passes them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "venation/leaf_shape.h"

namespace cellform::venation {

/// The most growth steps (from initial_scale to final_scale by scale_step) any growth mode allows.
inline constexpr double kMaxGrowthSteps = 1e7;

/// The growth scales of marginal growth, one per step: sigma_0 = initial_scale, sigma_{k+1} =
/// min(final_scale, sigma_k + scale_step) up to the first that equals final_scale (Section 3.3 of
/// Runions et al. 2005: sigma_{t + Delta t} = sigma_t + Delta sigma). These are the bits Colonisation
/// starts its step k with. Throws core::InvalidInput naming colonisation.scale_step if growth would take
/// more than 10^7 steps.
std::vector<double> marginal_scales(double initial_scale, double final_scale, double scale_step);

/// Parameters of precompute_marginal_sources().
struct MarginalSourceParams {
  double birth_distance = 10;    ///< b_s, model units: accepted darts are farther than this from each other
  double darts_per_area = 2e-4;  ///< rho: darts per unit area per step (all steps' darts thrown at once)
  std::uint64_t seed = 1;        ///< the darts derive from this (a stream of their own)
  int threads = 1;               ///< threads for the entry steps (0 = all cores); same result for any count
};

/// Precomputed sources grouped by the step at which the growing blade first contains them.
struct MarginalSources {
  std::vector<Vec2> points;        ///< model units; by entry step, then in the order the darts were thrown
  std::vector<std::size_t> start;  ///< points [start[k], start[k + 1]) enter at step k; size = scales + 1
  std::size_t darts = 0;           ///< darts thrown to make them (in the whole box)
  std::size_t accepted = 0;        ///< darts accepted in the box (before keeping those the blade reaches)

  /// The points that enter at step k (none after the last growth step).
  std::span<const Vec2> entering(std::size_t k) const {
    if (k + 1 >= start.size()) return {};
    return std::span<const Vec2>(points).subspan(start[k], start[k + 1] - start[k]);
  }
};

/// Section 3.3 of Runions et al. 2005 for marginal growth: "we precompute the set of sources in a square
/// that embeds the maximum leaf size, and include new sources as they appear within the expanding leaf
/// contour". The set is the paper's dart throwing (Cook 1986) over the bounding box of the final blade
/// (`outline` scaled by scales.back() about `petiole`) for every step at once: rho darts per unit area
/// per step times scales.size() steps, uniform in the box, each accepted if farther than b_s from every
/// dart accepted before it (no veins exist yet: the b_v test is made when a source is revealed). So rho
/// keeps its meaning, darts per unit area per step (Figure 9f-h varies it under marginal growth), and a
/// run throws about as many darts as diffuse dart throwing into the growing blade would.
/// Each accepted point is then assigned the first step k at which the blade of scale scales[k] contains it
/// (OutlineIndex::contains of petiole + (q - petiole) / scales[k], as the colonisation's blade test),
/// found from the crossings of the ray from the petiole through q with the outline (so a point that a
/// notch uncovers later is found at its first entry) and confirmed by that test; points the final blade
/// never contains are dropped. Memory and time are linear in the darts and the outline's vertices.
/// Throws core::InvalidInput naming colonisation.darts if more than 10^9 darts would be thrown.
MarginalSources precompute_marginal_sources(const Outline& outline, const Vec2& petiole,
                                            const std::vector<double>& scales, const MarginalSourceParams& params);

}  // namespace cellform::venation
