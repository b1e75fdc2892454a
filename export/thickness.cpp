// Ray-cast wall thickness over a bounding-volume hierarchy of the triangles.
#include "export/thickness.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/parallel.h"

namespace cellform::exporters {

using core::Vec3;

namespace {

struct Bvh {
  struct Node {
    Vec3 lo, hi;
    std::uint32_t first = 0, count = 0;  // leaf: items order[first, first + count)
    std::uint32_t left = 0, right = 0;   // inner (count == 0)
  };
  std::vector<Node> nodes;
  std::vector<std::uint32_t> order;  // items
  std::vector<std::uint32_t> tri;    // per item: its triangle
};

constexpr std::uint32_t kLeafSize = 4;
// A ray that has entered this many nodes is given up (a spot where very many triangles meet, where every
// box holds the ray's start): it keeps one check linear in triangles.
constexpr std::size_t kMaxVisits = 4096;
// A long thin triangle (a sliver of a finely divided cone or disc, meeting thousands of others at its tip)
// has a box far larger than itself: every ray through the cone's axis would enter all of them. Such a
// triangle gets, for the tree only, the boxes of its parts in slabs across its box's longest side, each
// slab no thicker than kPieceLength times the side of a square of its area, at most kMaxPieces of them.
constexpr double kPieceLength = 8;
constexpr int kMaxPieces = 64;
constexpr std::size_t kMaxBoxesPerTriangle = 8;  // boxes in the tree per triangle of the mesh, at most
constexpr int kMaxLevel = 8;                     // a large triangle gets at most kMaxLevel^2 rays
constexpr std::size_t kSubRayBudget = 1 << 20;   // sub-rays of a check, at least (4 per triangle if more)
constexpr std::size_t kCoarseRays = 1 << 12;     // a mesh of few triangles gets about this many rays in all

/// How many pieces triangle T would be cut into (1: its own box).
int pieces_wanted(const Vec3* T) {
  const Vec3 blo = T[0].cwiseMin(T[1]).cwiseMin(T[2]), bhi = T[0].cwiseMax(T[1]).cwiseMax(T[2]);
  const double piece = kPieceLength * std::sqrt((T[1] - T[0]).cross(T[2] - T[0]).norm());
  const double want = piece > 0 ? std::ceil((bhi - blo).maxCoeff() / piece) : 1;
  return want > 1 ? static_cast<int>(std::min<double>(want, kMaxPieces)) : 1;
}

/// The boxes of triangle t cut into `pieces`: its own box, or those of its parts in consecutive slabs (a
/// ray that enters one tests the whole triangle, so a hit is the same as with one box).
void triangle_boxes(const Vec3* T, std::uint32_t t, int pieces, std::vector<Vec3>& lo, std::vector<Vec3>& hi,
                    std::vector<std::uint32_t>& tri) {
  const Vec3 blo = T[0].cwiseMin(T[1]).cwiseMin(T[2]), bhi = T[0].cwiseMax(T[1]).cwiseMax(T[2]);
  int axis = 0;
  const double extent = (bhi - blo).maxCoeff(&axis);
  if (pieces == 1) {
    lo.push_back(blo);
    hi.push_back(bhi);
    tri.push_back(t);
    return;
  }
  const double size = std::max({T[0].cwiseAbs().maxCoeff(), T[1].cwiseAbs().maxCoeff(), T[2].cwiseAbs().maxCoeff()});
  const Vec3 grow = Vec3::Constant(1e-9 * extent + 4 * std::numeric_limits<double>::epsilon() * size);  // cut rounding
  for (int i = 0; i < pieces; ++i) {
    const double s0 = blo[axis] + extent * i / pieces,
                 s1 = i + 1 == pieces ? bhi[axis] : blo[axis] + extent * (i + 1) / pieces;
    Vec3 plo = Vec3::Constant(std::numeric_limits<double>::infinity()), phi = -plo;
    const auto add = [&](const Vec3& q) {
      plo = plo.cwiseMin(q);
      phi = phi.cwiseMax(q);
    };
    for (int k = 0; k < 3; ++k) {
      const Vec3 &p = T[k], &q = T[(k + 1) % 3];
      if (p[axis] >= s0 && p[axis] <= s1) add(p);
      for (const double cut : {s0, s1})
        if ((p[axis] - cut) * (q[axis] - cut) < 0) add(p + (cut - p[axis]) / (q[axis] - p[axis]) * (q - p));
    }
    if (!(plo[axis] <= phi[axis])) continue;  // (a slab the triangle misses: none, but rounding)
    plo[axis] = std::min(plo[axis], s0);
    phi[axis] = std::max(phi[axis], s1);
    lo.push_back(plo - grow);
    hi.push_back(phi + grow);
    tri.push_back(t);
  }
}

Bvh build_bvh(const PrintableMesh& m) {
  Bvh b;
  std::vector<Vec3> lo, hi;
  // at most kMaxPieces each, and kMaxBoxesPerTriangle per triangle of the mesh in all (a file of needles):
  // when more are wanted, each sliver gets its share
  const std::size_t nt = m.triangles.size();
  std::vector<int> want(nt);
  std::size_t wanted = 0, extra = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& w = m.triangles[t];
    const Vec3 T[3] = {m.vertices[w[0]], m.vertices[w[1]], m.vertices[w[2]]};
    want[t] = pieces_wanted(T);
    wanted += static_cast<std::size_t>(want[t]);
    extra += static_cast<std::size_t>(want[t] - 1);
  }
  const double share = wanted <= kMaxBoxesPerTriangle * nt
                           ? 1.0
                           : static_cast<double>((kMaxBoxesPerTriangle - 1) * nt) / static_cast<double>(extra);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& w = m.triangles[t];
    const Vec3 T[3] = {m.vertices[w[0]], m.vertices[w[1]], m.vertices[w[2]]};
    const int pieces = 1 + static_cast<int>(std::floor(share * (want[t] - 1)));
    triangle_boxes(T, static_cast<std::uint32_t>(t), pieces, lo, hi, b.tri);
  }
  const std::size_t n = lo.size();
  std::vector<Vec3> centre(n);
  for (std::size_t i = 0; i < n; ++i) centre[i] = (lo[i] + hi[i]) / 2;
  b.order.resize(n);
  std::iota(b.order.begin(), b.order.end(), 0u);
  b.nodes.reserve(2 * n / kLeafSize + 2);
  struct Job {
    std::uint32_t node, first, count;
  };
  std::vector<Job> stack;
  b.nodes.emplace_back();
  stack.push_back({0, 0, static_cast<std::uint32_t>(n)});
  while (!stack.empty()) {
    const Job j = stack.back();
    stack.pop_back();
    Vec3 blo = Vec3::Constant(std::numeric_limits<double>::infinity()), bhi = -blo;
    Vec3 clo = blo, chi = bhi;
    for (std::uint32_t k = j.first; k < j.first + j.count; ++k) {
      const std::uint32_t t = b.order[k];
      blo = blo.cwiseMin(lo[t]);
      bhi = bhi.cwiseMax(hi[t]);
      clo = clo.cwiseMin(centre[t]);
      chi = chi.cwiseMax(centre[t]);
    }
    b.nodes[j.node].lo = blo;
    b.nodes[j.node].hi = bhi;
    if (j.count <= kLeafSize) {
      b.nodes[j.node].first = j.first;
      b.nodes[j.node].count = j.count;
      continue;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const std::uint32_t half = j.count / 2;
    auto first = b.order.begin() + j.first;
    // ties broken by index: the tree, and so every result, is the same on every run
    std::nth_element(first, first + half, first + j.count, [&](std::uint32_t a, std::uint32_t c) {
      return centre[a][axis] < centre[c][axis] || (centre[a][axis] == centre[c][axis] && a < c);
    });
    const auto left = static_cast<std::uint32_t>(b.nodes.size());
    b.nodes.emplace_back();
    b.nodes.emplace_back();
    b.nodes[j.node].left = left;
    b.nodes[j.node].right = left + 1;
    stack.push_back({left, j.first, half});
    stack.push_back({left + 1, j.first + half, j.count - half});
  }
  return b;
}

bool shares_vertex(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b) {
  for (std::uint32_t i : a)
    if (i == b[0] || i == b[1] || i == b[2]) return true;
  return false;
}

/// Entry parameter of the ray into the box within [0, t_max], or infinity if it misses.
double enter_box(const Vec3& o, const Vec3& inv, const Vec3& lo, const Vec3& hi, double t_max) {
  double t0 = 0, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    double near = (lo[a] - o[a]) * inv[a], far = (hi[a] - o[a]) * inv[a];
    if (near > far) std::swap(near, far);
    if (std::isnan(near)) near = -std::numeric_limits<double>::infinity();  // 0 * inf: origin on the slab
    if (std::isnan(far)) far = std::numeric_limits<double>::infinity();
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

/// Möller-Trumbore; returns the ray parameter or a negative number.
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return -1;
  const double inv = 1 / det;
  const Vec3 s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return -1;
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0 || u + v > 1) return -1;
  return e2.dot(q) * inv;
}

}  // namespace

namespace {

using Stack = std::vector<std::pair<std::uint32_t, double>>;

/// The ray from `o` (on triangle `self`) along the unit vector `d` to the first triangle it meets farther
/// than `eps` that shares no corner with self (neighbours meet it only at folds of a crease or of a fine
/// mesh, not across the wall), or, if it meets none such, to the first other triangle (a coarse solid
/// whose faces all share corners, a tetrahedron; `through_neighbour` says so): the distance if the ray
/// leaves the solid there (that triangle faces along d), a negative number if it meets none or enters the
/// solid first, kGivenUp past kMaxVisits boxes.
double cast(const Bvh& bvh, const PrintableMesh& m, const Vec3& o, const Vec3& d, std::uint32_t self, double eps,
            Stack& stack, bool* through_neighbour) {
  const auto& own = m.triangles[self];
  const Vec3 inv = d.cwiseInverse();
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t best_tri = 0;
  std::size_t visits = 0;
  // depth first, nearer child first, each entry kept with the distance at which the ray enters it
  auto search = [&](bool neighbours) {
    stack.clear();
    if (std::isfinite(enter_box(o, inv, bvh.nodes[0].lo, bvh.nodes[0].hi, best))) stack.push_back({0, 0.0});
    while (!stack.empty()) {
      const auto [id, enter] = stack.back();
      stack.pop_back();
      if (enter > best) continue;
      if (++visits > kMaxVisits) return false;
      const Bvh::Node& nd = bvh.nodes[id];
      if (nd.count == 0) {
        const Bvh::Node &l = bvh.nodes[nd.left], &r = bvh.nodes[nd.right];
        const double tl = enter_box(o, inv, l.lo, l.hi, best), tr = enter_box(o, inv, r.lo, r.hi, best);
        const bool left_first = tl <= tr;
        const double t_far = left_first ? tr : tl, t_near = left_first ? tl : tr;
        if (std::isfinite(t_far)) stack.push_back({left_first ? nd.right : nd.left, t_far});
        if (std::isfinite(t_near)) stack.push_back({left_first ? nd.left : nd.right, t_near});
        continue;
      }
      for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) {
        const std::uint32_t u = bvh.tri[bvh.order[k]];  // a piece's triangle: tested whole
        const auto& h = m.triangles[u];
        if (neighbours ? u == self : shares_vertex(own, h)) continue;
        const double s = ray_triangle(o, d, m.vertices[h[0]], m.vertices[h[1]], m.vertices[h[2]]);
        if (s > eps && (s < best || (s == best && u < best_tri))) {
          best = s;
          best_tri = u;
        }
      }
    }
    return true;
  };
  if (!search(false)) return kGivenUp;
  *through_neighbour = !std::isfinite(best);
  if (*through_neighbour && !search(true)) return kGivenUp;
  if (!std::isfinite(best)) return -1;
  const auto& h = m.triangles[best_tri];
  const Vec3 hn = (m.vertices[h[1]] - m.vertices[h[0]]).cross(m.vertices[h[2]] - m.vertices[h[0]]);
  return hn.dot(d) > 0 ? best : -1;  // leaving the solid: a wall; else the ray went outside first
}

/// The inward unit normal of triangle t, or zero for a triangle of no area.
Vec3 inward(const PrintableMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  const Vec3 normal = (m.vertices[tri[1]] - m.vertices[tri[0]]).cross(m.vertices[tri[2]] - m.vertices[tri[0]]);
  const double len = normal.norm();
  return len > 0 ? Vec3(-normal / len) : Vec3::Zero();
}

Vec3 centroid(const PrintableMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  return (m.vertices[tri[0]] + m.vertices[tri[1]] + m.vertices[tri[2]]) / 3;
}

double longest_side(const PrintableMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  const Vec3 &a = m.vertices[tri[0]], &b = m.vertices[tri[1]], &c = m.vertices[tri[2]];
  return std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
}

/// Rays from the centroids (see triangle_thickness); `neighbour[t]` = 1 where t's ray met only neighbours.
std::vector<double> centroid_rays(const PrintableMesh& m, const Bvh& bvh, double eps, int threads,
                                  std::vector<std::uint8_t>& neighbour) {
  std::vector<double> out(m.triangles.size(), -1.0);
  neighbour.assign(m.triangles.size(), 0);
  core::parallel_for(
      m.triangles.size(), threads,
      [&](std::size_t begin, std::size_t end) {
        Stack stack;
        for (std::size_t t = begin; t < end; ++t) {
          const Vec3 d = inward(m, t);
          if (d == Vec3::Zero()) continue;
          bool through = false;
          out[t] = cast(bvh, m, centroid(m, t), d, static_cast<std::uint32_t>(t), eps, stack, &through);
          neighbour[t] = through;
        }
      },
      1024);
  return out;
}

/// Barycentric (u, v) of the centroid of sub-triangle k (0 <= k < level^2) of the regular subdivision of a
/// triangle into level^2: first the level (level + 1) / 2 upright ones, then the others.
std::array<double, 2> sub_centroid(int level, int k) {
  const int up = level * (level + 1) / 2;
  const bool upright = k < up;
  int rest = upright ? k : k - up, i = 0;
  const int rows = upright ? level : level - 1;  // row i holds rows - i of them
  while (rest >= rows - i) rest -= rows - i, ++i;
  const double third = upright ? 1.0 / 3 : 2.0 / 3;
  return {(i + third) / level, (rest + third) / level};
}

}  // namespace

std::vector<double> triangle_thickness(const PrintableMesh& m, int threads) {
  if (m.triangles.empty()) return {};
  const Bvh bvh = build_bvh(m);
  std::vector<std::uint8_t> neighbour;
  return centroid_rays(m, bvh, 1e-9 * (bvh.nodes[0].hi - bvh.nodes[0].lo).norm(), threads, neighbour);
}

ThicknessReport wall_thickness(const PrintableMesh& m, int threads) {
  ThicknessReport r;
  const std::size_t n = m.triangles.size();
  if (n == 0) return r;
  const Bvh bvh = build_bvh(m);
  const double eps = 1e-9 * (bvh.nodes[0].hi - bvh.nodes[0].lo).norm();  // closer hits: the ray's own start
  std::vector<std::uint8_t> th_neighbour;  // the centroid's ray met only neighbours of its triangle
  const std::vector<double> th = centroid_rays(m, bvh, eps, threads, th_neighbour);
  std::vector<double> areas(n), longest(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = m.triangles[t];
    const Vec3 &a = m.vertices[tri[0]], &b = m.vertices[tri[1]], &c = m.vertices[tri[2]];
    areas[t] = 0.5 * (b - a).cross(c - a).norm();
    longest[t] = longest_side(m, t);
  }
  // A triangle at least twice as long as its wall is thick gets level^2 rays, one from each sub-triangle of
  // its regular subdivision (level = longest side / thickness at its centroid, rounded down, at most
  // kMaxLevel): one ray from the centroid would miss how the wall changes across it (the large faces of a
  // coarse mesh: a wedge of two triangles a side). Each ray weighs its sub-triangle's area. A budget of
  // sub-rays keeps a check linear: over it, the largest level comes down until it fits. A mesh of few
  // triangles (a modeller's tetrahedron, prism or star) gets about kCoarseRays on its measured triangles
  // whatever their length: one ray per face would say a tetrahedron is as thick everywhere as at the
  // centres of its faces.
  const int coarse = static_cast<int>(
      std::min<double>(kMaxLevel, std::floor(std::sqrt(static_cast<double>(kCoarseRays) / static_cast<double>(n)))));
  std::vector<int> level(n, 1);
  auto wanted = [&](std::size_t t, int cap) {
    if (!(th[t] > 0)) return 1;
    const int by_length =
        longest[t] >= 2 * th[t] ? static_cast<int>(std::min<double>(kMaxLevel, std::floor(longest[t] / th[t]))) : 1;
    return std::min(cap, std::max(by_length, coarse));
  };
  const std::size_t budget = std::max<std::size_t>(kSubRayBudget, 4 * n);
  int cap = kMaxLevel;
  for (;; --cap) {
    std::size_t rays = 0;
    for (std::size_t t = 0; t < n; ++t) {
      level[t] = wanted(t, cap);
      if (level[t] > 1) rays += static_cast<std::size_t>(level[t] * level[t]);
    }
    if (rays <= budget || cap == 1) break;
  }
  std::vector<std::size_t> first(n + 1, 0);  // each refined triangle's sub-rays
  for (std::size_t t = 0; t < n; ++t)
    first[t + 1] = first[t] + (level[t] > 1 ? static_cast<std::size_t>(level[t] * level[t]) : 0);
  auto origin = [&](std::size_t t, int k) {
    const auto& tri = m.triangles[t];
    const auto [u, v] = sub_centroid(level[t], k);
    const Vec3& a = m.vertices[tri[0]];
    return Vec3(a + u * (m.vertices[tri[1]] - a) + v * (m.vertices[tri[2]] - a));
  };
  std::vector<double> sub(first[n], -1.0);
  std::vector<std::uint8_t> sub_neighbour(first[n], 0);
  core::parallel_for(
      n, threads,
      [&](std::size_t begin, std::size_t end) {
        Stack stack;
        for (std::size_t t = begin; t < end; ++t)
          for (int k = 0; k < (level[t] > 1 ? level[t] * level[t] : 0); ++k) {
            const std::size_t i = first[t] + static_cast<std::size_t>(k);
            bool through = false;
            sub[i] = cast(bvh, m, origin(t, k), inward(m, t), static_cast<std::uint32_t>(t), eps, stack, &through);
            sub_neighbour[i] = through;
          }
      },
      256);

  // the shortest ray leaves out slivers (a mesher's micrometre triangles at a voxel corner: the ray along
  // their noisy normal meets a neighbour of theirs, not the far wall) and rays that met only neighbours
  // (where a fine mesh folds over at a ridge, a ray can leave through a neighbour within a hair of its start)
  std::vector<double> sorted = areas;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double sliver = kSliverArea * sorted[sorted.size() / 2];
  std::vector<std::pair<double, double>> samples;  // (thickness, area)
  double total = 0, neighbours_area = 0;
  // the shortest ray of the non-slivers, with and without the rays that met only neighbours, and of all
  struct Shortest {
    bool found = false;
    double value = 0;
    Vec3 at = Vec3::Zero();
    void offer(double v, const Vec3& where) {
      if (!found || v < value) found = true, value = v, at = where;
    }
  } across, with_neighbours, any;
  auto sample = [&](std::size_t t, double value, double area, const Vec3& at, bool through_neighbour) {
    samples.emplace_back(value, area);
    total += area;
    if (through_neighbour) neighbours_area += area;
    any.offer(value, at);
    if (areas[t] < sliver) return;
    with_neighbours.offer(value, at);
    if (!through_neighbour) across.offer(value, at);
  };
  for (std::size_t t = 0; t < n; ++t) {
    if (!(areas[t] > 0)) continue;
    if (th[t] == kGivenUp) {
      ++r.given_up;
      continue;
    }
    if (th[t] < 0) {
      ++r.missed;
      continue;
    }
    ++r.samples;
    if (level[t] == 1) {
      sample(t, th[t], areas[t], centroid(m, t), th_neighbour[t]);
      continue;
    }
    // a sub-ray that finds no wall (it enters the solid again first, or is given up; or, in a mesh of many
    // triangles, it met only neighbours where the centroid's ray did not) leaves its part of the
    // area to the centroid's value, so the triangle weighs its whole area as before
    const double part = areas[t] / static_cast<double>(level[t] * level[t]);
    double unmeasured = 0;
    for (int k = 0; k < level[t] * level[t]; ++k) {
      const std::size_t i = first[t] + static_cast<std::size_t>(k);
      if (sub[i] >= 0 && (th_neighbour[t] || !sub_neighbour[i] || coarse > 1))
        sample(t, sub[i], part, origin(t, k), th_neighbour[t] || sub_neighbour[i]);  // a fold's, if th's was
      else
        unmeasured += part;
    }
    if (unmeasured > 0) {
      sample(t, th[t], unmeasured, centroid(m, t), th_neighbour[t]);
    }
  }
  if (samples.empty()) return r;
  // rays that met only neighbours are left out of the shortest where they are a fine mesh's odd folds (under
  // 1% of the measured surface, so p01 lies among the others); where they are more, a coarse solid's
  // thin parts (a prism's, a wedge's), they count
  const Shortest& shortest = !across.found                    ? (with_neighbours.found ? with_neighbours : any)
                             : neighbours_area < 0.01 * total ? across
                                                              : with_neighbours;
  r.min = shortest.value;
  r.min_at = shortest.at;
  std::sort(samples.begin(), samples.end());
  auto quantile = [&](double q) {
    double acc = 0;
    for (const auto& [value, area] : samples) {
      acc += area;
      if (acc >= q * total) return value;
    }
    return samples.back().first;
  };
  r.p01 = quantile(0.01);
  r.median = quantile(0.5);
  return r;
}

}  // namespace cellform::exporters
