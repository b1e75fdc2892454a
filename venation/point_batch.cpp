// PointBatch: the vein nodes added in one step, queried by every source (nearest, sector bests, lunes).
#include <algorithm>
#include <limits>

#include "venation/point_tree.h"
#include "venation/point_tree_detail.h"

namespace cellform::venation {

using detail::Lune;

void PointBatch::assign(std::span<const Vec3> points, Index offset) {
  const auto n = static_cast<int>(points.size());
  pos_.assign(points.begin(), points.end());
  id_.resize(points.size());
  for (int i = 0; i < n; ++i) id_[static_cast<std::size_t>(i)] = offset + static_cast<Index>(i);
  nodes_.clear();
  if (n == 0) return;
  nodes_.emplace_back();
  build(0, 0, n);
}

// Fills node n with the points [first, last) of pos_ and id_, sorting them into its subtree.
void PointBatch::build(int n, int first, int last) {
  Vec3 lo = pos_[first], hi = pos_[first];
  for (int i = first + 1; i < last; ++i) {
    lo = lo.cwiseMin(pos_[i]);
    hi = hi.cwiseMax(pos_[i]);
  }
  Node& nd = nodes_[n];
  nd.lo = lo;
  nd.hi = hi;
  nd.first = first;
  nd.last = last;
  const Vec3 ext = hi - lo;
  int dim = 0;
  if (ext[1] > ext[dim]) dim = 1;
  if (ext[2] > ext[dim]) dim = 2;
  if (last - first <= kLeaf || !(ext[dim] > 0)) return;
  const int mid = first + (last - first) / 2;
  order_.resize(static_cast<std::size_t>(last - first));
  for (int i = first; i < last; ++i) order_[static_cast<std::size_t>(i - first)] = i;
  std::nth_element(order_.begin(), order_.begin() + (mid - first), order_.end(),
                   [&](int a, int b) { return pos_[a][dim] < pos_[b][dim]; });
  tmp_pos_.resize(order_.size());
  tmp_id_.resize(order_.size());
  for (std::size_t k = 0; k < order_.size(); ++k) {
    tmp_pos_[k] = pos_[order_[k]];
    tmp_id_[k] = id_[order_[k]];
  }
  std::copy(tmp_pos_.begin(), tmp_pos_.end(), pos_.begin() + first);
  std::copy(tmp_id_.begin(), tmp_id_.end(), id_.begin() + first);
  const int c = static_cast<int>(nodes_.size());
  nodes_[n].child = c;
  nodes_[n].dim = dim;
  nodes_[n].split = pos_[mid][dim];  // lower child <= split <= upper child
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(c, first, mid);
  build(c + 1, mid, last);
}

double PointBatch::mindist2(const Node& nd, const Vec3& q) const { return box_distance2(nd.lo, nd.hi, q); }

void PointBatch::nearest(const Vec3& q, Index& best, double& best_d2, bool* tie) const {
  if (best == kNoIndex) best_d2 = std::numeric_limits<double>::infinity();
  if (tie) *tie = false;
  if (nodes_.empty()) return;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (mindist2(nd, q) > best_d2) continue;
    if (nd.child < 0) {
      for (int i = nd.first; i < nd.last; ++i) {
        const double d2 = (pos_[i] - q).squaredNorm();
        if (tie && d2 <= best_d2) *tie = d2 == best_d2 && id_[i] != best;  // a nearer point clears it
        if (d2 < best_d2 || (d2 == best_d2 && id_[i] < best)) {
          best_d2 = d2;
          best = id_[i];
        }
      }
      continue;
    }
    const int near = q[nd.dim] <= nd.split ? 0 : 1;
    stack[top++] = nd.child + 1 - near;
    stack[top++] = nd.child + near;
  }
}

bool PointBatch::any_within(const Vec3& q, double r2) const {
  if (nodes_.empty()) return false;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (mindist2(nd, q) > r2) continue;
    if (nd.child < 0) {
      for (int i = nd.first; i < nd.last; ++i)
        if ((pos_[i] - q).squaredNorm() <= r2) return true;
      continue;
    }
    const int near = q[nd.dim] <= nd.split ? 0 : 1;
    stack[top++] = nd.child + 1 - near;
    stack[top++] = nd.child + near;
  }
  return false;
}

void PointBatch::clippers(const Vec3& s, const VoronoiCell& cell, std::vector<std::pair<double, Index>>& out) const {
  if (nodes_.empty() || cell.poly.empty()) return;
  constexpr std::size_t kMax = 64;
  const std::size_t nv = std::min(cell.poly.size(), kMax);
  Vec3 c[kMax];
  double r2[kMax];
  for (std::size_t k = 0; k < nv; ++k) {
    c[k] = Vec3(cell.poly[k].x, cell.poly[k].y, s.z());
    r2[k] = (c[k] - s).squaredNorm();
  }
  const bool all = cell.poly.size() > kMax;  // never in practice: fall back to the bounding disc
  const double disc = 4 * cell.r2max;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    bool reach = false;
    if (all)
      reach = mindist2(nd, s) <= disc;
    else
      for (std::size_t k = 0; k < nv && !reach; ++k) reach = mindist2(nd, c[k]) <= r2[k];
    if (!reach) continue;
    if (nd.child < 0) {
      for (int i = nd.first; i < nd.last; ++i) {
        bool hit = all && (pos_[i] - s).squaredNorm() <= disc;
        for (std::size_t k = 0; k < nv && !hit; ++k) hit = (pos_[i] - c[k]).squaredNorm() <= r2[k];
        if (hit) out.emplace_back((pos_[i] - s).squaredNorm(), id_[i]);
      }
      continue;
    }
    stack[top++] = nd.child;
    stack[top++] = nd.child + 1;
  }
}

bool PointBatch::any_in_lune(const Vec3& s, const Vec3& v) const {
  if (nodes_.empty()) return false;
  const Lune l(s, v);
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (mindist2(nd, l.m) > l.m2 || mindist2(nd, l.s) > l.r2 || mindist2(nd, l.v) > l.r2) continue;
    if (nd.child < 0) {
      for (int i = nd.first; i < nd.last; ++i)
        if (l.holds(pos_[i])) return true;
      continue;
    }
    const int near = l.m[nd.dim] <= nd.split ? 0 : 1;
    stack[top++] = nd.child + 1 - near;
    stack[top++] = nd.child + near;
  }
  return false;
}

// Each comparison in PointTree::sector() is monotone in the rounded differences p - s (rounding keeps
// order, and -t * dx is exactly -(t * dx)), so over a box its values are bounded by its values at two
// corners. The mask mixes the comparisons independently: it may hold a sector no point of the box gets,
// never miss one, and needs no widening for rounding.
unsigned PointBatch::sector_mask(const Vec3& lo, const Vec3& hi, const Vec3& s) {
  constexpr double t = 1.7320508075688772;  // as in sector()
  const double x0 = lo.x() - s.x(), x1 = hi.x() - s.x(), y0 = lo.y() - s.y(), y1 = hi.y() - s.y();
  const bool upper_can = y1 > 0 || (y1 == 0 && x1 >= 0), lower_can = !(y0 > 0 || (y0 == 0 && x0 >= 0));
  unsigned m = 0;
  if (upper_can) {
    if (y0 < t * x1) m |= 1u;  // dy < t dx somewhere
    if (!(y1 < t * x0)) {      // and not everywhere
      if (y1 > -t * x1) m |= 2u;
      if (!(y0 > -t * x0)) m |= 4u;
    }
  }
  if (lower_can) {
    if (y1 > t * x0) m |= 8u;
    if (!(y0 > t * x1)) {
      if (y0 < -t * x0) m |= 16u;
      if (!(y1 < -t * x1)) m |= 32u;
    }
  }
  return m;
}

void PointBatch::sector_merge(const Vec3& s, Index* best, double* best_d2, unsigned* ties) const {
  if (ties) *ties = 0;
  if (nodes_.empty()) return;
  auto worst = [&] { return std::max({best_d2[0], best_d2[1], best_d2[2], best_d2[3], best_d2[4], best_d2[5]}); };
  auto least = [&] { return std::min({best_d2[0], best_d2[1], best_d2[2], best_d2[3], best_d2[4], best_d2[5]}); };
  double far = worst();    // no point beyond this can be a best
  double close = least();  // a box no farther than this is needed whatever sectors it reaches
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    // mindist2 and a point's squared distance may round differently: compare with a little slack
    const double d2 = mindist2(nd, s) * (1 - 1e-12);
    if (d2 > far) continue;
    double reach = far;  // a point of this box farther than this beats no best of the sectors it can be in
    if (d2 > close) {
      const unsigned m = sector_mask(nd.lo, nd.hi, s);
      reach = -1;
      for (int k = 0; k < 6; ++k)
        if (m >> k & 1u) reach = std::max(reach, best_d2[k]);
      if (!(reach >= d2)) continue;
    }
    if (nd.child < 0) {
      bool changed = false;
      for (int i = nd.first; i < nd.last; ++i) {
        const Vec3 d = pos_[i] - s;
        const double pd2 = d.squaredNorm();
        if (pd2 > reach) continue;
        const int k = PointTree::sector(d.x(), d.y());
        if (ties && pd2 <= best_d2[k]) {  // a nearer point clears the sector's tie
          if (pd2 == best_d2[k] && id_[i] != best[k])
            *ties |= 1u << k;
          else
            *ties &= ~(1u << k);
        }
        if (pd2 <= best_d2[k] && (pd2 < best_d2[k] || id_[i] < best[k])) {
          best_d2[k] = pd2;
          best[k] = id_[i];
          changed = true;
        }
      }
      if (changed) {
        far = worst();
        close = least();
      }
      continue;
    }
    const int near = s[nd.dim] <= nd.split ? 0 : 1;
    stack[top++] = nd.child + 1 - near;
    stack[top++] = nd.child + near;
  }
}

}  // namespace cellform::venation
