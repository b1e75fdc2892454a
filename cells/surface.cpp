// Triangles of the cell sheet: 3-cliques of the link graph, oriented consistently by a breadth-first walk.
#include "cells/surface.h"

#include <algorithm>
#include <deque>

namespace cellform::cells {

Surface triangulate(const Cells& cells) {
  const std::size_t n = cells.size();
  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  Surface s;

  // Undirected edges, (i < j), sorted and unique.
  auto& edges = s.edges;
  for (std::size_t i = 0; i < n; ++i) {
    const auto a = static_cast<Index>(i);
    for (std::size_t k = 0; k < stride && i * stride + k < cells.links.size(); ++k) {
      const Index b = cells.links[i * stride + k];
      if (b != kNoIndex && b != a && b < n) edges.push_back({std::min(a, b), std::max(a, b)});
    }
    const Index p = cells.vein_parent[i];
    if (p != kNoIndex && p != a && p < n) edges.push_back({std::min(a, p), std::max(a, p)});
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // Adjacency to larger indices only (CSR); lists are sorted because edges are.
  std::vector<std::size_t> start(n + 1, 0);
  for (const auto& e : edges) ++start[e[0] + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<Index> up(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) up[e] = edges[e][1];  // edges sorted by e[0] already

  // Triangles a < b < c: c in up(a) and up(b).
  auto& tris = s.triangles;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t x = start[a]; x < start[a + 1]; ++x) {
      const Index b = up[x];
      auto ia = up.begin() + static_cast<long>(x) + 1, ea = up.begin() + static_cast<long>(start[a + 1]);
      auto ib = up.begin() + static_cast<long>(start[b]), eb = up.begin() + static_cast<long>(start[b + 1]);
      while (ia != ea && ib != eb) {
        if (*ia < *ib) {
          ++ia;
        } else if (*ib < *ia) {
          ++ib;
        } else {
          tris.push_back({static_cast<Index>(a), b, *ia});
          ++ia;
          ++ib;
        }
      }
    }
  }

  // Triangles around each edge: (edge index, triangle) pairs sorted by edge.
  auto edge_index = [&](Index u, Index v) {
    const std::array<Index, 2> key{std::min(u, v), std::max(u, v)};
    return static_cast<std::size_t>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
  };
  std::vector<std::pair<std::size_t, std::size_t>> incidence;
  incidence.reserve(tris.size() * 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) incidence.push_back({edge_index(tris[t][k], tris[t][(k + 1) % 3]), t});
  std::sort(incidence.begin(), incidence.end());
  std::vector<std::size_t> inc_start(edges.size() + 1, 0);
  for (const auto& [e, t] : incidence) ++inc_start[e + 1];
  for (std::size_t e = 0; e < edges.size(); ++e) inc_start[e + 1] += inc_start[e];

  // Does triangle t traverse u -> v?
  auto has_directed = [&](std::size_t t, Index u, Index v) {
    for (int k = 0; k < 3; ++k)
      if (tris[t][k] == u && tris[t][(k + 1) % 3] == v) return true;
    return false;
  };

  // Breadth-first walk over manifold edges (exactly two triangles): the neighbour must run the shared
  // edge the other way. Seeds in index order keep their sorted orientation, so the result is deterministic.
  std::vector<std::uint8_t> seen(tris.size(), 0);
  std::deque<std::size_t> queue;
  for (std::size_t seed = 0; seed < tris.size(); ++seed) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    queue.push_back(seed);
    while (!queue.empty()) {
      const std::size_t t = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const Index u = tris[t][k], v = tris[t][(k + 1) % 3];
        const std::size_t e = edge_index(u, v);
        if (inc_start[e + 1] - inc_start[e] != 2) continue;  // boundary or non-manifold edge
        for (std::size_t x = inc_start[e]; x < inc_start[e + 1]; ++x) {
          const std::size_t o = incidence[x].second;
          if (o == t || seen[o]) continue;
          if (has_directed(o, u, v)) std::swap(tris[o][1], tris[o][2]);
          seen[o] = 1;
          queue.push_back(o);
        }
      }
    }
  }
  return s;
}

}  // namespace cellform::cells
