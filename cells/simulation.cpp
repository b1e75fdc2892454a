// The stepper: (reorder) -> links -> accelerations -> hooks -> integrate -> hooks -> divide.
#include "cells/simulation.h"

#include "cells/integrate.h"

namespace cellform::cells {

namespace {
constexpr std::uint64_t kReorderInterval = 32;  // steps between spatial re-sorts of the cell arrays
}

Simulation::Simulation(Params params, std::uint64_t seed) : params_(std::move(params)), seed_(seed) {
  validate(params_);
  cells_.link_stride = params_.neighbours;
}

StepReport Simulation::step(const std::function<void(Cells&)>& forces, const std::function<void(Cells&)>& constrain) {
  const std::uint64_t step = step_ + 1;
  // Spatial memory order keeps neighbour lookups cache-friendly; done before the first step (cells come in
  // whatever order the caller added them) and every 32 steps after. Only indices change, never ids.
  if (step_ % kReorderInterval == 0) reorder(cells_, core::spatial_order(cells_.position, params_.rest_length));
  update_links(cells_, params_, grid_, threads_);
  children_ = vein_children(cells_);
  compute_accelerations(cells_, params_, children_, threads_);
  if (forces) forces(cells_);
  StepReport report;
  report.max_speed = integrate_and_measure(cells_, params_, step, threads_);
  if (constrain) constrain(cells_);
  // Cells moved since update_links built the grid: the neighbour-count trigger needs a fresh one.
  if (!rules_.divides && params_.division.trigger == DivisionTrigger::neighbours)
    grid_.build(cells_.position, params_.rest_length);
  report.divisions = divide(cells_, params_, rules_, seed_, step, grid_, threads_);
  step_ = step;
  report.step = step_;
  report.cells = cells_.size();
  return report;
}

}  // namespace cellform::cells
