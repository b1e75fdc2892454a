// Incremental k-d tree and the neighbourhood queries of space colonisation (Runions et al. 2005, Eq. 2).
#include "venation/point_tree.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/spatial_index.h"
#include "venation/point_tree_detail.h"

namespace cellform::venation {

namespace {
constexpr double kPruneSlack = 1e-9;  // makes cone pruning conservative under rounding
}  // namespace

Index PointTree::insert(const Vec3& p) {
  const Index id = static_cast<Index>(points_.size());
  points_.push_back(p);
  index(id);
  return id;
}

void PointTree::insert_batch(std::span<const Vec3> points) {
  if (points.empty()) return;
  const auto first = static_cast<Index>(points_.size());
  points_.insert(points_.end(), points.begin(), points.end());
  // Morton cells of the batch's extent / 2^21 (core::spatial_order: ties by index, non-finite last)
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double side = (hi - lo).maxCoeff();
  const double cell = side > 0 && std::isfinite(side) ? side / 0x1fffff : 1.0;
  for (Index k : core::spatial_order(points, cell)) index(first + k);
}

void PointTree::index(Index id) {
  const Vec3& p = points_[id];
  if (nodes_.empty()) {
    Node leaf;
    leaf.lo = leaf.hi = p;
    leaf.pts.push_back(id);
    leaf.count = 1;
    nodes_.push_back(std::move(leaf));
    return;
  }
  path_.clear();
  int n = 0;
  for (;;) {
    path_.push_back(n);
    Node& nd = nodes_[n];
    nd.lo = nd.lo.cwiseMin(p);
    nd.hi = nd.hi.cwiseMax(p);
    ++nd.count;
    if (nd.child[0] < 0) break;
    n = nd.child[p[nd.dim] < nd.split ? 0 : 1];
  }
  nodes_[n].pts.push_back(id);
  if (nodes_[n].pts.size() > static_cast<std::size_t>(kBucket)) split_leaf(n);
  // scapegoat rebalancing: points arrive along growing veins, so plain insertion degenerates into a
  // chain; rebuild the topmost subtree in which one child holds more than 3/4 of the points
  for (int m : path_) {
    const Node& nd = nodes_[m];
    if (nd.child[0] < 0 || nd.count < 4 * kBucket) continue;
    const std::uint32_t big = std::max(nodes_[nd.child[0]].count, nodes_[nd.child[1]].count);
    if (4 * big > 3 * nd.count) {
      rebuild(m);
      break;
    }
  }
}

void PointTree::assign(std::span<const Vec3> points) {
  clear();
  if (points.empty()) return;
  points_.assign(points.begin(), points.end());
  scratch_ids_.resize(points_.size());
  for (Index i = 0; i < points_.size(); ++i) scratch_ids_[i] = i;
  nodes_.emplace_back();
  build(0, scratch_ids_.data(), scratch_ids_.data() + scratch_ids_.size());
}

void PointTree::clear() {
  points_.clear();
  nodes_.clear();
  garbage_ = 0;
}

void PointTree::collect(int n, std::vector<Index>& out) {
  Node& nd = nodes_[n];
  if (nd.child[0] < 0) {
    out.insert(out.end(), nd.pts.begin(), nd.pts.end());
    return;
  }
  collect(nd.child[0], out);
  collect(nd.child[1], out);
  garbage_ += 2;
}

void PointTree::rebuild(int n) {
  scratch_ids_.clear();
  collect(n, scratch_ids_);
  if (garbage_ > nodes_.size() / 2) {  // compact: rebuild everything into a fresh node array
    // every point in the tree, in index order (not all of points_: a batch may be partly inserted)
    scratch_ids_.clear();
    collect(0, scratch_ids_);
    std::sort(scratch_ids_.begin(), scratch_ids_.end());
    nodes_.clear();
    nodes_.emplace_back();
    garbage_ = 0;
    n = 0;
  }
  build(n, scratch_ids_.data(), scratch_ids_.data() + scratch_ids_.size());
}

void PointTree::build(int n, Index* first, Index* last) {
  Node nd;
  nd.count = static_cast<std::uint32_t>(last - first);
  nd.lo = nd.hi = points_[*first];
  for (Index* it = first; it != last; ++it) {
    nd.lo = nd.lo.cwiseMin(points_[*it]);
    nd.hi = nd.hi.cwiseMax(points_[*it]);
  }
  const Vec3 ext = nd.hi - nd.lo;
  int dim = 0;
  if (ext[1] > ext[dim]) dim = 1;
  if (ext[2] > ext[dim]) dim = 2;
  Index* mid = first;
  double split = 0;
  if (last - first > kBucket && ext[dim] > 0) {
    Index* median = first + (last - first) / 2;
    std::nth_element(first, median, last, [&](Index a, Index b) { return points_[a][dim] < points_[b][dim]; });
    split = points_[*median][dim];
    mid = std::partition(first, last, [&](Index i) { return points_[i][dim] < split; });
    if (mid == first) {  // many equal to the minimum: put them left, split just above
      mid = std::partition(first, last, [&](Index i) { return points_[i][dim] <= split; });
      split = std::nextafter(split, std::numeric_limits<double>::infinity());
    }
  }
  if (mid == first || mid == last) {
    nd.pts.assign(first, last);
    nodes_[n] = std::move(nd);
    return;
  }
  nd.dim = dim;
  nd.split = split;
  const int c0 = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nd.child[0] = c0;
  nd.child[1] = c0 + 1;
  nodes_[n] = std::move(nd);
  build(c0, first, mid);
  build(c0 + 1, mid, last);
}

void PointTree::split_leaf(int n) {
  const Vec3 ext = nodes_[n].hi - nodes_[n].lo;
  int dim = 0;
  if (ext[1] > ext[dim]) dim = 1;
  if (ext[2] > ext[dim]) dim = 2;
  if (!(ext[dim] > 0)) return;  // all points coincide: keep one larger leaf
  const double split = 0.5 * (nodes_[n].lo[dim] + nodes_[n].hi[dim]);
  Node kids[2];
  for (Index i : nodes_[n].pts) {
    Node& k = kids[points_[i][dim] < split ? 0 : 1];
    if (k.pts.empty()) k.lo = k.hi = points_[i];
    k.lo = k.lo.cwiseMin(points_[i]);
    k.hi = k.hi.cwiseMax(points_[i]);
    k.pts.push_back(i);
    ++k.count;
  }
  const int c0 = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(kids[0]));
  nodes_.push_back(std::move(kids[1]));
  Node& nd = nodes_[n];
  nd.pts.clear();
  nd.pts.shrink_to_fit();
  nd.child[0] = c0;
  nd.child[1] = c0 + 1;
  nd.dim = dim;
  nd.split = split;
}

void PointTree::expand(const Node& nd, const Vec3& s, std::vector<std::pair<double, std::int64_t>>& heap) const {
  const auto cmp = std::greater<>();
  if (nd.child[0] < 0) {
    for (Index i : nd.pts) {
      heap.emplace_back((points_[i] - s).squaredNorm(), ~static_cast<std::int64_t>(i));
      std::push_heap(heap.begin(), heap.end(), cmp);
    }
  } else {
    for (int c : nd.child) {
      heap.emplace_back(mindist2(nodes_[c], s), c);
      std::push_heap(heap.begin(), heap.end(), cmp);
    }
  }
}

double PointTree::mindist2(const Node& nd, const Vec3& q) const { return box_distance2(nd.lo, nd.hi, q); }

namespace {
constexpr double kSector = M_PI / 3;  // six fixed 60-degree sectors around the query

}  // namespace

int PointTree::sector(double dx, double dy) {
  constexpr double t = 1.7320508075688772;  // tan 60 degrees
  if (dy > 0 || (dy == 0 && dx >= 0)) return dy < t * dx ? 0 : (dy > -t * dx ? 1 : 2);
  return dy > t * dx ? 3 : (dy < -t * dx ? 4 : 5);
}

// In the plane: a relative neighbour v of s is the nearest point in the 60-degree cone around its own
// direction (any closer point within 60 degrees lies in the lune), so it is the nearest point of the
// fixed 60-degree sector that holds it. One best-first pass finds the nearest point of each of the six
// sectors; a box is skipped once every sector it overlaps has a nearer point. The (at most six)
// candidates are then checked exactly with lune_occupied().
void PointTree::relative_neighbourhood_planar(const Vec3& s, std::vector<Index>& out, Scratch& sc) const {
  Index best[6];
  double best_d2[6];
  sector_nearest(s, best, best_d2, sc);
  out.clear();
  for (int k = 0; k < 6; ++k)
    if (best[k] != kNoIndex && !lune_occupied(s, best[k])) out.push_back(best[k]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void PointTree::sector_nearest(const Vec3& s, Index* best, double* best_d2, Scratch& sc, bool reset,
                               const Vec3* best_pos, Index offset) const {
  double best_dx[6], best_dy[6];
  bool have_pos[6];
  for (int k = 0; k < 6; ++k) {
    if (reset) {
      best_d2[k] = std::numeric_limits<double>::infinity();
      best[k] = kNoIndex;
    }
    have_pos[k] = best[k] != kNoIndex && best_pos;
    best_dx[k] = have_pos[k] ? best_pos[k].x() - s.x() : 0;
    best_dy[k] = have_pos[k] ? best_pos[k].y() - s.y() : 0;
  }
  if (nodes_.empty()) return;
  auto& heap = sc.heap;
  heap.clear();
  const auto cmp = std::greater<>();
  heap.emplace_back(mindist2(nodes_[0], s), 0);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    const auto [d2, id] = heap.back();
    heap.pop_back();
    const Node& nd = nodes_[id];
    // The box is needed if some sector it overlaps has no point nearer than the box, unless one best
    // point u at most as far as the box sees the whole box within 60 degrees of its own direction
    // (then u excludes every point in the box, Eq. 2). Corner sectors are taken relative to the sector
    // of the box centre: a box not holding s spans less than 180 degrees, so they differ by at most 2.
    bool needed = d2 == 0;
    if (!needed) {
      const double cx = 0.5 * (nd.lo.x() + nd.hi.x()) - s.x(), cy = 0.5 * (nd.lo.y() + nd.hi.y()) - s.y();
      const int kc = sector(cx, cy);
      int rmin = 0, rmax = 0;
      double cdx[4], cdy[4];
      for (int c = 0; c < 4; ++c) {
        cdx[c] = ((c & 1) ? nd.hi.x() : nd.lo.x()) - s.x();
        cdy[c] = ((c & 2) ? nd.hi.y() : nd.lo.y()) - s.y();
        int r = sector(cdx[c], cdy[c]) - kc;
        if (r > 3) r -= 6;
        if (r < -3) r += 6;
        rmin = std::min(rmin, r);
        rmax = std::max(rmax, r);
      }
      // a corner exactly on a sector boundary may be rounded into the neighbour: widen by one
      rmin -= 1;
      rmax += 1;
      for (int r = rmin; r <= rmax && !needed; ++r) needed = best_d2[((kc + r) % 6 + 6) % 6] >= d2;
      if (needed && rmax - rmin < 5) {
        for (int j = 0; j < 6 && needed; ++j) {
          if (!(best_d2[j] <= d2) || !(best_d2[j] > 0) || !have_pos[j]) continue;
          bool inside = true;
          for (int c = 0; c < 4 && inside; ++c) {
            const double dot = cdx[c] * best_dx[j] + cdy[c] * best_dy[j];
            const double c2 = cdx[c] * cdx[c] + cdy[c] * cdy[c];
            inside = dot > 0 && dot * dot >= (0.25 + 1e-9) * c2 * best_d2[j];
          }
          needed = !inside;
        }
      }
    }
    if (!needed) continue;
    if (nd.child[0] < 0) {
      for (Index i : nd.pts) {
        const Vec3 d = points_[i] - s;
        const double pd2 = d.squaredNorm();
        const int k = sector(d.x(), d.y());
        if (pd2 < best_d2[k] || (pd2 == best_d2[k] && i + offset < best[k])) {
          best_d2[k] = pd2;
          best[k] = i + offset;
          best_dx[k] = d.x();
          best_dy[k] = d.y();
          have_pos[k] = true;
        }
      }
    } else {
      for (int c : nd.child) {
        heap.emplace_back(mindist2(nodes_[c], s), c);
        std::push_heap(heap.begin(), heap.end(), cmp);
      }
    }
  }
}

bool PointTree::nearest_rec(int n, const Vec3& q, Index& best, double& best_d2) const {
  const Node& nd = nodes_[n];
  if (mindist2(nd, q) > best_d2) return false;
  if (nd.child[0] < 0) {
    bool changed = false;
    for (Index i : nd.pts) {
      const double d2 = (points_[i] - q).squaredNorm();
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = i;
        changed = true;
      }
    }
    return changed;
  }
  const int first = q[nd.dim] < nd.split ? 0 : 1;
  bool a = nearest_rec(nd.child[first], q, best, best_d2);
  bool b = nearest_rec(nd.child[1 - first], q, best, best_d2);
  return a || b;
}

bool PointTree::margin_rec(int n, const Vec3& s, Index c, const Vec3& pc, double t) const {
  const Node& nd = nodes_[n];
  if (nd.child[0] < 0) {
    for (Index i : nd.pts)
      if (i != c && (points_[i] - s).norm() - (points_[i] - pc).norm() < t) return false;
    return true;
  }
  // |v - s| - |v - n| >= (a) the nearest box point to s minus the farthest from n, and (b) for a box on
  // n's side of the bisector, 2 |n - s| h / (|v - s| + |v - n|) with h the box's least distance past
  // the bisector (|v - s|^2 - |v - n|^2 = 2 (v - m) . (n - s), m the midpoint), the denominator at
  // most the farthest box points. A child whose bound reaches t is skipped; the other child first
  // (a point below t ends the search).
  const Vec3 d = pc - s;
  const double r0 = d.norm();
  const Vec3 u = d / r0, m = 0.5 * (s + pc);
  double lb[2];
  for (int k = 0; k < 2; ++k) {
    const Node& ch = nodes_[nd.child[k]];
    const Vec3 far_n = (ch.lo - pc).cwiseAbs().cwiseMax((ch.hi - pc).cwiseAbs());
    lb[k] = std::sqrt(mindist2(ch, s)) - far_n.norm();
    if (lb[k] >= t) continue;
    const Vec3 centre = 0.5 * (ch.lo + ch.hi), half = 0.5 * (ch.hi - ch.lo);
    const double h = (centre - m).dot(u) - half.dot(u.cwiseAbs());
    if (h > 0) {
      const Vec3 far_s = (ch.lo - s).cwiseAbs().cwiseMax((ch.hi - s).cwiseAbs());
      lb[k] = std::max(lb[k], 2 * r0 * h / (far_s.norm() + far_n.norm()));
    }
  }
  const int first = lb[0] <= lb[1] ? 0 : 1;
  return (lb[first] >= t || margin_rec(nd.child[first], s, c, pc, t)) &&
         (lb[1 - first] >= t || margin_rec(nd.child[1 - first], s, c, pc, t));
}

bool PointTree::margin_at_least(const Vec3& s, Index n, double t) const {
  return nodes_.empty() || margin_rec(0, s, n, points_[n], t);
}

bool PointTree::nearest(const Vec3& q, Index& best, double& best_d2) const {
  if (best == kNoIndex) best_d2 = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best != kNoIndex;
  nearest_rec(0, q, best, best_d2);
  return best != kNoIndex;
}

bool PointTree::any_within_rec(int n, const Vec3& q, double r2, Index exclude) const {
  const Node& nd = nodes_[n];
  if (mindist2(nd, q) > r2) return false;
  if (nd.child[0] >= 0) {  // the side of q first: a hit there ends the search soonest
    const int first = q[nd.dim] < nd.split ? 0 : 1;
    return any_within_rec(nd.child[first], q, r2, exclude) || any_within_rec(nd.child[1 - first], q, r2, exclude);
  }
  for (Index i : nd.pts)
    if (i != exclude && (points_[i] - q).squaredNorm() <= r2) return true;
  return false;
}

bool PointTree::any_within(const Vec3& q, double r2, Index exclude) const {
  return !nodes_.empty() && any_within_rec(0, q, r2, exclude);
}

void PointTree::within(const Vec3& q, double r2, std::vector<Index>& out) const {
  if (nodes_.empty()) return;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& nd = nodes_[stack.back()];
    stack.pop_back();
    if (mindist2(nd, q) > r2) continue;
    if (nd.child[0] < 0) {
      for (Index i : nd.pts)
        if ((points_[i] - q).squaredNorm() <= r2) out.push_back(i);
    } else {
      stack.push_back(nd.child[1]);
      stack.push_back(nd.child[0]);
    }
  }
}

// The closed lune of s and v (radius r = |v - s|) lies in the disc about the midpoint m of radius
using detail::Lune;

bool PointTree::lune_rec(int n, const Lune& l, Index v) const {
  const Node& nd = nodes_[n];
  if (mindist2(nd, l.m) > l.m2 || mindist2(nd, l.s) > l.r2 || mindist2(nd, l.v) > l.r2) return false;
  if (nd.child[0] >= 0) {
    const int first = l.m[nd.dim] < nd.split ? 0 : 1;
    return lune_rec(nd.child[first], l, v) || lune_rec(nd.child[1 - first], l, v);
  }
  for (Index u : nd.pts)
    if (u != v && l.holds(points_[u])) return true;
  return false;
}

bool PointTree::any_in_lune(const Vec3& s, const Vec3& v) const {
  return !nodes_.empty() && lune_rec(0, Lune(s, v), kNoIndex);
}

bool PointTree::lune_occupied(const Vec3& s, Index v) const {
  return !nodes_.empty() && lune_rec(0, Lune(s, points_[v]), v);
}

void PointTree::relative_neighbourhood(const Vec3& s, std::vector<Index>& out, Scratch& sc) const {
  out.clear();
  if (nodes_.empty()) return;
  if (nodes_[0].lo.z() == s.z() && nodes_[0].hi.z() == s.z()) {
    relative_neighbourhood_planar(s, out, sc);
    return;
  }
  auto& heap = sc.heap;
  heap.clear();
  sc.found.clear();
  sc.found_d2.clear();
  sc.corner_dir.clear();  // unit directions from s to found points (zero for a point at s)
  const auto cmp = std::greater<>();
  heap.emplace_back(mindist2(nodes_[0], s), 0);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    const auto [d2, id] = heap.back();
    heap.pop_back();
    if (id < 0) {
      const Index v = static_cast<Index>(~id);
      const Vec3& pv = points_[v];
      bool blocked = false;
      for (Index f : sc.found)
        if ((points_[f] - pv).squaredNorm() <= d2) {
          blocked = true;
          break;
        }
      if (!blocked) out.push_back(v);
      sc.found.push_back(v);
      sc.found_d2.push_back(d2);
      const double len = std::sqrt(d2);
      sc.corner_dir.push_back(len > 0 ? Vec3((pv - s) / len) : Vec3::Zero());
      continue;
    }
    const Node& nd = nodes_[id];
    // skip the subtree if one visited point u excludes all of it: every point p in the box is at least
    // as far from s as u and within 60 degrees of the direction of u, hence |p - u| <= |p - s|.
    bool pruned = false;
    Vec3 corners[8];
    bool have_corners = false;
    for (std::size_t k = 0; k < sc.found.size() && !pruned; ++k) {
      if (!(sc.found_d2[k] > 0) || d2 < sc.found_d2[k] * (1 + kPruneSlack)) continue;
      if (!have_corners) {
        for (int c = 0; c < 8; ++c) {
          const Vec3 p((c & 1) ? nd.hi.x() : nd.lo.x(), (c & 2) ? nd.hi.y() : nd.lo.y(),
                       (c & 4) ? nd.hi.z() : nd.lo.z());
          corners[c] = (p - s).normalized();
        }
        have_corners = true;
      }
      pruned = true;
      for (int c = 0; c < 8 && pruned; ++c)
        if (corners[c].dot(sc.corner_dir[k]) < 0.5 + kPruneSlack) pruned = false;
    }
    if (pruned) continue;
    expand(nd, s, heap);
  }
  // exact final check (covers distance ties, where visiting order alone could miss a blocker)
  std::erase_if(out, [&](Index v) { return lune_occupied(s, v); });
  std::sort(out.begin(), out.end());
}

}  // namespace cellform::venation
