// The scene: cells, veins, obstacles, attractors and petioles, stepped together.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cells/simulation.h"
#include "forms/attractors.h"
#include "forms/obstacles.h"
#include "venation/canalisation.h"

namespace cellform::forms {

/// A petiole: at `step` the cell nearest to `at` becomes a petiole (step 0 = before the first step).
struct PetioleSpec {
  Vec3 at = Vec3::Zero();  ///< model units
  bool fixed = true;       ///< the petiole does not move
  std::uint64_t step = 0;  ///< when it appears
  std::string origin;      ///< where it was asked for (e.g. "leaf.lua:12: "), prefixed to error messages
};

/// Everything a scene is made of, as plain data.
struct SceneDescription {
  cells::Params cells;                       ///< the cell system
  std::optional<venation::Params> venation;  ///< auxin canalisation; none = no veins
  std::string venation_origin;               ///< where venation was asked for, prefixed to its error messages
  bool split_along_auxin = false;            ///< divisions split along the local auxin flow
  std::vector<PetioleSpec> petioles;         ///< sinks of the auxin flow and roots of the veins
  Obstacles obstacles;                       ///< solids and surfaces cells cannot pass
  ObstacleNames obstacle_names;              ///< how messages name the obstacles (e.g. with their script line)
  std::vector<Attractor> attractors;         ///< points pulling cells
  double obstacle_margin = 0.0;              ///< model units cells keep from obstacle surfaces; 0 = 1% of rest length
};

/// Throws core::InvalidInput naming the parameter for anything out of range.
void validate(const SceneDescription& description);

/// Turns the cell nearest to `at` into a petiole (fixed if asked; a cell that was fixed stays fixed) and
/// makes it a root of the veins.
/// Adds a new cell there if there are no cells or the nearest is farther than half a rest length;
/// throws core::InvalidInput if the nearest is farther than three rest lengths (not on the form).
core::Index make_petiole(cells::Cells& cells, const Vec3& at, bool fixed, double rest_length);

/// A scene that steps: cells move under their forces and the attractors, obstacles push them back,
/// cells divide, new petioles appear, and auxin canalisation turns cells into veins.
class Scene {
 public:
  /// Validates `description` (core::InvalidInput) and starts with no cells.
  Scene(SceneDescription description, std::uint64_t seed);
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  cells::Simulation& simulation() { return sim_; }
  const cells::Simulation& simulation() const { return sim_; }
  const SceneDescription& description() const { return desc_; }
  /// The obstacles as the steps search them (for check_outside of cells placed later).
  const PreparedObstacles& obstacles() const { return obstacles_; }

  /// Makes the petioles due at the current step count (call once after placing the initial cells).
  /// Throws core::InvalidInput if a cell lies inside a solid obstacle (see check_outside), if a link the first
  /// step makes crosses a mesh obstacle (see check_links_clear), or if venation is on and no petiole exists
  /// before the first step.
  void start();

  /// Per-cell auxin source for venation (empty = venation.source for every cell).
  void set_source_rule(venation::SourceRule rule) { source_rule_ = std::move(rule); }

  /// One step of everything; throws core::SimulationDiverged (state is then that of the last good step).
  cells::StepReport step();

  /// Receives what the user should hear of but that stops nothing: two petiole{} of one step that landed on
  /// one cell (the two are one sink). None by default.
  void set_note(std::function<void(const std::string&)> note) { note_ = std::move(note); }

  /// What canalisation did in the last step.
  const venation::Report& venation_report() const { return vein_report_; }

 private:
  void apply_petioles(std::uint64_t step);

  SceneDescription desc_;
  std::uint64_t seed_;
  cells::Simulation sim_;
  PreparedObstacles obstacles_;
  std::vector<Vec3> previous_;
  venation::SourceRule source_rule_;
  venation::Workspace vein_ws_;
  venation::Report vein_report_;
  std::function<void(const std::string&)> note_;
};

}  // namespace cellform::forms
