// Attractor points: constant-magnitude pulls of cells towards (or, with negative strength, away from) a point.
#pragma once

#include <vector>

#include "cells/cells.h"
#include "core/types.h"

namespace cellform::forms {

using core::Vec3;

/// A point that pulls cells towards itself with a constant acceleration.
struct Attractor {
  Vec3 position = Vec3::Zero();  ///< model units
  double strength = 1.0;         ///< model units per time unit squared; negative repels
  double radius = 0.0;           ///< model units: cells farther away are not affected; <= 0 = unlimited range
};

/// Cells closer than this to an attractor feel no pull from it (the direction is undefined there), model units.
inline constexpr double kAttractorDeadZone = 1e-9;

/// Throws core::InvalidInput naming "attractor i" for a non-finite position, strength or radius.
void validate(const std::vector<Attractor>& attractors);

/// Adds to cells.acceleration of every non-fixed cell, for each attractor within range
/// (distance <= radius, or any distance when radius <= 0), an acceleration of magnitude `strength`
/// pointing at the attractor. Cells within kAttractorDeadZone of an attractor get nothing from it.
void apply_attractors(cells::Cells& cells, const std::vector<Attractor>& attractors);

}  // namespace cellform::forms
