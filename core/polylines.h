// A graph's edges joined into polylines, one per unbranched run: how modellers want curves.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// The edges of a graph on `n` vertices (directed pairs a -> b, a, b < n; a == b is skipped) as
/// polylines: maximal walks along the edges' direction whose inner vertices have exactly two edge ends, one
/// in and one out. A vein tree (edges child -> parent) gives one polyline per branch, from a tip or fork
/// towards the root, ending at the next fork, root, or node where two edges meet head to head. Every
/// other edge is in exactly one polyline, as vertex sequences. A directed cycle of such vertices alone is
/// one closed polyline that starts and ends at its smallest vertex. Deterministic: in the order of the
/// vertices it starts from, then of their edges.
std::vector<std::vector<Index>> polylines(std::size_t n, std::span<const std::array<Index, 2>> edges);

}  // namespace cellform::core
