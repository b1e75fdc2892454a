// Self-intersections of a triangle soup: a grid of cells as broad phase, an orientation-predicate
// triangle-triangle test as narrow phase.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/triangle_intersection.h"
#include "export/mesh_check.h"

#include <tbb/parallel_sort.h>

namespace cellform::exporters {

using core::Vec3;
using Tri = std::array<std::uint32_t, 3>;

namespace {

// Does the triangle T meet the axis-aligned box of centre c and half sides e (separating axes,
// Akenine-Moller: the box's axes, the triangle's normal, and the nine edge-axis cross products)?
bool triangle_meets_box(const Vec3* T, const Vec3& c, const Vec3& e) {
  const Vec3 v[3] = {T[0] - c, T[1] - c, T[2] - c};
  for (int k = 0; k < 3; ++k)
    if (std::min({v[0][k], v[1][k], v[2][k]}) > e[k] || std::max({v[0][k], v[1][k], v[2][k]}) < -e[k]) return false;
  const Vec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  for (const Vec3& d : edges)
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = Vec3::Unit(k).cross(d);
      const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
      const double r = e.dot(axis.cwiseAbs());
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  const Vec3 n = edges[0].cross(edges[1]);
  return std::abs(n.dot(v[0])) <= e.dot(n.cwiseAbs());
}

struct CellRef {
  std::uint64_t cell;
  std::uint32_t tri;
  std::uint32_t whole;  // the triangle is held in every cell of its box (in the padding: costs nothing)
  bool operator<(const CellRef& o) const { return cell != o.cell ? cell < o.cell : tri < o.tri; }
};

using Pairs = std::vector<std::array<std::uint32_t, 2>>;

constexpr double kMaxCellsPerTriangle = 4096;  // a triangle over more grid cells is tested by a scan ("big")
constexpr std::size_t kMaxBig = 256;           // more big triangles than this: a coarser grid
constexpr double kMaxRefsPerTriangle = 64;     // more grid entries than this per triangle: a coarser grid
constexpr std::size_t kHubRun = 256;           // a cell's triangles beyond this are checked for a shared vertex
constexpr std::size_t kWholeBox = 8;           // a triangle over at most this many cells is held in all of them

/// Key of a grid cell: its coordinates packed, x first, when every gridded triangle's cells fit in 21 bits
/// per axis (sorted keys then visit the cells in space order, which the caches like); else a hash, where
/// equal keys may be two cells (their triangles then share a run: more pairs tried, none missed).
struct CellKey {
  bool packed = true;
  std::int64_t x0 = 0, y0 = 0, z0 = 0;
  std::uint64_t operator()(std::int64_t x, std::int64_t y, std::int64_t z) const {
    if (packed)
      return static_cast<std::uint64_t>(x - x0) << 42 | static_cast<std::uint64_t>(y - y0) << 21 |
             static_cast<std::uint64_t>(z - z0);
    std::uint64_t k = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
    k = (k ^ (k >> 29)) + static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full;
    k = (k ^ (k >> 31)) + static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull;
    return k ^ (k >> 32);
  }
};

/// Bounds of a search that only counts (check_mesh): at most `keep` pairs kept per grid cell (the smallest), and
/// given up (`tested` false) when one grid cell enumerates more than `max_tests` candidate pairs (after its fans
/// are peeled off). Deterministic: whether some cell passes the bound does not depend on the threads; once one
/// does, the others stop early.
struct Budget {
  std::size_t keep = std::numeric_limits<std::size_t>::max();
  double max_tests = std::numeric_limits<double>::infinity();
  std::size_t count = 0;  // out: every intersecting pair, kept or not
  bool tested = true;     // out
};

/// A fan triangle's side opposite its hub, as directions seen from the hub: a box holding them.
struct Arc {
  Vec3 lo, hi;
  std::uint32_t tri;
};

/// The pairs of a fan round `hub` (triangles [first, last)) to `visit(ti, tj, may_cross)`, which returns false
/// to stop: every pair whose boxes (below) overlap along the sweep's axis, `may_cross` if they overlap. Two
/// triangles round one corner cross beyond it iff their sides opposite it, seen from it, share a direction:
/// each side's directions (an arc of the unit sphere) lie in the box of its ends' unit directions grown by the
/// arc's sagitta, and by the narrow test's rounding tolerance over the side's distance from the hub. A sweep
/// over those boxes, along the axis where they overlap least (a flat fan's plane, a cone's cross-section),
/// meets only neighbours' boxes, not all.
template <class Visit>
void fan_pairs_of(const std::vector<Vec3>& v, const std::vector<Tri>& tris, std::uint32_t hub,
                  const std::uint32_t* first, const std::uint32_t* last, std::vector<Arc>& arcs, const Visit& visit) {
  const Vec3& h = v[hub];
  double scale = h.cwiseAbs().maxCoeff(), edge = 0;
  for (const std::uint32_t* t = first; t != last; ++t)
    for (int c = 0; c < 3; ++c) {
      scale = std::max(scale, v[tris[*t][c]].cwiseAbs().maxCoeff());
      edge = std::max(edge, (v[tris[*t][c]] - v[tris[*t][(c + 1) % 3]]).norm());
    }
  const double tol = 2 * (8 * std::numeric_limits<float>::epsilon() * scale + 1e-9 * edge);  // (the narrow test's)
  arcs.clear();
  for (const std::uint32_t* t = first; t != last; ++t) {
    const Tri& w = tris[*t];
    const int at = w[0] == hub ? 0 : w[1] == hub ? 1 : 2;
    const Vec3 p = v[w[(at + 1) % 3]] - h, q = v[w[(at + 2) % 3]] - h;
    const double side = (q - p).norm(), height = side > 0 ? p.cross(q).norm() / side : 0;  // hub to the side
    const Vec3 a = p.normalized(), b = q.normalized();
    const double grow = std::min(4.0, 1 - 0.5 * (a + b).norm() + (height > 0 ? tol / height : 4.0));
    arcs.push_back({a.cwiseMin(b) - Vec3::Constant(grow), a.cwiseMax(b) + Vec3::Constant(grow), *t});
  }
  // the axis: the least summed box width over the boxes' span (a flat fan in a plane x = const spans nothing
  // in x, where every pair would overlap)
  int axis = 0;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    double width = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Arc& r : arcs) {
      width += r.hi[k] - r.lo[k];
      lo = std::min(lo, r.lo[k]);
      hi = std::max(hi, r.hi[k]);
    }
    if (hi > lo && width / (hi - lo) < best) best = width / (hi - lo), axis = k;
  }
  std::sort(arcs.begin(), arcs.end(), [axis](const Arc& x, const Arc& y) {
    return x.lo[axis] != y.lo[axis] ? x.lo[axis] < y.lo[axis] : x.tri < y.tri;
  });
  for (std::size_t i = 0; i < arcs.size(); ++i)
    for (std::size_t j = i + 1; j < arcs.size() && arcs[j].lo[axis] <= arcs[i].hi[axis]; ++j) {
      const bool meet =
          !((arcs[i].lo.array() > arcs[j].hi.array()).any() || (arcs[j].lo.array() > arcs[i].hi.array()).any());
      if (!visit(arcs[i].tri, arcs[j].tri, meet)) return;
    }
}

Pairs intersecting_pairs(const std::vector<Vec3>& v, const std::vector<Tri>& tris, const std::vector<char>& skip,
                         int threads, Budget* budget = nullptr) {
  const std::size_t n = tris.size();
  if (n < 2) return {};
  std::vector<Vec3> lo(n), hi(n);
  // the size a cell is made from: the extent, but a sliver's width rather than its length (held in the
  // cells it crosses, a long thin triangle takes a line of them, not its whole box)
  std::vector<double> size_at(n, 0);
  core::parallel_for(n, threads, [&](std::size_t b0, std::size_t e0) {
    for (std::size_t t = b0; t < e0; ++t) {
      const Vec3 &a = v[tris[t][0]], &b = v[tris[t][1]], &c = v[tris[t][2]];
      lo[t] = a.cwiseMin(b).cwiseMin(c);
      hi[t] = a.cwiseMax(b).cwiseMax(c);
      const double extent = (hi[t] - lo[t]).maxCoeff();
      const double cross2 = (b - a).cross(c - a).squaredNorm();  // (2 area)^2; 2 sqrt(area) < extent iff:
      size_at[t] = 4 * cross2 < extent * extent * extent * extent ? std::sqrt(2 * std::sqrt(cross2)) : extent;
    }
  });
  Vec3 glo = Vec3::Constant(std::numeric_limits<double>::infinity()), ghi = -glo;
  double longest = 0;  // the largest extent
  std::vector<double> size;
  for (std::size_t t = 0; t < n; ++t) {
    if (skip[t]) continue;
    glo = glo.cwiseMin(lo[t]);
    ghi = ghi.cwiseMax(hi[t]);
    longest = std::max(longest, (hi[t] - lo[t]).maxCoeff());
    size.push_back(size_at[t]);
  }
  if (size.size() < 2) return {};
  const double span = (ghi - glo).maxCoeff();
  if (!std::isfinite(span))  // not testable in doubles; read_mesh refuses such files
    throw core::InvalidInput("self-intersection test: coordinates too far apart (beyond about 1e300)");
  if (!(span > 0)) return {};
  // Cells twice the mean triangle size, sizes capped at 8 times the median: a few huge triangles (a
  // stray far vertex) must not make the whole mesh one cell, where every pair would be tested.
  std::vector<double> sorted = size;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double cap = 8 * sorted[sorted.size() / 2];
  double mean = 0;
  for (const double e : size) mean += std::min(e, cap);
  mean /= static_cast<double>(size.size());
  double h = 2 * mean;
  if (!(h > 0)) h = span;
  // Triangles are registered in the cells they meet within `pad`: more than the rounding of the box test
  // and than the narrow phase's tolerance (points that near the other plane count as on it), so two
  // triangles it finds meeting always share a cell.
  const double scale = std::max(glo.cwiseAbs().maxCoeff(), ghi.cwiseAbs().maxCoeff());
  const double pad = 16 * std::numeric_limits<float>::epsilon() * scale + 2e-8 * longest;  // (edges < 1.8 extents)
  const auto coord = [&](double x, double x0) {  // far cells clamp (order kept: at worst more pairs tried)
    return static_cast<std::int64_t>(std::clamp(std::floor((x - x0) / h), -0x1p52, 0x1p52));
  };
  // each triangle's range of cells (its box and the pad), computed once per cell size
  std::vector<std::array<std::int64_t, 6>> range(n);
  const auto find_ranges = [&] {
    core::parallel_for(n, threads, [&](std::size_t b0, std::size_t e0) {
      for (std::size_t t = b0; t < e0; ++t)
        for (int k = 0; k < 3; ++k) {
          range[t][k] = coord(lo[t][k] - pad, glo[k]);
          range[t][k + 3] = coord(hi[t][k] + pad, glo[k]);
        }
    });
  };
  const auto box_cells = [&](std::size_t t) {
    double count = 1;
    for (int k = 0; k < 3; ++k) count *= static_cast<double>(range[t][k + 3] - range[t][k] + 1);
    return count;
  };
  // cells a triangle meets: at most those of its box; about its area and perimeter in cells otherwise
  const auto cells_of = [&](std::size_t t) {
    const double box = box_cells(t);
    if (box <= static_cast<double>(kWholeBox)) return box;
    const Vec3 &a = v[tris[t][0]], &b = v[tris[t][1]], &c = v[tris[t][2]];
    const double area = 0.5 * (b - a).cross(c - a).norm(), perimeter = (b - a).norm() + (c - b).norm() + (a - c).norm();
    const double g = 1 + 2 * pad / h;
    return std::min(box, (3 * area / (h * h) + 2 * perimeter / h + 8) * g * g * g);
  };
  // Triangles over too many cells are few, and all triangles together over at most kMaxRefsPerTriangle
  // cells each on average (sizes of two kinds: the large ones would cover thousands of the small ones'
  // cells), or the grid is made coarser until they are.
  std::vector<std::uint32_t> big;
  std::vector<double> cells_at = std::move(size_at);  // (its room reused)
  for (;;) {
    find_ranges();
    core::parallel_for(n, threads, [&](std::size_t b0, std::size_t e0) {
      for (std::size_t t = b0; t < e0; ++t) cells_at[t] = skip[t] ? 0 : cells_of(t);
    });
    big.clear();
    double refs_total = 0;  // summed in order: the same grid for any thread count
    for (std::size_t t = 0; t < n; ++t) {
      if (skip[t]) continue;
      const double cells = cells_at[t];
      if (cells > kMaxCellsPerTriangle)
        big.push_back(static_cast<std::uint32_t>(t));
      else
        refs_total += cells;
    }
    if ((big.size() <= kMaxBig && refs_total <= kMaxRefsPerTriangle * static_cast<double>(n)) || h >= span) break;
    h *= 2;
  }
  std::vector<char> is_big(n, 0);
  for (const std::uint32_t t : big) is_big[t] = 1;
  CellKey cell_key;
  {
    std::int64_t c0[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, c1[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (std::size_t t = 0; t < n; ++t)
      if (!skip[t] && !is_big[t])
        for (int k = 0; k < 3; ++k) {
          c0[k] = std::min(c0[k], range[t][k]);
          c1[k] = std::max(c1[k], range[t][k + 3]);
        }
    for (int k = 0; k < 3; ++k)  // (no gridded triangle: nothing to pack)
      cell_key.packed = cell_key.packed && (c0[k] > c1[k] || c1[k] - c0[k] < (std::int64_t{1} << 21));
    cell_key.x0 = c0[0];
    cell_key.y0 = c0[1];
    cell_key.z0 = c0[2];
  }
  // A triangle whose box spans at most kWholeBox cells is registered in all of them ("whole"); a larger
  // one (a sliver across many cells) only in those it meets, found by halving its range while the half
  // meets it, and its cells are kept, ascending (a CSR by triangle), to find the first two triangles share.
  std::vector<char> whole(n, 0);
  std::vector<std::size_t> offset(n + 1, 0), key_begin(n + 1, 0);
  std::vector<std::uint64_t> keys;
  {
    constexpr std::size_t kBlock = 4096;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<std::vector<std::uint64_t>> block_keys(blocks);
    core::parallel_for(blocks, threads, [&](std::size_t b0, std::size_t e0) {
      std::vector<std::array<std::int64_t, 6>> stack;
      for (std::size_t b = b0; b < e0; ++b) {
        std::vector<std::uint64_t>& out = block_keys[b];
        for (std::size_t t = b * kBlock; t < std::min(n, (b + 1) * kBlock); ++t) {
          if (skip[t] || is_big[t]) continue;
          if (box_cells(t) <= static_cast<double>(kWholeBox)) {
            whole[t] = 1;
            offset[t + 1] = static_cast<std::size_t>(box_cells(t));
            continue;
          }
          const std::size_t before = out.size();
          const Vec3 T[3] = {v[tris[t][0]], v[tris[t][1]], v[tris[t][2]]};
          stack.assign(1, range[t]);
          while (!stack.empty()) {
            const std::array<std::int64_t, 6> c = stack.back();
            stack.pop_back();
            Vec3 clo, chi;
            for (int k = 0; k < 3; ++k) {
              clo[k] = glo[k] + static_cast<double>(c[k]) * h;
              chi[k] = glo[k] + static_cast<double>(c[k + 3] + 1) * h;
            }
            if (!triangle_meets_box(T, 0.5 * (clo + chi), 0.5 * (chi - clo) + Vec3::Constant(pad))) continue;
            int axis = 0;
            for (int k = 1; k < 3; ++k)
              if (c[k + 3] - c[k] > c[axis + 3] - c[axis]) axis = k;
            if (c[axis + 3] == c[axis]) {  // one cell
              out.push_back(cell_key(c[0], c[1], c[2]));
              continue;
            }
            const std::int64_t mid = c[axis] + (c[axis + 3] - c[axis]) / 2;
            std::array<std::int64_t, 6> lower = c, upper = c;
            lower[axis + 3] = mid;
            upper[axis] = mid + 1;
            stack.push_back(upper);
            stack.push_back(lower);
          }
          if (out.size() == before)  // rounding: never lose a triangle; its box's first cell holds it
            out.push_back(cell_key(range[t][0], range[t][1], range[t][2]));
          std::sort(out.begin() + static_cast<std::ptrdiff_t>(before), out.end());
          out.erase(std::unique(out.begin() + static_cast<std::ptrdiff_t>(before), out.end()), out.end());
          offset[t + 1] = key_begin[t + 1] = out.size() - before;
        }
      }
    });
    for (std::size_t t = 0; t < n; ++t) {
      offset[t + 1] += offset[t];
      key_begin[t + 1] += key_begin[t];
    }
    keys.reserve(key_begin[n]);
    for (const auto& k : block_keys) keys.insert(keys.end(), k.begin(), k.end());
  }
  // a whole triangle's cells, ascending
  const auto box_keys = [&](std::size_t t, std::array<std::uint64_t, kWholeBox>& out) {
    const auto& c = range[t];
    std::size_t m = 0;
    for (std::int64_t x = c[0]; x <= c[3]; ++x)
      for (std::int64_t y = c[1]; y <= c[4]; ++y)
        for (std::int64_t z = c[2]; z <= c[5]; ++z) out[m++] = cell_key(x, y, z);
    if (!cell_key.packed)  // (insertion: at most kWholeBox keys)
      for (std::size_t i = 1; i < m; ++i)
        for (std::size_t j = i; j > 0 && out[j] < out[j - 1]; --j) std::swap(out[j], out[j - 1]);
    return m;
  };
  std::vector<CellRef> refs(offset[n]);
  core::parallel_for(n, threads, [&](std::size_t b0, std::size_t e0) {
    std::array<std::uint64_t, kWholeBox> box{};
    for (std::size_t t = b0; t < e0; ++t) {
      const auto tri = static_cast<std::uint32_t>(t);
      if (whole[t]) {
        const std::size_t m = box_keys(t, box);
        for (std::size_t k = 0; k < m; ++k) refs[offset[t] + k] = {box[k], tri, 1};
      } else {
        for (std::size_t k = key_begin[t]; k < key_begin[t + 1]; ++k)
          refs[offset[t] + k - key_begin[t]] = {keys[k], tri, 0};
      }
    }
  });
  // equal elements are equal: one order
  core::with_threads(threads, [&] { tbb::parallel_sort(refs.begin(), refs.end()); });
  // two cells whose keys collide: a triangle in both is one entry of their run
  refs.erase(std::unique(refs.begin(), refs.end(),
                         [](const CellRef& a, const CellRef& b) { return a.cell == b.cell && a.tri == b.tri; }),
             refs.end());
  std::vector<std::size_t> runs;
  for (std::size_t k = 0; k < refs.size(); ++k)
    if (k == 0 || refs[k].cell != refs[k - 1].cell) runs.push_back(k);
  const std::size_t nruns = runs.size();
  runs.push_back(refs.size());
  const auto overlap = [&](std::uint32_t ti, std::uint32_t tj) {
    return !((lo[ti].array() > hi[tj].array()) || (lo[tj].array() > hi[ti].array())).any();
  };
  const auto key_of = [&](const Vec3& p) {
    return cell_key(coord(p.x(), glo.x()), coord(p.y(), glo.y()), coord(p.z(), glo.z()));
  };
  // is `cell` the smallest cell key two triangles share (their lists are ascending)?
  const auto first_shared_is = [&](std::uint32_t ti, std::uint32_t tj, std::uint64_t cell) {
    std::array<std::uint64_t, kWholeBox> box_i{}, box_j{};
    const std::uint64_t *a = keys.data() + key_begin[ti], *a_end = keys.data() + key_begin[ti + 1];
    const std::uint64_t *b = keys.data() + key_begin[tj], *b_end = keys.data() + key_begin[tj + 1];
    if (whole[ti]) a = box_i.data(), a_end = a + box_keys(ti, box_i);
    if (whole[tj]) b = box_j.data(), b_end = b + box_keys(tj, box_j);
    while (a < a_end && b < b_end) {
      if (*a == *b) return *a == cell;
      if (*a > cell || *b > cell) return false;  // any key both hold from here on is past `cell`
      if (*a < *b)
        ++a;
      else
        ++b;
    }
    return false;  // not reached: both are in the cell that found them
  };
  // how many corners two triangles share, and (for one) where it is in each
  const auto shared_corners = [&](std::uint32_t ti, std::uint32_t tj, int& at_i, int& at_j) {
    const Tri &s = tris[ti], &t = tris[tj];
    int count = 0;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        if (s[p] == t[q]) ++count, at_i = p, at_j = q;
    return count;
  };
  const auto share_side = [&](std::uint32_t ti, std::uint32_t tj) {  // neighbours across a side meet only there
    int p = 0, q = 0;
    return shared_corners(ti, tj, p, q) >= 2;
  };
  std::vector<Pairs> found(nruns + big.size());
  std::vector<std::size_t> counted(budget ? found.size() : 0, 0);
  std::atomic<bool> gave_up{false};
  const auto stop = [&] { return budget && gave_up.load(std::memory_order_relaxed); };
  const auto test = [&](std::uint32_t ti, std::uint32_t tj, Pairs& out) {  // boxes overlap
    int at_i = 0, at_j = 0;
    const int shared = shared_corners(ti, tj, at_i, at_j);
    if (shared >= 2) return;  // neighbours across a side (or a triangle repeated) meet there
    const Tri &s = tris[ti], &t = tris[tj];
    const std::array<Vec3, 3> S{v[s[0]], v[s[1]], v[s[2]]}, T{v[t[0]], v[t[1]], v[t[2]]};
    // two triangles round one corner (a crease folded into itself) cross iff either's far side meets the other
    if (shared == 1 ? !core::triangles_cross_beyond_corner(S, at_i, T, at_j) : !core::triangles_intersect(S, T)) return;
    const std::array<std::uint32_t, 2> pair{std::min(ti, tj), std::max(ti, tj)};
    if (!budget) {
      out.push_back(pair);
      return;
    }
    ++counted[static_cast<std::size_t>(&out - found.data())];
    // keep the smallest `keep` of this cell's pairs, sorted
    if (out.size() == budget->keep && !(pair < out.back())) return;
    if (out.size() == budget->keep) out.pop_back();
    out.insert(std::upper_bound(out.begin(), out.end(), pair), pair);
  };
  core::parallel_for(
      nruns, threads,
      [&](std::size_t b0, std::size_t e0) {
        std::vector<std::uint32_t> ids, group, hubs;
        std::vector<std::size_t> bounds;
        std::vector<Arc> arcs;
        for (std::size_t r = b0; r < e0 && !stop(); ++r) {
          const std::uint64_t cell = refs[runs[r]].cell;
          // each pair once: in the cell of the low corner of the boxes' overlap when both are whole (both
          // hold it), else in the first cell (by key) that both hold
          double enumerated = 0;  // candidate pairs of this cell (a counting search gives up past its bound)
          const auto candidate = [&](std::uint32_t ti, std::uint32_t tj, bool both_whole) {
            if (budget && ++enumerated > budget->max_tests) {
              if (!gave_up.load(std::memory_order_relaxed)) gave_up.store(true, std::memory_order_relaxed);
              return;
            }
            if (overlap(ti, tj) && (both_whole ? key_of(lo[ti].cwiseMax(lo[tj])) == cell
                                               : !share_side(ti, tj) && first_shared_is(ti, tj, cell)))
              test(std::min(ti, tj), std::max(ti, tj), found[r]);  // in index order, whatever the path
          };
          const std::size_t first = runs[r], end = runs[r + 1];
          if (end - first <= kHubRun) {
            for (std::size_t i = first; i < end; ++i)
              for (std::size_t j = i + 1; j < end; ++j)
                candidate(refs[i].tri, refs[j].tri, refs[i].whole & refs[j].whole);
            continue;
          }
          // Many triangles of one cell around one vertex (the tip of a cone, a polygon's fan): the pairs of
          // such a fan are not all enumerated (below). The fans are peeled off while one vertex is in a
          // quarter of what is left; the rest stays first.
          group.assign(end - first, 0);
          for (std::size_t i = first; i < end; ++i) group[i - first] = refs[i].tri;
          std::size_t rest = group.size();
          bounds.assign(1, 0);
          hubs.clear();
          while (rest > kHubRun) {
            ids.clear();
            for (std::size_t i = 0; i < rest; ++i)
              for (const std::uint32_t w : tris[group[i]]) ids.push_back(w);
            std::sort(ids.begin(), ids.end());
            std::uint32_t hub = 0;
            std::size_t hub_count = 0;
            for (std::size_t i = 0, j = 0; i < ids.size(); i = j) {
              for (j = i; j < ids.size() && ids[j] == ids[i]; ++j) {
              }
              if (j - i > hub_count) hub = ids[i], hub_count = j - i;
            }
            if (hub_count * 4 < rest) break;
            const auto fan = std::stable_partition(group.begin(), group.begin() + static_cast<std::ptrdiff_t>(rest),
                                                   [&](std::uint32_t t) {
                                                     const Tri& w = tris[t];
                                                     return w[0] != hub && w[1] != hub && w[2] != hub;
                                                   });
            rest = static_cast<std::size_t>(fan - group.begin());
            bounds.push_back(rest);  // the fan lies from here to the previous bound
            hubs.push_back(hub);
          }
          // the rest with everything after it; each fan with what lies after it (its own pairs share the hub)
          for (std::size_t i = 0; i < rest && !stop(); ++i)
            for (std::size_t j = i + 1; j < group.size(); ++j)
              candidate(group[i], group[j], whole[group[i]] && whole[group[j]]);
          for (std::size_t k = 1; k < bounds.size(); ++k) {
            const std::size_t fan_end = k == 1 ? group.size() : bounds[k - 1];
            for (std::size_t i = bounds[k]; i < fan_end && !stop(); ++i)
              for (std::size_t j = fan_end; j < group.size(); ++j)
                candidate(group[i], group[j], whole[group[i]] && whole[group[j]]);
            fan_pairs_of(v, tris, hubs[k - 1], group.data() + bounds[k], group.data() + fan_end, arcs,
                         [&](std::uint32_t ti, std::uint32_t tj, bool may_cross) {
                           if (may_cross) {
                             candidate(ti, tj, whole[ti] && whole[tj]);
                           } else if (budget && ++enumerated > budget->max_tests) {  // a sweep step counts too
                             if (!gave_up.load(std::memory_order_relaxed))
                               gave_up.store(true, std::memory_order_relaxed);
                           }
                           return !stop();
                         });
          }
        }
      },
      64);
  // big triangles: against every triangle whose box meets theirs (a pair of two big ones once)
  core::parallel_for(big.size(), threads, [&](std::size_t b0, std::size_t e0) {
    for (std::size_t k = b0; k < e0; ++k) {
      const std::uint32_t b = big[k];
      for (std::uint32_t t = 0; t < n; ++t)
        if (!skip[t] && t != b && !(is_big[t] && t < b) && overlap(b, t))
          test(std::min(b, t), std::max(b, t), found[nruns + k]);  // in index order, as from the grid
    }
  });
  Pairs all;
  for (const Pairs& f : found) all.insert(all.end(), f.begin(), f.end());
  std::sort(all.begin(), all.end());
  if (budget && gave_up.load()) {
    budget->tested = false;
    return {};
  }
  if (budget) {
    for (const std::size_t c : counted) budget->count += c;
    if (all.size() > budget->keep) all.resize(budget->keep);
  }
  return all;
}

/// Per triangle: repeated corners or zero area (never tested).
std::vector<char> degenerate(const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles) {
  std::vector<char> skip(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Tri& w = triangles[t];
    const Vec3 &a = vertices[w[0]], &b = vertices[w[1]], &c = vertices[w[2]];
    skip[t] = w[0] == w[1] || w[1] == w[2] || w[0] == w[2] || (b - a).cross(c - a).squaredNorm() == 0;
  }
  return skip;
}

}  // namespace

std::vector<std::array<std::uint32_t, 2>> self_intersecting_pairs(const std::vector<Vec3>& vertices,
                                                                  const std::vector<Tri>& triangles, int threads) {
  const std::vector<char> skip = degenerate(vertices, triangles);
  return intersecting_pairs(vertices, triangles, skip, threads);
}

SelfIntersectionCount count_self_intersections(const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles,
                                               std::size_t examples, double max_tests, int threads) {
  const std::vector<char> skip = degenerate(vertices, triangles);
  Budget budget;
  budget.keep = std::max<std::size_t>(examples, 1);
  budget.max_tests = max_tests;
  SelfIntersectionCount out;
  out.examples = intersecting_pairs(vertices, triangles, skip, threads, &budget);
  out.examples.resize(std::min(out.examples.size(), examples));
  out.count = budget.count;
  out.tested = budget.tested;
  return out;
}

std::vector<std::array<std::uint32_t, 2>> self_intersecting_pairs(const PrintableMesh& mesh, int threads) {
  return self_intersecting_pairs(mesh.vertices, mesh.triangles, threads);
}

}  // namespace cellform::exporters
