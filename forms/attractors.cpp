// Attractor points: constant-magnitude accelerations towards given positions.
#include "forms/attractors.h"

#include <cmath>
#include <string>

#include "core/errors.h"

namespace cellform::forms {

void validate(const std::vector<Attractor>& attractors) {
  for (std::size_t i = 0; i < attractors.size(); ++i) {
    const Attractor& a = attractors[i];
    const std::string name = "attractor " + std::to_string(i);
    if (!a.position.allFinite()) throw core::InvalidInput(name + ": position has a non-finite coordinate");
    if (!std::isfinite(a.strength))
      throw core::InvalidInput(name + ": strength must be a finite number (model units per time unit squared)");
    if (!std::isfinite(a.radius))
      throw core::InvalidInput(name + ": radius must be a finite number (model units; <= 0 for unlimited range)");
  }
}

void apply_attractors(cells::Cells& cells, const std::vector<Attractor>& attractors) {
  if (attractors.empty()) return;
  const std::size_t n = cells.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (cells.fixed[i]) continue;
    Vec3 sum = Vec3::Zero();
    for (const Attractor& a : attractors) {
      const Vec3 d = a.position - cells.position[i];
      const double dist = d.norm();
      if (dist <= kAttractorDeadZone) continue;
      if (a.radius > 0 && dist > a.radius) continue;
      sum += (a.strength / dist) * d;
    }
    cells.acceleration[i] += sum;
  }
}

}  // namespace cellform::forms
