// Maximal unbranched walks of a graph.
#include "core/polylines.h"

#include <algorithm>

namespace cellform::core {

std::vector<std::vector<Index>> polylines(std::size_t n, std::span<const std::array<Index, 2>> edges) {
  // incidence (CSR): for each vertex its edge ends in edge order
  std::vector<std::size_t> start(n + 1, 0);
  for (const auto& [a, b] : edges)
    if (a != b && a < n && b < n) {
      ++start[a + 1];
      ++start[b + 1];
    }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::size_t> incident(start[n]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto [a, b] = edges[e];
      if (a == b || a >= n || b >= n) continue;
      incident[fill[a]++] = e;
      incident[fill[b]++] = e;
    }
  }
  auto degree = [&](Index v) { return start[v + 1] - start[v]; };
  // where a polyline ends: a tip, a fork, or a vertex where the direction turns (a root with two
  // children, a node with two parents)
  auto stop = [&](Index v) {
    if (degree(v) != 2) return true;
    const std::size_t e1 = incident[start[v]], e2 = incident[start[v] + 1];
    return (edges[e1][1] == v) == (edges[e2][1] == v);
  };
  auto other = [&](std::size_t e, Index v) { return edges[e][0] == v ? edges[e][1] : edges[e][0]; };
  std::vector<std::uint8_t> used(edges.size(), 0);
  std::vector<std::vector<Index>> out;
  // from vertex v along edge e until a vertex that does not have exactly two edge ends (or back at v)
  auto walk = [&](Index v, std::size_t e) {
    std::vector<Index> line{v};
    const bool forward = edges[e][0] == v;
    for (;;) {
      used[e] = 1;
      const Index w = other(e, line.back());
      line.push_back(w);
      if (stop(w) || w == v) break;
      const std::size_t e1 = incident[start[w]], e2 = incident[start[w] + 1];
      e = used[e1] ? e2 : e1;
      if (used[e]) break;
    }
    if (!forward) std::reverse(line.begin(), line.end());
    out.push_back(std::move(line));
  };
  for (Index v = 0; v < n; ++v) {
    if (!stop(v)) continue;
    for (std::size_t k = start[v]; k < start[v + 1]; ++k)
      if (!used[incident[k]]) walk(v, incident[k]);
  }
  for (Index v = 0; v < n; ++v)  // what is left: directed cycles through vertices with two edge ends each
    for (std::size_t k = start[v]; k < start[v + 1]; ++k)
      if (!used[incident[k]]) walk(v, incident[k]);
  return out;
}

}  // namespace cellform::core
