// Do two triangles meet? The narrow phase of the printed-mesh checks and of the cell surface's hole filling.
// And the point of a triangle closest to a point (sources on surfaces, the volume a dilated sheet takes).
#pragma once

#include <array>

#include "core/types.h"

namespace cellform::core {

/// Do triangles a and b meet (share any point)? Moller's separating planes first; then, in general
/// position, an edge of one crossing the other; coplanar pairs in 2-D. Points within a rounding tolerance
/// (about 1e-6 of the largest coordinate, in the triangles' units, plus 1e-9 of the longest side) of the
/// other's plane count as on it, so coplanar neighbours written through float or decimal files do not meet.
/// Triangles that share a corner meet there: callers test such pairs with triangles_cross_beyond_corner().
bool triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

/// Does segment pq meet triangle t, with the same tolerance? For triangles that share one corner, which
/// cross (beyond that corner) iff the side of one opposite it meets the other. A triangle of no area meets
/// nothing.
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const std::array<Vec3, 3>& t);

/// Triangles a and b that share the corner a[i] == b[j] and no other: do they meet anywhere but there? They
/// do iff the side of one opposite that corner meets the other (segment_meets_triangle, its tolerance).
bool triangles_cross_beyond_corner(const std::array<Vec3, 3>& a, int i, const std::array<Vec3, 3>& b, int j);

/// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection, 5.1.5); of a
/// degenerate triangle, the closest point of its sides.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace cellform::core
