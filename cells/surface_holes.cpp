// Small holes of the one-layer cell surface, closed by their shortest-diagonal triangulation.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>

#include "cells/surface_detail.h"

namespace cellform::cells::detail {

namespace {

/// The triangulation of polygon p[0..n) (n <= kMaxHole) with the least total diagonal length (dynamic
/// programming over sub-polygons; ties to the first found), as corner triples in polygon order.
constexpr std::size_t kMaxHole = 6;
std::vector<std::array<std::size_t, 3>> shortest_triangulation(const std::vector<Vec3>& p) {
  const std::size_t n = p.size();
  double cost[kMaxHole][kMaxHole] = {};
  std::size_t pick[kMaxHole][kMaxHole] = {};
  for (std::size_t len = 2; len < n; ++len)
    for (std::size_t i = 0; i + len < n; ++i) {
      const std::size_t j = i + len;
      cost[i][j] = std::numeric_limits<double>::infinity();
      for (std::size_t k = i + 1; k < j; ++k) {
        const double c = cost[i][k] + cost[k][j] + (k > i + 1 ? (p[i] - p[k]).norm() : 0.0) +
                         (j > k + 1 ? (p[k] - p[j]).norm() : 0.0);
        if (c < cost[i][j]) {
          cost[i][j] = c;
          pick[i][j] = k;
        }
      }
    }
  std::vector<std::array<std::size_t, 3>> out;
  std::vector<std::array<std::size_t, 2>> pending{{0, n - 1}};  // sub-polygons left to split
  while (!pending.empty()) {
    const auto [i, j] = pending.back();
    pending.pop_back();
    if (j < i + 2) continue;
    const std::size_t k = pick[i][j];
    out.push_back({i, k, j});
    pending.push_back({i, k});
    pending.push_back({k, j});
  }
  return out;
}

}  // namespace

/// Fills the small holes the one-layer surface leaves where pruning took a crossing edge out of a pentagon
/// or hexagon of cells: a closed loop of 3 to kMaxHole boundary sides (one triangle each), simple, without
/// a chord (a side between two of its cells that are not neighbours on it), gets the triangulation of
/// least diagonal length. The loop runs each side against its triangle, so the new triangles continue the
/// orientation around them; a loop whose fill would face against the triangles around it (the outline of
/// a small sheet, an isolated triangle) is left open. Deterministic: loops in the order of their sides.
void fill_small_holes(const std::vector<Vec3>& pos, const std::vector<std::array<Index, 2>>& sides,
                      const std::vector<std::size_t>& inc_start,
                      const std::vector<std::pair<std::size_t, std::size_t>>& incidence,
                      std::vector<std::array<Index, 3>>& tris) {
  struct Half {
    Index from, to;
    std::size_t tri;  // the one triangle on this side
    bool operator<(const Half& o) const { return from != o.from ? from < o.from : to < o.to; }
  };
  std::vector<Half> half;  // boundary sides, run against their triangle
  for (std::size_t e = 0; e < sides.size(); ++e) {
    if (inc_start[e + 1] - inc_start[e] != 1) continue;
    const std::size_t t = incidence[inc_start[e]].second;
    const auto [a, b] = sides[e];
    bool forward = false;  // does t run a -> b?
    for (int k = 0; k < 3; ++k) forward = forward || (tris[t][k] == a && tris[t][(k + 1) % 3] == b);
    half.push_back(forward ? Half{b, a, t} : Half{a, b, t});
  }
  std::sort(half.begin(), half.end());
  // the one boundary side leaving v, or half.size() when none or several (a pinch: not a simple loop)
  auto leaving = [&](Index v) {
    const auto lo = std::lower_bound(half.begin(), half.end(), Half{v, 0, 0});
    if (lo == half.end() || lo->from != v || (lo + 1 != half.end() && (lo + 1)->from == v)) return half.size();
    return static_cast<std::size_t>(lo - half.begin());
  };
  auto is_side = [&](Index u, Index v) {
    const std::array<Index, 2> key{std::min(u, v), std::max(u, v)};
    return std::binary_search(sides.begin(), sides.end(), key);
  };
  auto normal = [&](Index a, Index b, Index c) -> Vec3 { return (pos[b] - pos[a]).cross(pos[c] - pos[a]); };
  std::vector<std::uint8_t> done(half.size(), 0);
  std::set<std::array<Index, 2>> diagonals;   // new sides, each used by one fill
  CornerIndex corners(pos.size(), {}, tris);  // a fill must not lie over a triangle round a corner
  for (std::size_t h = 0; h < half.size(); ++h) {
    if (done[h]) continue;
    std::vector<std::size_t> loop{h};  // half-edges around the loop
    bool closed = false;
    while (loop.size() <= kMaxHole) {
      const Index v = half[loop.back()].to;
      if (v == half[h].from) {
        closed = true;
        break;
      }
      const std::size_t next = leaving(v);
      if (next == half.size() || done[next] ||
          std::any_of(loop.begin(), loop.end(), [&](std::size_t x) { return half[x].from == v; }))
        break;
      loop.push_back(next);
    }
    if (!closed || loop.size() < 3 || loop.size() > kMaxHole) continue;
    for (const std::size_t x : loop) done[x] = 1;  // a loop is found once, from its first side
    const std::size_t n = loop.size();
    std::vector<Index> corner(n);
    std::vector<Vec3> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = pos[corner[i] = half[loop[i]].from];
    bool ok = true;
    for (std::size_t i = 0; i < n && ok; ++i)
      for (std::size_t j = i + 2; j < n && ok; ++j)
        if (!(i == 0 && j == n - 1) && is_side(corner[i], corner[j])) ok = false;  // a chord
    if (!ok) continue;
    const std::vector<std::array<std::size_t, 3>> fill = shortest_triangulation(p);
    // every side of the loop: its fill triangle must face the way its old triangle does
    for (std::size_t i = 0; i < n && ok; ++i) {
      const std::size_t j = (i + 1) % n;
      for (const auto& f : fill) {
        const bool has_i = f[0] == i || f[1] == i || f[2] == i, has_j = f[0] == j || f[1] == j || f[2] == j;
        if (!has_i || !has_j) continue;
        const auto& t = tris[half[loop[i]].tri];
        const Vec3 nf = normal(corner[f[0]], corner[f[1]], corner[f[2]]), nt = normal(t[0], t[1], t[2]);
        ok = nf.squaredNorm() > 0 && nf.dot(nt) > 0;
      }
    }
    for (const auto& f : fill)
      for (int k = 0; k < 3 && ok; ++k) {
        const std::size_t a = f[k], b = f[(k + 1) % 3];
        if ((a + 1) % n == b || (b + 1) % n == a) continue;  // a side of the loop
        ok = !diagonals.count({std::min(corner[a], corner[b]), std::max(corner[a], corner[b])});
      }
    for (std::size_t a = 0; a < fill.size() && ok; ++a) {
      const std::array<Index, 3> t{corner[fill[a][0]], corner[fill[a][1]], corner[fill[a][2]]};
      ok = !corners.stacks(pos, t);
      for (std::size_t b = a + 1; b < fill.size() && ok; ++b) {  // nor on each other (a twisted loop)
        const std::array<Index, 3> u{corner[fill[b][0]], corner[fill[b][1]], corner[fill[b][2]]};
        int common = 0;
        Index shared = kNoIndex;
        for (const Index x : t)
          if (x == u[0] || x == u[1] || x == u[2]) {
            ++common;
            shared = x;
          }
        ok = common != 1 || !stacked_at(pos, t, u, shared);
      }
    }
    if (!ok) continue;
    for (const auto& f : fill) {
      std::array<Index, 3> t{corner[f[0]], corner[f[1]], corner[f[2]]};  // the loop's turn: facing as around it
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      corners.add(t);
      tris.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = f[k], b = f[(k + 1) % 3];
        if ((a + 1) % n != b && (b + 1) % n != a)
          diagonals.insert({std::min(corner[a], corner[b]), std::max(corner[a], corner[b])});
      }
    }
  }
  // sorted by smallest index, the triangles that were there keeping their order
  std::stable_sort(tris.begin(), tris.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
}

}  // namespace cellform::cells::detail
