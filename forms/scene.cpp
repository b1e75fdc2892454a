// Scene stepping: forces, attractors, integration, obstacles, division.
#include "forms/scene.h"

#include <limits>

#include "core/errors.h"

namespace cellform::forms {

void validate(const SceneDescription& description) {
  cells::validate(description.cells);
  validate(description.obstacles);
  validate(description.attractors);
  if (!(description.obstacle_margin >= 0) || !std::isfinite(description.obstacle_margin))
    throw core::InvalidInput("obstacle margin must be a finite number >= 0 (model units)");
}

core::Index make_petiole(cells::Cells& cells, const Vec3& at, bool fixed, double rest_length) {
  if (!at.allFinite()) throw core::InvalidInput("petiole position must be finite");
  core::Index best = core::kNoIndex;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double d2 = (cells.position[i] - at).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<core::Index>(i);
    }
  }
  if (best == core::kNoIndex || best_d2 > 0.25 * rest_length * rest_length)
    return cells::add_cell(cells, at, cells::CellType::petiole, fixed);
  cells.type[best] = cells::CellType::petiole;
  cells.fixed[best] = fixed ? 1 : 0;
  return best;
}

Scene::Scene(SceneDescription description, std::uint64_t seed)
    : desc_((validate(description), std::move(description))), sim_(desc_.cells, seed), obstacles_(desc_.obstacles) {}

cells::StepReport Scene::step() {
  const int threads = sim_.threads();
  const double margin = desc_.obstacle_margin > 0 ? desc_.obstacle_margin : 0.01 * desc_.cells.rest_length;
  const bool has_obstacles = !desc_.obstacles.empty();
  return sim_.step(
      [&](cells::Cells& c) {
        if (has_obstacles) previous_ = c.position;
        if (!desc_.attractors.empty()) apply_attractors(c, desc_.attractors);
      },
      [&](cells::Cells& c) {
        if (has_obstacles) obstacles_.apply(c, previous_, margin, threads);
      });
}

}  // namespace cellform::forms
