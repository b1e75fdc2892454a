// Voronoi cells, Delaunay and Urquhart neighbourhoods of a point among the tree's points, in the plane
// (the Urquhart approximation of the relative neighbourhood, Runions et al. 2005, Section 5).
#include <algorithm>
#include <cmath>

#include "venation/point_tree.h"

namespace cellform::venation {

void VoronoiCell::reset(const Vec3& s, double half_extent) {
  poly = {{s.x() - half_extent, s.y() - half_extent, -1},
          {s.x() + half_extent, s.y() - half_extent, -1},
          {s.x() + half_extent, s.y() + half_extent, -1},
          {s.x() - half_extent, s.y() + half_extent, -1}};
  r2max = 2 * half_extent * half_extent;
}

bool VoronoiCell::clip(const Vec3& s, const Vec3& u, Index label, std::vector<Vertex>& next) {
  // half-plane closer to s than to u: a . x <= b
  const double ax = u.x() - s.x(), ay = u.y() - s.y();
  const double b = 0.5 * (ax * (u.x() + s.x()) + ay * (u.y() + s.y()));
  next.clear();
  bool changed = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vertex& P = poly[i];
    const Vertex& Q = poly[(i + 1) % n];
    const double fp = ax * P.x + ay * P.y - b, fq = ax * Q.x + ay * Q.y - b;
    const bool in_p = fp <= 0, in_q = fq <= 0;
    changed |= !in_p;
    if (in_p) next.push_back(P);
    if (in_p != in_q) {
      const double t = fp / (fp - fq);
      next.push_back({P.x + t * (Q.x - P.x), P.y + t * (Q.y - P.y), in_p ? static_cast<std::int64_t>(label) : P.label});
    }
  }
  if (!changed) return false;
  poly.swap(next);
  r2max = 0;
  for (const Vertex& p : poly) r2max = std::max(r2max, (p.x - s.x()) * (p.x - s.x()) + (p.y - s.y()) * (p.y - s.y()));
  return true;
}

void VoronoiCell::neighbours(double tiny, std::vector<Index>& out) const {
  out.clear();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vertex& P = poly[i];
    const Vertex& Q = poly[(i + 1) % poly.size()];
    if (P.label >= 0 && std::hypot(Q.x - P.x, Q.y - P.y) > tiny) out.push_back(static_cast<Index>(P.label));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void PointTree::voronoi_cell(const Vec3& s, double half_extent, VoronoiCell& cell, Scratch& sc,
                             std::size_t max_points) const {
  cell.reset(s, half_extent);
  if (nodes_.empty()) return;
  std::vector<VoronoiCell::Vertex> next;
  std::size_t clipped = 0;
  auto& heap = sc.heap;
  heap.clear();
  const auto cmp = std::greater<>();
  heap.emplace_back(mindist2(nodes_[0], s), 0);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    const auto [d2, id] = heap.back();
    heap.pop_back();
    if (d2 > 4 * cell.r2max) break;  // farther than twice the cell's radius: cannot clip it
    if (id >= 0) {
      expand(nodes_[id], s, heap);
      continue;
    }
    if (!(d2 > 0)) continue;
    if (++clipped > max_points) break;
    const auto u = static_cast<Index>(~id);
    cell.clip(s, points_[u], u, next);
    if (cell.poly.size() < 3) break;
  }
}

void PointTree::delaunay_neighbourhood(const Vec3& s, double half_extent, std::vector<Index>& out, Scratch& sc,
                                       std::size_t max_points) const {
  out.clear();
  if (nodes_.empty()) return;
  VoronoiCell cell;
  voronoi_cell(s, half_extent, cell, sc, max_points);
  cell.neighbours(1e-12 * half_extent, out);
}

void PointTree::urquhart_filter(const Vec3& s, const std::vector<Index>& dn, std::vector<Index>& out) const {
  out.clear();
  for (Index v : dn) {
    const double r2 = (points_[v] - s).squaredNorm();
    bool excluded = false;
    for (Index u : dn)
      if (u != v && (points_[u] - s).squaredNorm() <= r2 && (points_[u] - points_[v]).squaredNorm() <= r2) {
        excluded = true;
        break;
      }
    if (!excluded) out.push_back(v);
  }
}

void PointTree::urquhart_neighbourhood(const Vec3& s, double half_extent, std::vector<Index>& out, Scratch& sc,
                                       std::size_t max_points) const {
  std::vector<Index> dn;
  delaunay_neighbourhood(s, half_extent, dn, sc, max_points);
  urquhart_filter(s, dn, out);
}

}  // namespace cellform::venation
