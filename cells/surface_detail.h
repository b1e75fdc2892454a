// Private to cells/: the filling of small holes in the one-layer cell surface (surface_holes.cpp), used by
// triangulate() in surface.cpp. Not installed, not for users.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "cells/cells.h"

namespace cellform::cells::detail {

/// Fills the small holes the one-layer surface leaves where pruning took a crossing edge out of a pentagon
/// or hexagon of cells (see surface_holes.cpp): `sides` are every triangle side, sorted; `incidence` the
/// (side, triangle) pairs sorted by side, `inc_start` where each side's pairs begin. New triangles are
/// appended to `tris`, which is then sorted by smallest index (stable).
void fill_small_holes(const std::vector<Vec3>& pos, const std::vector<std::array<Index, 2>>& sides,
                      const std::vector<std::size_t>& inc_start,
                      const std::vector<std::pair<std::size_t, std::size_t>>& incidence,
                      std::vector<std::array<Index, 3>>& tris);

}  // namespace cellform::cells::detail
