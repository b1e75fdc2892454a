// Splitting a file's polygon faces into triangles.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// Ear clipping gives up on polygons that are not convex past this many corners (its time grows with the
/// square of the corners, or worse): the readers refuse such a face, naming it.
inline constexpr std::size_t kMaxConcaveCorners = 1024;

/// Splits a polygon (corners in order, in 3-D, about planar) into corners.size() - 2 triangles, as
/// indices into `corners`, each wound as the polygon is. A convex polygon (every corner turning left, once
/// round) is fanned from its first corner; another (with corners in line too, up to 16 kMaxConcaveCorners corners,
/// so that no triangle has zero area) is cut by ear clipping in the coordinate plane most nearly its own (by its Newell
/// normal; for a planar face, its plane), so that a concave face, an L or a notched outline as modellers export n-gons,
/// is covered where it is and nowhere else. What clipping cannot cut (a polygon that crosses itself, or has no area)
/// has its rest fanned. Deterministic. Empty for fewer than 3 corners; `concave_too_large` is set (and nothing
/// returned) for a polygon that is not convex and has more than kMaxConcaveCorners corners.
std::vector<std::array<std::uint32_t, 3>> triangulate_polygon(std::span<const Vec3> corners,
                                                              bool* concave_too_large = nullptr);

}  // namespace cellform::core
