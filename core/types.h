// Vector types shared by every module (Eigen underneath).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace cellform::core {

using Vec3 = Eigen::Vector3d;  ///< a point or direction in model units
using Index = std::uint32_t;   ///< index of a cell or node in a flat array

/// Marks "no cell" in index arrays (parent of a root, empty neighbour slot).
inline constexpr Index kNoIndex = 0xffffffffu;

}  // namespace cellform::core
