// One step of the cell system as separate phases, and a Simulation that runs them in order.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "cells/cells.h"
#include "cells/params.h"
#include "core/random.h"
#include "core/spatial_index.h"

namespace cellform::cells {

/// Rule functions supplied by a script (or C++); empty functions mean "use the built-in rule".
/// They are called serially, in cell index order, so they may be impure without breaking determinism.
struct Rules {
  /// Overrides the division trigger: return true if cell i divides this step.
  std::function<bool(const Cells&, Index)> divides;
  /// Split direction of cell i (SplitDirection::rule); need not be normalised, must not be zero.
  std::function<Vec3(const Cells&, Index)> split_direction;
  /// Where a daughter of cell `mother` that division would put at `daughter` (model units) goes instead,
  /// e.g. not across an obstacle surface; empty: where division puts it.
  std::function<Vec3(const Cells&, Index mother, const Vec3& daughter)> place;
};

/// A seeded random unit direction in the plane of cell i's three closest links (division direction "tangent":
/// the sheet grows within itself); any direction where the links span no plane.
Vec3 random_tangent(const Cells& cells, Index i, core::StreamRng& rng);

/// Recomputes the k nearest links of every cell (exact, ties by index), using `grid` as scratch.
void update_links(Cells& cells, const Params& params, core::PointGrid& grid, int threads);

/// Acceleration of every cell from Eqs. 2-6 with the weights of its type, into cells.acceleration.
/// Vein cells also act on their vein parent and children (cohesion) and grandparent and grandchildren
/// (separation) with the vein factors. Fixed cells get zero. Reads links; writes only its own slot.
void compute_accelerations(Cells& cells, const Params& params, const VeinChildren& children, int threads);

/// Applies drag (Eq. 7) and moves cells by one time step. Fixed cells do not move. Throws
/// core::SimulationDiverged naming the step and cell id, before any position changes, if an
/// acceleration or new velocity is NaN, infinite or faster than params.max_speed.
void integrate(Cells& cells, const Params& params, std::uint64_t step, int threads);

/// Ages every cell by one step and divides those whose trigger fires, in index order. A daughter is
/// placed half a rest length from its mother along the split direction (a split axis (axis, radial,
/// circumferential, a rule's vector) has no sign: the daughter goes either way along it, by a seeded draw), is a
/// general cell, copies the mother's velocity, generation + 1, attributes and links; both get age 0. Cells of every
/// type divide, vein and petiole cells too (the paper has only general cells divide); their daughters are general,
/// not fixed, with no vein parent (the vein radius and order they copy are cleared by the next canalisation pass
/// or, between passes, by forms::Scene), and canalisation may make them vein cells again. Stops at
/// max_cells: when more cells would divide than it leaves room for, a seeded choice of them (by seed, step and id,
/// spread over the form) does. Randomness comes from (seed, step, cell id) only. Returns the number of divisions.
/// `grid` must index the current positions (trigger = neighbours counts cells within the radius through it); the
/// built-in triggers are evaluated on up to `threads` threads, the rules serially. Throws core::InvalidInput naming the
/// cell if a split direction rule returns a zero or non-finite vector.
std::size_t divide(Cells& cells, const Params& params, const Rules& rules, std::uint64_t seed, std::uint64_t step,
                   const core::PointGrid& grid, int threads = 1);

/// What one step did.
struct StepReport {
  std::uint64_t step = 0;
  std::size_t cells = 0;
  std::size_t divisions = 0;
  double max_speed = 0;  ///< model units per time unit
};

/// The stateful stepper: owns the cells and the scratch needed between steps.
/// Step order: links -> accelerations -> (external forces) -> integrate -> (constraints) -> divide.
class Simulation {
 public:
  Simulation(Params params, std::uint64_t seed);

  Cells& cells() { return cells_; }
  const Cells& cells() const { return cells_; }
  const Params& params() const { return params_; }
  Rules& rules() { return rules_; }
  std::uint64_t step_count() const { return step_; }
  void set_step_count(std::uint64_t step) { step_ = step; }
  void set_threads(int threads) { threads_ = threads; }
  int threads() const { return threads_; }

  /// One whole step with optional hooks: `forces` may add to cells.acceleration before integration,
  /// `constrain` may move cells after it (obstacles). Reorders cells in memory (spatially, by
  /// core::spatial_order) at the start of every 32nd step, including the first: indices change, ids do not.
  /// On core::SimulationDiverged the cells keep the positions of the last good step (the step count is
  /// not advanced; links, accelerations and a reorder of this step may have been applied). Any other
  /// exception (a rule or a hook that throws) leaves the cells part way through the step: go on from a
  /// copy or a checkpoint taken before it, as `cellform run` does.
  StepReport step(const std::function<void(Cells&)>& forces = {}, const std::function<void(Cells&)>& constrain = {});

  /// Links the cells as they lie now, for output (surfaces, frames, checkpoints): a step links them before
  /// it moves and divides them, so after a step a daughter holds a copy of her mother's row and no row holds
  /// her. Changes no later step: every step links the cells again from their positions alone.
  void relink() { update_links(cells_, params_, grid_, threads_); }

 private:
  Params params_;
  std::uint64_t seed_;
  Cells cells_;
  Rules rules_;
  core::PointGrid grid_;
  VeinChildren children_;  // scratch: vein children of the current step
  std::uint64_t step_ = 0;
  int threads_ = 0;
};

}  // namespace cellform::cells
