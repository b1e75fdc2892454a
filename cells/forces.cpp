// Force kernels (Eqs. 2-6) and the gather-style acceleration pass over all cells.
#include "cells/forces.h"

#include <algorithm>
#include <cmath>

#include "cells/simulation.h"
#include "core/parallel.h"
#include "core/random.h"

namespace cellform::cells {

namespace {

bool contains(std::span<const Index> v, Index x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// Children of i, or an empty span when `children` was not computed for these cells.
std::span<const Index> children_of(const VeinChildren& children, Index i) {
  if (children.start.size() <= static_cast<std::size_t>(i) + 1) return {};
  return {children.child.data() + children.start[i], children.child.data() + children.start[i + 1]};
}

}  // namespace

Vec3 spring_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> neighbours, double rest_length) {
  if (neighbours.empty()) return Vec3::Zero();
  const Vec3& c = positions[self];
  Vec3 sum = Vec3::Zero();
  for (const Index r : neighbours) {
    const Vec3 delta = positions[r] - c;
    const double dist = delta.norm();
    if (dist > 0) {
      sum += ((dist - rest_length) / dist) * delta;
    } else {
      // coincident: pretend P lies along a direction of the pair (the smaller index's way round), so the two
      // cells are pushed apart in opposite directions; a direction differing from pair to pair, as along +x for
      // all a pile of coincident cells spread into a line along x, whatever the sheet's plane
      const Vec3 towards = core::StreamRng(core::stream_key(0, std::min(self, r), std::max(self, r))).unit_vector();
      sum -= rest_length * (r > self ? towards : Vec3(-towards));
    }
  }
  return sum / static_cast<double>(neighbours.size());
}

Vec3 planar_kernel(const Vec3& c, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  const Vec3 e1 = p2 - p1;
  const Vec3 e2 = p3 - p1;
  const Vec3 normal = e1.cross(e2);
  const double n2 = normal.squaredNorm();
  // sin^2 of the angle between the edges below 1e-12: no well-defined plane
  if (!(n2 > 1e-12 * e1.squaredNorm() * e2.squaredNorm())) return Vec3::Zero();
  return -((c - p1).dot(normal) / n2) * normal;
}

Vec3 cohesion_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> neighbours, double near) {
  if (neighbours.empty()) return Vec3::Zero();
  const Vec3& c = positions[self];
  const double near2 = near * near;
  Vec3 sum = Vec3::Zero();
  for (const Index r : neighbours) {
    const Vec3 delta = positions[r] - c;
    const double d2 = delta.squaredNorm();
    if (d2 > 0) sum += delta / std::max(d2, near2);
  }
  return sum / static_cast<double>(neighbours.size());
}

Vec3 separation_kernel(std::span<const Vec3> positions, Index self, std::span<const Index> others) {
  if (others.empty()) return Vec3::Zero();
  const Vec3& c = positions[self];
  Vec3 sum = Vec3::Zero();
  for (const Index r : others) {
    const Vec3 delta = c - positions[r];
    const double d2 = delta.squaredNorm();
    if (d2 > 0) sum += delta / d2;
  }
  return sum / static_cast<double>(others.size());
}

void direct_neighbours(const Cells& cells, const VeinChildren& children, Index i, std::vector<Index>& out) {
  out.clear();
  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  const Index* links = cells.links.data() + static_cast<std::size_t>(i) * stride;
  for (std::size_t j = 0; j < stride; ++j)
    if (links[j] != kNoIndex && links[j] != i) out.push_back(links[j]);
  const std::size_t linked = out.size();
  const std::span<const Index> linked_span(out.data(), linked);
  const Index parent = cells.vein_parent[i];
  if (parent != kNoIndex && parent != i && !contains(linked_span, parent)) out.push_back(parent);
  for (const Index c : children_of(children, i))
    if (!contains(std::span<const Index>(out.data(), linked), c)) out.push_back(c);
}

void second_ring(const Cells& cells, Index i, std::span<const Index> direct, std::vector<Index>& out) {
  out.clear();
  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  for (const Index r : direct) {
    const Index* links = cells.links.data() + static_cast<std::size_t>(r) * stride;
    for (std::size_t j = 0; j < stride; ++j) {
      const Index q = links[j];
      if (q == kNoIndex || q == i || contains(direct, q) || contains(out, q)) continue;
      out.push_back(q);
    }
  }
}

namespace {

// second_ring() into `dst` (room for direct.size() * link_stride entries); returns the count. mark[n]
// stands for every index that is not a cell (kNoIndex padding): marked up front, so never added.
std::size_t second_ring_into(const Cells& cells, Index i, std::span<const Index> direct, Index* dst, ForceScratch& s) {
  const std::size_t n = cells.size();
  const std::size_t stride = static_cast<std::size_t>(cells.link_stride);
  if (s.mark.size() < n + 1) s.mark.resize(n + 1, 0);
  if (++s.stamp == 0) {  // wrapped: forget every old mark
    std::fill(s.mark.begin(), s.mark.end(), 0);
    s.stamp = 1;
  }
  const std::uint32_t stamp = s.stamp;
  std::uint32_t* mark = s.mark.data();
  mark[n] = stamp;
  if (i < n) mark[i] = stamp;
  for (const Index r : direct)
    if (r < n) mark[r] = stamp;
  std::size_t count = 0;
  for (const Index r : direct) {
    const Index* links = cells.links.data() + static_cast<std::size_t>(r) * stride;
    for (std::size_t j = 0; j < stride; ++j) {  // branch-free: always write, advance only when new
      const Index q = links[j] < n ? links[j] : static_cast<Index>(n);
      const bool fresh = mark[q] != stamp;
      mark[q] = stamp;
      dst[count] = q;
      count += fresh;
    }
  }
  return count;
}

}  // namespace

void second_ring(const Cells& cells, Index i, std::span<const Index> direct, std::vector<Index>& out, ForceScratch& s) {
  out.resize(direct.size() * static_cast<std::size_t>(cells.link_stride));
  out.resize(second_ring_into(cells, i, direct, out.data(), s));
}

void vein_second_ring(const Cells& cells, const VeinChildren& children, Index i, std::vector<Index>& out) {
  out.clear();
  const Index parent = cells.vein_parent[i];
  if (parent != kNoIndex) {
    const Index grand = cells.vein_parent[parent];
    if (grand != kNoIndex && grand != i) out.push_back(grand);
  }
  for (const Index c : children_of(children, i))
    for (const Index g : children_of(children, c))
      if (g != i && !contains(out, g)) out.push_back(g);
}

Vec3 cell_acceleration(const Cells& cells, const Params& params, const VeinChildren& children, Index i,
                       ForceScratch& s) {
  if (cells.fixed[i]) return Vec3::Zero();
  const ForceWeights& w = params.weights[static_cast<std::size_t>(cells.type[i])];
  const std::span<const Vec3> pos(cells.position);
  direct_neighbours(cells, children, i, s.direct);
  Vec3 a = params.unary;
  if (w.spring != 0) a += w.spring * spring_kernel(pos, i, s.direct, params.rest_length);
  if (w.planar != 0) {
    // the three closest neighbours are the first three links (sorted by distance)
    const Index* links = cells.links.data() + static_cast<std::size_t>(i) * cells.link_stride;
    if (cells.link_stride >= 3 && links[0] != kNoIndex && links[1] != kNoIndex && links[2] != kNoIndex)
      a += w.planar * planar_kernel(pos[i], pos[links[0]], pos[links[1]], pos[links[2]]);
  }
  if (w.cohesion != 0) a += w.cohesion * cohesion_kernel(pos, i, s.direct, kCohesionNear * params.rest_length);
  if (w.separation != 0) {
    // s.ring only grows, so no element is initialised per cell
    const std::size_t room = s.direct.size() * static_cast<std::size_t>(cells.link_stride);
    if (s.ring.size() < room) s.ring.resize(std::max<std::size_t>(room, 256));
    const std::size_t count = second_ring_into(cells, i, s.direct, s.ring.data(), s);
    a += w.separation * separation_kernel(pos, i, std::span<const Index>(s.ring.data(), count));
  }
  const bool in_vein = cells.vein_parent[i] != kNoIndex || !children_of(children, i).empty();
  if (in_vein) {
    const double vc = w.cohesion * params.vein_cohesion_factor;
    if (vc != 0) {
      s.vein.clear();
      if (cells.vein_parent[i] != kNoIndex && cells.vein_parent[i] != i) s.vein.push_back(cells.vein_parent[i]);
      for (const Index c : children_of(children, i)) s.vein.push_back(c);
      a += vc * cohesion_kernel(pos, i, s.vein, kCohesionNear * params.rest_length);
    }
    const double vs = w.separation * params.vein_separation_factor;
    if (vs != 0) {
      vein_second_ring(cells, children, i, s.vein_ring);
      a += vs * separation_kernel(pos, i, s.vein_ring);
    }
  }
  return a;
}

void compute_accelerations(Cells& cells, const Params& params, const VeinChildren& children, int threads) {
  const std::size_t n = cells.size();
  cells.acceleration.resize(n);
  core::parallel_for(n, threads, [&](std::size_t begin, std::size_t end) {
    // per thread and kept between steps: the stamp array of second_ring has one entry per cell
    thread_local ForceScratch scratch;
    scratch.direct.reserve(64);
    for (std::size_t i = begin; i < end; ++i)
      cells.acceleration[i] = cell_acceleration(cells, params, children, static_cast<Index>(i), scratch);
  });
}

}  // namespace cellform::cells
