// Small holes of the one-layer cell surface, closed by their shortest-diagonal triangulation.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>

#include "cells/surface_detail.h"

namespace cellform::cells::detail {

namespace {

constexpr std::size_t kMaxHole = 12;       // boundary sides of the longest loop closed
constexpr double kMinFacing = 0.25;        // |sum of the unit normals round a hole| / their number, at least
constexpr std::size_t kWalkBudget = 1024;  // steps of the search for the loops through one boundary side

/// The triangulation of polygon p[0..n) (n <= kMaxHole) with the least total diagonal length (dynamic
/// programming over sub-polygons; ties to the first found) that crosses none of `chords` (pairs i < j of
/// polygon positions, which a triangulation then holds, being maximal), uses none of `taken` (i < j) and
/// has every triangle, in polygon order, facing along `up` (so none lies outside a polygon that is nearly
/// flat across `up`: its triangles' areas add up to the polygon's), as corner triples in polygon order;
/// empty if there is none.
std::vector<std::array<std::size_t, 3>> shortest_triangulation(const std::vector<Vec3>& p,
                                                               const std::vector<std::array<std::size_t, 2>>& chords,
                                                               const std::vector<std::array<std::size_t, 2>>& taken,
                                                               const Vec3& up) {
  const std::size_t n = p.size();
  auto allowed = [&](std::size_t a, std::size_t b) {  // a < b: a side, or a diagonal crossing no chord
    if (std::find(taken.begin(), taken.end(), std::array<std::size_t, 2>{a, b}) != taken.end()) return false;
    for (const auto& [c, d] : chords)
      if ((a < c && c < b && b < d) || (c < a && a < d && d < b)) return false;
    return true;
  };
  constexpr double kNone = std::numeric_limits<double>::infinity();
  double cost[kMaxHole][kMaxHole] = {};
  std::size_t pick[kMaxHole][kMaxHole] = {};
  for (std::size_t len = 2; len < n; ++len)
    for (std::size_t i = 0; i + len < n; ++i) {
      const std::size_t j = i + len;
      cost[i][j] = kNone;
      for (std::size_t k = i + 1; k < j; ++k) {
        if (!allowed(i, k) || !allowed(k, j) || !((p[k] - p[i]).cross(p[j] - p[i]).dot(up) > 0)) continue;
        const double c = cost[i][k] + cost[k][j] + (k > i + 1 ? (p[i] - p[k]).norm() : 0.0) +
                         (j > k + 1 ? (p[k] - p[j]).norm() : 0.0);
        if (c < cost[i][j]) {
          cost[i][j] = c;
          pick[i][j] = k;
        }
      }
    }
  std::vector<std::array<std::size_t, 3>> out;
  if (!(cost[0][n - 1] < kNone)) return out;
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

/// Fills the small holes the one-layer surface leaves where pruning took crossing edges out of a few cells,
/// or no link closed a triangle: a closed simple loop of 3 to kMaxHole boundary sides (one triangle each;
/// through a cell where holes touch, the shortest that can be closed) whose triangles face one way (their
/// unit normals add up to at least kMinFacing of their number) gets the triangulation of least diagonal
/// length whose triangles all face that way too (so none lies outside a nearly flat hole). A side across
/// the hole without a triangle (a chord) is kept in the fill; a side between two of its cells that has
/// triangles, or that an earlier fill made, is not used. The loop runs each side against its triangle, so
/// the new triangles continue the orientation around them. A loop with no such fill (the outline of a
/// small sheet or an isolated triangle, a loop twisted round a fold, the open end of a tube), or whose fill
/// would fold (less than 90 degrees between two triangles round a side, the fill's own or the loop's), lie
/// over a triangle round a corner or cross any triangle (another sheet passing through the hole), is left
/// open. Deterministic: loops in the order of their sides.
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
  auto side_index = [&](Index u, Index v) {  // sides.size() when u-v is no side
    const std::array<Index, 2> key{std::min(u, v), std::max(u, v)};
    const auto it = std::lower_bound(sides.begin(), sides.end(), key);
    return it != sides.end() && *it == key ? static_cast<std::size_t>(it - sides.begin()) : sides.size();
  };
  auto normal = [&](Index a, Index b, Index c) -> Vec3 { return (pos[b] - pos[a]).cross(pos[c] - pos[a]); };
  std::vector<std::uint8_t> done(half.size(), 0);
  std::set<std::array<Index, 2>> diagonals;  // new sides, each used by one fill
  SheetIndex sheet(pos, tris);               // a fill must not lie over a triangle round a corner, nor cross one
  std::set<std::vector<std::size_t>> tried;  // loops that could not be closed (canonical rotation)
  // Closes the hole `loop` (half-edges in order) if it can; see above.
  auto try_fill = [&](const std::vector<std::size_t>& loop) {
    const std::size_t n = loop.size();
    std::vector<Index> corner(n);
    std::vector<Vec3> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = pos[corner[i] = half[loop[i]].from];
    // a chord (a side between two cells of the loop that are not neighbours on it) with no triangle lies
    // over the hole and divides it: the fill holds it; one with triangles lies outside the hole (round a
    // corner of the loop that turns away from it, or across a fold): the fill must not use it
    bool ok = true;
    std::vector<std::array<std::size_t, 2>> chords, taken;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;
        const std::size_t e = side_index(corner[i], corner[j]);
        const bool filled = diagonals.count({std::min(corner[i], corner[j]), std::max(corner[i], corner[j])}) > 0;
        if (e == sides.size() && !filled) continue;
        (e < sides.size() && inc_start[e + 1] == inc_start[e] && !filled ? chords : taken).push_back({i, j});
      }
    // the way the triangles round the loop face; their unit normals must add up to at least half their
    // number (round the open end of a tube they cancel: it stays open)
    Vec3 up = Vec3::Zero();
    for (const std::size_t x : loop) {
      const auto& t = tris[half[x].tri];
      const Vec3 nt = normal(t[0], t[1], t[2]);
      if (nt.squaredNorm() > 0) up += nt.normalized();
    }
    if (!(up.norm() >= kMinFacing * static_cast<double>(n))) return false;
    const std::vector<std::array<std::size_t, 3>> fill = shortest_triangulation(p, chords, taken, up);
    if (fill.empty()) return false;
    // every side of the loop: its fill triangle must not fold onto its old triangle (a crease sharper than
    // a right angle, as the one-layer surface has none)
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
      ok = !sheet.stacks(t);
      for (std::size_t b = a + 1; b < fill.size() && ok; ++b) {  // nor on each other, nor folded onto each other
        const std::array<Index, 3> u{corner[fill[b][0]], corner[fill[b][1]], corner[fill[b][2]]};
        int common = 0;
        Index shared = kNoIndex;
        for (const Index x : t)
          if (x == u[0] || x == u[1] || x == u[2]) {
            ++common;
            shared = x;
          }
        if (common == 1) ok = !stacked_at(pos, t, u, shared);
        if (common == 2) ok = normal(t[0], t[1], t[2]).dot(normal(u[0], u[1], u[2])) > 0;
      }
    }
    std::vector<std::array<Index, 3>> added;
    for (std::size_t a = 0; a < fill.size() && ok; ++a) {
      const std::array<Index, 3> t{corner[fill[a][0]], corner[fill[a][1]], corner[fill[a][2]]};
      ok = !sheet.crosses(t, added);
      added.push_back(t);
    }
    if (!ok) return false;
    for (const std::size_t x : loop) done[x] = 1;
    if (!chords.empty()) tried.clear();  // a loop that failed with one of them forced may now close
    for (const auto& f : fill) {
      std::array<Index, 3> t{corner[f[0]], corner[f[1]], corner[f[2]]};  // the loop's turn: facing as around it
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      sheet.add(t);
      tris.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = f[k], b = f[(k + 1) % 3];
        if ((a + 1) % n != b && (b + 1) % n != a)
          diagonals.insert({std::min(corner[a], corner[b]), std::max(corner[a], corner[b])});
      }
    }
    return true;
  };
  std::vector<std::vector<std::size_t>> loops;  // per boundary side h, reused: most sheets have many
  std::vector<std::size_t> path;
  for (std::size_t h = 0; h < half.size(); ++h) {
    if (done[h]) continue;
    // the simple loops of boundary sides from h back to its start, of at most kMaxHole sides; at a pinch,
    // where several boundary sides leave a cell (holes or the outlines of small pieces that touch there),
    // each way is taken. The shortest that can be closed is.
    loops.clear();
    path.assign(1, h);
    std::size_t budget = kWalkBudget;  // steps of the walk from h: a tangle of pinches would branch without end
    auto walk = [&](auto& self) -> void {
      if (budget == 0) return;
      --budget;
      const Index v = half[path.back()].to;
      if (v == half[h].from) {
        if (path.size() >= 3) loops.push_back(path);
        return;
      }
      if (path.size() == kMaxHole ||
          std::any_of(path.begin(), path.end(), [&](std::size_t x) { return half[x].from == v; }))
        return;
      for (auto it = std::lower_bound(half.begin(), half.end(), Half{v, 0, 0}); it != half.end() && it->from == v;
           ++it) {
        const auto next = static_cast<std::size_t>(it - half.begin());
        if (done[next]) continue;
        path.push_back(next);
        self(self);
        path.pop_back();
      }
    };
    walk(walk);
    std::stable_sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
    for (const auto& loop : loops) {
      // a loop that could not be closed is found again from each of its sides: tried once
      std::vector<std::size_t> key = loop;
      std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
      if (!tried.insert(key).second) continue;
      if (try_fill(loop)) break;
    }
  }
  // sorted by smallest index, the triangles that were there keeping their order
  std::stable_sort(tris.begin(), tris.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
}

}  // namespace cellform::cells::detail
