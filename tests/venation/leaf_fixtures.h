// Small leaves and colonisation parameters shared by the space-colonisation tests.
#pragma once

#include "venation/colonisation.h"
#include "venation/leaf_shape.h"

namespace cellform::test {

/// A leaf whose blade is an outline of `kind`, `length` by `width` model units, with default settings.
inline venation::Leaf ellipse_leaf(double length, double width,
                                   venation::ShapeKind kind = venation::ShapeKind::ellipse) {
  venation::ShapeParams sp;
  sp.kind = kind;
  sp.length = length;
  sp.width = width;
  venation::Leaf leaf;
  leaf.outline = venation::make_outline(sp);
  return leaf;
}

/// Colonisation parameters of the small test runs: `type`, kill distance `kill`, birth distances `birth`,
/// unit segments, 0.01 darts per unit area, seed 42, at most 5,000 steps.
inline venation::ColonisationParams params(venation::VenationType type, double kill, double birth = 3) {
  venation::ColonisationParams p;
  p.type = type;
  p.kill_distance = kill;
  p.source_birth_distance = p.vein_birth_distance = birth;
  p.node_distance = 1;
  p.darts_per_area = 0.01;
  p.seed = 42;
  p.max_steps = 5000;
  return p;
}

}  // namespace cellform::test
