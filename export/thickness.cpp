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

std::vector<double> triangle_thickness(const PrintableMesh& m, int threads) {
  const std::size_t n = m.triangles.size();
  std::vector<double> out(n, -1.0);
  if (n == 0) return out;
  const Bvh bvh = build_bvh(m);
  const double extent = (bvh.nodes[0].hi - bvh.nodes[0].lo).norm();
  const double eps = 1e-9 * extent;  // rays start at a centroid; hits closer than this are that triangle's own
  core::parallel_for(
      n, threads,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::pair<std::uint32_t, double>> stack;
        for (std::size_t t = begin; t < end; ++t) {
          const auto& tri = m.triangles[t];
          const Vec3 &a = m.vertices[tri[0]], &b = m.vertices[tri[1]], &c = m.vertices[tri[2]];
          const Vec3 normal = (b - a).cross(c - a);
          const double len = normal.norm();
          if (!(len > 0)) continue;
          const Vec3 d = -normal / len;
          const Vec3 o = (a + b + c) / 3;
          const Vec3 inv = d.cwiseInverse();
          double best = std::numeric_limits<double>::infinity();
          std::uint32_t best_tri = 0;
          // depth first, nearer child first, each entry kept with the distance at which the ray enters it
          stack.clear();
          if (std::isfinite(enter_box(o, inv, bvh.nodes[0].lo, bvh.nodes[0].hi, best))) stack.push_back({0, 0.0});
          std::size_t visits = 0;
          while (!stack.empty()) {
            const auto [id, enter] = stack.back();
            stack.pop_back();
            if (enter > best) continue;
            if (++visits > kMaxVisits) break;
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
              if (shares_vertex(tri, h)) continue;  // itself, or a fold at a crease: not the opposite wall
              const double s = ray_triangle(o, d, m.vertices[h[0]], m.vertices[h[1]], m.vertices[h[2]]);
              if (s > eps && (s < best || (s == best && u < best_tri))) {
                best = s;
                best_tri = u;
              }
            }
          }
          if (visits > kMaxVisits) {
            out[t] = kGivenUp;
            continue;
          }
          if (!std::isfinite(best)) continue;
          const auto& h = m.triangles[best_tri];
          const Vec3 hn = (m.vertices[h[1]] - m.vertices[h[0]]).cross(m.vertices[h[2]] - m.vertices[h[0]]);
          if (hn.dot(d) > 0) out[t] = best;  // leaving the solid: a wall; else the ray went outside first
        }
      },
      1024);
  return out;
}

ThicknessReport wall_thickness(const PrintableMesh& m, int threads) {
  ThicknessReport r;
  const std::vector<double> th = triangle_thickness(m, threads);
  std::vector<std::pair<double, double>> samples;  // (thickness, area)
  std::vector<double> areas(th.size());
  for (std::size_t t = 0; t < th.size(); ++t) {
    const auto& tri = m.triangles[t];
    areas[t] = 0.5 * (m.vertices[tri[1]] - m.vertices[tri[0]]).cross(m.vertices[tri[2]] - m.vertices[tri[0]]).norm();
  }
  // the shortest ray leaves out slivers (a mesher's micrometre triangles at a voxel corner): the ray along
  // their noisy normal meets a neighbour of theirs, not the far wall
  std::vector<double> sorted = areas;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double sliver = sorted.empty() ? 0.0 : kSliverArea * sorted[sorted.size() / 2];
  double total = 0;
  bool min_found = false;
  double any_min = 0;  // the shortest ray of all, for a mesh of slivers only
  Vec3 any_at = Vec3::Zero();
  for (std::size_t t = 0; t < th.size(); ++t) {
    const auto& tri = m.triangles[t];
    const double area = areas[t];
    if (!(area > 0)) continue;
    if (th[t] == kGivenUp) {
      ++r.given_up;
      continue;
    }
    if (th[t] < 0) {
      ++r.missed;
      continue;
    }
    samples.emplace_back(th[t], area);
    total += area;
    if (r.samples == 0 || th[t] < any_min) {
      any_min = th[t];
      any_at = (m.vertices[tri[0]] + m.vertices[tri[1]] + m.vertices[tri[2]]) / 3;
    }
    if (area >= sliver && (!min_found || th[t] < r.min)) {
      min_found = true;
      r.min = th[t];
      r.min_at = (m.vertices[tri[0]] + m.vertices[tri[1]] + m.vertices[tri[2]]) / 3;
    }
    ++r.samples;
  }
  if (samples.empty()) return r;
  if (!min_found) {
    r.min = any_min;
    r.min_at = any_at;
  }
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
