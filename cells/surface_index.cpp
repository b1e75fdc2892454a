// The triangles of a growing one-layer cell sheet, indexed to test a new one against them: stacked on one
// round a common corner, or crossing one. Private to cells/ (see surface_detail.h).
#include <algorithm>
#include <cmath>

#include "cells/surface_detail.h"
#include "core/triangle_intersection.h"

namespace cellform::cells::detail {

namespace {

/// Whether the angles AvB and CvD of two triangles with the common corner v (A to D: their other corners
/// from v; n = A x B, not zero) are disjoint seen along n, found with signs of cross products: no end (nor
/// the bisector, for two equal angles) of either strictly inside the other. Then neither triangle reaches
/// over the other: each lies in the cone of its angle, and seen along n the cones meet only at v. (Exactly
/// so; core::segment_meets_triangle counts points within its rounding tolerance, about 1e-6 of the
/// coordinates (here taken about a corner of the new triangle), of a plane as on it, so for a pair that all but touches
/// the two may disagree.)
bool apart(const Vec3& A, const Vec3& B, const Vec3& C, const Vec3& D, const Vec3& n) {
  auto turn = [&](const Vec3& x, const Vec3& y) { return x.cross(y).dot(n); };  // > 0: x to y anticlockwise
  const double sigma = turn(C, D) > 0 ? 1.0 : -1.0;
  auto in_ab = [&](const Vec3& x) { return turn(A, x) > 0 && turn(x, B) > 0; };
  auto in_cd = [&](const Vec3& x) { return sigma * turn(C, x) > 0 && sigma * turn(x, D) > 0; };
  const Vec3 mid = C.normalized() + D.normalized();
  return !in_ab(C) && !in_ab(D) && !in_ab(mid) && !in_cd(A) && !in_cd(B);
}

}  // namespace

bool stacked_at(const std::vector<Vec3>& pos, const std::array<Index, 3>& t1, const std::array<Index, 3>& t2, Index v) {
  constexpr double kCosCoplanar = 0.819;  // cos 35 degrees
  constexpr double kMinShare = 0.2;
  auto others = [&](const std::array<Index, 3>& t) {
    return t[0] == v   ? std::array<Index, 2>{t[1], t[2]}
           : t[1] == v ? std::array<Index, 2>{t[0], t[2]}
                       : std::array<Index, 2>{t[0], t[1]};
  };
  const auto [a1, b1] = others(t1);
  const auto [a2, b2] = others(t2);
  const Vec3 n1 = (pos[a1] - pos[v]).cross(pos[b1] - pos[v]), n2 = (pos[a2] - pos[v]).cross(pos[b2] - pos[v]);
  const double l1 = n1.norm(), l2 = n2.norm();
  if (!(l1 > 0 && l2 > 0) || std::abs(n1.dot(n2)) < kCosCoplanar * l1 * l2) return false;
  // disjoint angles, the common case round a corner of a sheet
  if (apart(pos[a1] - pos[v], pos[b1] - pos[v], pos[a2] - pos[v], pos[b2] - pos[v], n1)) return false;
  const Vec3 e1 = (pos[a1] - pos[v]).normalized(), e2 = (n1 / l1).cross(e1);
  auto angle = [&](Index w) {
    const Vec3 d = pos[w] - pos[v];
    return std::atan2(d.dot(e2), d.dot(e1));
  };
  constexpr double kTwoPi = 6.283185307179586;
  // arcs [start, start + width], the shorter way round between the two other corners
  auto arc = [&](double x, double y) {
    double d = std::fmod(y - x + 2 * kTwoPi, kTwoPi);
    return d <= kTwoPi / 2 ? std::array<double, 2>{x, d} : std::array<double, 2>{y, kTwoPi - d};
  };
  const auto [s1, w1] = arc(0.0, angle(b1));
  const auto [s2, w2] = arc(angle(a2), angle(b2));
  const double off = std::fmod(s2 - s1 + 2 * kTwoPi, kTwoPi);  // s2 from s1, round the way arc 1 runs
  const double shared = std::max(0.0, std::min(w1, off + w2) - off) + std::max(0.0, std::min(w1, off + w2 - kTwoPi));
  return shared > kMinShare * std::min(w1, w2);
}

CornerIndex::CornerIndex(std::size_t cells, const std::vector<std::array<Index, 3>>& room,
                         const std::vector<std::array<Index, 3>>& tris)
    : start_(cells + 1, 0), head_(cells, kNone) {
  for (const auto* list : {&room, &tris})
    for (const auto& t : *list)
      for (const Index v : t) ++start_[v + 1];
  for (std::size_t v = 0; v < cells; ++v) start_[v + 1] += start_[v];
  fill_.assign(start_.begin(), start_.end() - 1);
  slot_.resize(start_.back());
  for (const auto& t : tris) add(t);
}

void CornerIndex::add(const std::array<Index, 3>& t) {
  for (const Index v : t) {
    if (fill_[v] < start_[v + 1]) {
      slot_[fill_[v]++] = t;
    } else {
      spill_.push_back({head_[v], t});
      head_[v] = static_cast<std::uint32_t>(spill_.size() - 1);
    }
  }
}

bool CornerIndex::stacks(const std::vector<Vec3>& pos, const std::array<Index, 3>& t) const {
  auto stacked_with = [&](const std::array<Index, 3>& u, Index v) {
    int common = 0;
    for (const Index a : t) common += a == u[0] || a == u[1] || a == u[2];
    return common == 1 && stacked_at(pos, t, u, v);
  };
  for (const Index v : t) {
    for (std::size_t x = start_[v]; x < fill_[v]; ++x)
      if (stacked_with(slot_[x], v)) return true;
    for (std::uint32_t x = head_[v]; x != kNone; x = spill_[x].first)
      if (stacked_with(spill_[x].second, v)) return true;
  }
  return false;
}

bool CornerIndex::crosses_at_corner(const std::vector<Vec3>& pos, const std::array<Index, 3>& t) const {
  // about a corner of t: the intersection tests' rounding tolerance grows with the coordinates (for meshes read
  // through float files), and a sheet far from the origin lost triangles to it (10 of 5,377 at 65,536 units)
  const Vec3 o = pos[t[0]];
  const std::array<Vec3, 3> T{Vec3::Zero(), pos[t[1]] - o, pos[t[2]] - o};
  for (int k = 0; k < 3; ++k) {
    const Index v = t[k];
    bool found = false;
    for_each_at(v, [&](const std::array<Index, 3>& u) {
      if (found) return;
      int common = 0, at = 0;
      for (int b = 0; b < 3; ++b)
        if (u[b] == t[0] || u[b] == t[1] || u[b] == t[2]) ++common;
      for (int b = 0; b < 3; ++b)
        if (u[b] == v) at = b;
      if (common != 1) return;
      const std::array<Vec3, 3> U{pos[u[0]] - o, pos[u[1]] - o, pos[u[2]] - o};
      const Vec3 A = T[(k + 1) % 3] - T[k], B = T[(k + 2) % 3] - T[k], n = A.cross(B);
      if (n.squaredNorm() > 0 && apart(A, B, U[(at + 1) % 3] - T[k], U[(at + 2) % 3] - T[k], n)) return;
      found = core::segment_meets_triangle(T[(k + 1) % 3], T[(k + 2) % 3], U) ||
              core::segment_meets_triangle(U[(at + 1) % 3], U[(at + 2) % 3], T);
    });
    if (found) return true;
  }
  return false;
}

SheetIndex::SheetIndex(const std::vector<Vec3>& pos, const std::vector<std::array<Index, 3>>& tris, double typical_side)
    : pos_(pos), corners_(pos.size(), {}, tris) {
  double total = 0;
  std::size_t counted = 0;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const double side = (pos[t[k]] - pos[t[(k + 1) % 3]]).norm();
      if (std::isfinite(side)) total += side, ++counted;
    }
  const double typical = typical_side > 0 && std::isfinite(typical_side) ? typical_side
                         : counted > 0                                   ? total / static_cast<double>(counted)
                                                                         : 0.0;
  reach_ = kLongSides * (typical > 0 && std::isfinite(typical) ? typical : 1.0);
  for (const auto& t : tris) note_long(t);
}

void SheetIndex::note_long(const std::array<Index, 3>& t) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    const double side = (pos_[t[k]] - pos_[t[(k + 1) % 3]]).norm();
    if (!(side <= reach_)) {
      long_.push_back(t);
      return;
    }
    longest = std::max(longest, side);
  }
  longest_short_ = std::max(longest_short_, longest);
}

void SheetIndex::add(const std::array<Index, 3>& t) {
  corners_.add(t);
  note_long(t);
}

bool SheetIndex::crosses(const std::array<Index, 3>& f, const std::vector<std::array<Index, 3>>& others) {
  const Vec3 o = pos_[f[0]];  // a local origin, as in crosses_at_corner
  const std::array<Vec3, 3> F{Vec3::Zero(), pos_[f[1]] - o, pos_[f[2]] - o};
  auto meets = [&](const std::array<Index, 3>& u) {
    const std::array<Vec3, 3> U{pos_[u[0]] - o, pos_[u[1]] - o, pos_[u[2]] - o};
    int common = 0, at_f = 0, at_u = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (f[a] == u[b]) ++common, at_f = a, at_u = b;
    if (common == 0) return core::triangles_intersect(F, U);
    if (common > 1) return false;  // a side: the fold test's case
    // one corner: they cross beyond it iff the side of one opposite it meets the other
    return core::segment_meets_triangle(F[(at_f + 1) % 3], F[(at_f + 2) % 3], U) ||
           core::segment_meets_triangle(U[(at_u + 1) % 3], U[(at_u + 2) % 3], F);
  };
  if (std::any_of(others.begin(), others.end(), meets) || std::any_of(long_.begin(), long_.end(), meets)) return true;
  if (!grid_built_) {
    grid_.build(pos_, reach_ / kLongSides);
    grid_built_ = true;
  }
  const Vec3 centre = (F[0] + F[1] + F[2]) / 3;
  double radius = 0;
  for (const Vec3& c : F) radius = std::max(radius, (c - centre).norm());
  near_.clear();
  grid_.within(centre + o, radius + longest_short_, kNoIndex, near_);
  bool found = false;
  for (const Index v : near_)
    corners_.for_each_at(v, [&](const std::array<Index, 3>& u) { found = found || meets(u); });
  return found;
}

}  // namespace cellform::cells::detail
