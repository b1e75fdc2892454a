// Parameters of the cell system, each with its unit and default (cell-division venation paper).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/types.h"

namespace cellform::cells {

using core::Vec3;

/// How velocities follow from forces (section "Basic Cell Behaviour").
enum class Integrator {
  velocity,               ///< velocity-only: v = a (drag applied), x += v dt
  velocity_acceleration,  ///< semi-implicit Euler: v += a dt, v *= drag, x += v dt
};

/// Weights of the intercellular forces for one cell type (accelerations are weight * kernel).
struct ForceWeights {
  double spring = 1.0;      ///< Eq. 2, per time unit squared
  double planar = 0.5;      ///< Eq. 3, per time unit squared, towards the plane of the three closest neighbours
  double cohesion = 0.0;    ///< Eq. 4, towards neighbours (model units^2 per time unit^2)
  double separation = 0.0;  ///< Eq. 5, away from neighbours of neighbours (model units^2 per time unit^2)
};

/// What triggers a division (section "Cell Proliferation").
enum class DivisionTrigger {
  none,        ///< no growth
  age,         ///< a cell divides when its age reaches division_age steps
  neighbours,  ///< marginal growth: a cell divides when fewer than min_neighbours cells lie within radius
};

/// Which way a dividing cell splits.
enum class SplitDirection {
  random,   ///< uniform growth: a random unit vector per division (seeded)
  tangent,  ///< uniform growth within the sheet: random, in the plane of the three closest neighbours
  /// Along `axis`. This gives the paper's "uniform anisotropic growth" only under marginal growth: with trigger
  /// neighbours a disc of radius 3 grown to 1,500 cells along x had 3.4 to 4.0 times the spread (standard
  /// deviation) in x as in y.
  /// With trigger age (the paper's case) the sheet, point cells whose links change every step, loses the
  /// orientation of each insertion and grows round: a spread ratio of 0.98 to 1.06.
  axis,
  radial,           ///< away from `centre` (a field)
  circumferential,  ///< around the line through `centre` along `axis` (a field)
  rule,             ///< non-uniform anisotropic: a rule function supplies the direction
};

/// Default radius of the neighbours trigger, in rest lengths (scripts scale it by cells.rest_length).
inline constexpr double kDivisionRadius = 1.25;

/// When and how cells divide (section "Cell Proliferation").
struct DivisionParams {
  /// what makes a cell divide
  DivisionTrigger trigger = DivisionTrigger::age;
  std::uint32_t division_age = 20;  ///< steps between divisions of a cell (trigger = age)
  double radius = kDivisionRadius;  ///< model units; neighbourhood counted for trigger = neighbours (the default suits
                                    ///< rest_length 1: scale it with a rest length of your own, as scripts do)
  int min_neighbours = 6;           ///< divide when fewer cells than this lie within radius
  std::uint32_t min_age = 5;        ///< steps a cell waits after its birth or division before dividing again
  double probability = 1.0;         ///< chance (0..1] that a triggered cell divides this step (seeded)
  /// direction of the split (the daughters' offset)
  SplitDirection direction = SplitDirection::random;
  Vec3 axis = Vec3::UnitX();         ///< split axis (axis, circumferential): a direction, any non-zero length
  Vec3 centre = Vec3::Zero();        ///< field centre (radial, circumferential), model units
  std::uint64_t max_cells = 100000;  ///< growth stops (no more divisions) at this many cells
};

/// All parameters of the cell system.
struct Params {
  double rest_length = 1.0;  ///< d of Eq. 2: target distance between linked cells, model units
  int neighbours = 6;        ///< k: links per cell (the six closest in the paper); at least 3
  /// Links reach only cells within link_range * rest_length ("if available, the six closest"); 0 = the k
  /// nearest at any distance (rim cells then link across the sheet and pull the rim inward). That holds for a
  /// sheet spaced at the rest length; in one packed closer than 1.5 / sqrt(3) = 0.87 rest lengths the second
  /// ring lies within 1.5 too, and the rim pulls inward either way (see kCohesionNear in forces.h).
  double link_range = 1.5;
  /// how a step moves the cells
  Integrator integrator = Integrator::velocity_acceleration;
  double time_step = 0.1;  ///< time units per step

  /// Force weights per cell type, indexed by CellType (general, petiole, vein).
  std::array<ForceWeights, 3> weights{};

  Vec3 unary = Vec3::Zero();  ///< Eq. 6: constant acceleration, e.g. gravity (model units / time^2)
  /// Eq. 7: factors (a, b, c) multiplying velocity each step, in [0, 1]. The paper also allows a factor above 1
  /// ("accelerated"); it is refused for stability, as it multiplies a cell's speed every step.
  Vec3 drag = Vec3(0.9, 0.9, 0.9);

  /// dimensionless: multiplies the cohesion weight between a vein cell and its vein parent and children
  double vein_cohesion_factor = 4.0;
  /// dimensionless: multiplies the separation weight between a vein cell and its grandparent and grandchildren
  double vein_separation_factor = 4.0;
  /// Whether cells can join vein trees (canalisation runs): only then does the stable time step count the
  /// straightening terms above and the vein cells' weights. The forces do not read it: they act on whatever
  /// vein parents and types the cells have.
  bool vein_trees = true;

  double max_speed = 1e6;  ///< model units per time unit; faster (or NaN) stops the run as diverged

  DivisionParams division;  ///< growth by division
};

/// Throws core::InvalidInput naming the parameter and what is allowed, for any value out of range
/// (rest length <= 0, k < 3, drag outside [0, 1], a time step that makes the integrator unstable, ...).
void validate(const Params& params);

/// Largest stable time step for these weights (explicit integration of the spring and planar terms).
double stable_time_step(const Params& params);

}  // namespace cellform::cells
