// A graph's edges joined into polylines, one per unbranched run: how modellers want curves.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// The edges of a graph on `n` vertices (pairs a, b < n; a == b is skipped) as polylines: maximal walks
/// whose inner vertices have exactly two edge ends, so a vein tree gives one polyline per branch between
/// tips, forks and roots. Every other edge is in exactly one polyline, as vertex sequences. A cycle of
/// such vertices alone is one closed polyline that starts and ends at its smallest vertex. A polyline
/// follows its edges' direction (a -> b) where its first edge allows. Deterministic: in the order of the
/// vertices it starts from, then of their edges.
std::vector<std::vector<Index>> polylines(std::size_t n, std::span<const std::array<Index, 2>> edges);

}  // namespace cellform::core
