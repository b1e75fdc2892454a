// The scene: the cell simulation together with its obstacles, attractors and petioles, stepped as one.
#pragma once

#include <cstdint>
#include <vector>

#include "cells/simulation.h"
#include "forms/attractors.h"
#include "forms/obstacles.h"

namespace cellform::forms {

/// Everything a scene is made of, as plain data.
struct SceneDescription {
  cells::Params cells;               ///< the cell system
  Obstacles obstacles;               ///< solids and surfaces cells cannot pass
  std::vector<Attractor> attractors; ///< points pulling cells
  double obstacle_margin = 0.0;      ///< model units cells keep from obstacle surfaces; 0 = 1% of rest length
};

/// Throws core::InvalidInput naming the parameter for anything out of range.
void validate(const SceneDescription& description);

/// Turns the cell nearest to `at` into a petiole (fixed if asked); adds a new cell there if the
/// nearest is farther than half a rest length or there is none. Returns its index.
core::Index make_petiole(cells::Cells& cells, const Vec3& at, bool fixed, double rest_length);

/// A scene that steps: cells move under their forces and the attractors, then obstacles push them back.
class Scene {
 public:
  /// Validates `description` (core::InvalidInput) and starts with no cells.
  Scene(SceneDescription description, std::uint64_t seed);

  cells::Simulation& simulation() { return sim_; }
  const cells::Simulation& simulation() const { return sim_; }
  const SceneDescription& description() const { return desc_; }

  /// One step of everything; throws core::SimulationDiverged (state is then that of the last good step).
  cells::StepReport step();

 private:
  SceneDescription desc_;
  cells::Simulation sim_;
  PreparedObstacles obstacles_;
  std::vector<Vec3> previous_;
};

}  // namespace cellform::forms
