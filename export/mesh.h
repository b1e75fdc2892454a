// The plain indexed triangle mesh that thickening produces, files carry and the checker inspects.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace cellform::exporters {

/// An indexed triangle mesh. thicken() produces it in millimetres, wound counter-clockwise seen from outside.
struct PrintableMesh {
  std::vector<core::Vec3> vertices;                     ///< positions (mm for thicken() output)
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices, counter-clockwise seen from outside
};

}  // namespace cellform::exporters
