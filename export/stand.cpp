// Standing on the bed: the footprint's convex hull (Andrew's monotone chain), the centre of mass by signed
// tetrahedra, and the same for the part above a cut, clipped triangle by triangle.
#include "export/stand.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/parallel.h"
#include "core/union_find.h"
#include "export/mesh_check.h"

namespace cellform::exporters {

namespace {

using core::Vec3;
using P2 = Eigen::Vector2d;

double cross(const P2& o, const P2& a, const P2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// The convex hull, counter-clockwise, without points in line; fewer than 3 points for a point or a segment.
std::vector<P2> convex_hull(std::vector<P2> p) {
  std::sort(p.begin(), p.end(),
            [](const P2& a, const P2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<P2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {  // lower hull
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);  // the last point is the first
  return h;
}

double hull_area(const std::vector<P2>& h) {
  double a = 0;
  for (std::size_t i = 0, j = h.size() - 1; i < h.size(); j = i++) a += h[j].x() * h[i].y() - h[i].x() * h[j].y();
  return h.size() < 3 ? 0.0 : a / 2;
}

P2 closest_on_segment(const P2& p, const P2& a, const P2& b) {
  const P2 ab = b - a;
  const double len2 = ab.squaredNorm();
  return a + (len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0) * ab;
}

/// Signed distance from p to the edge of the hull: positive inside, negative outside (a hull of one or two
/// points has no inside).
double signed_margin(const std::vector<P2>& h, const P2& p) {
  if (h.empty()) return -std::numeric_limits<double>::infinity();
  if (h.size() == 1) return -(p - h[0]).norm();
  double d = std::numeric_limits<double>::infinity();
  bool inside = h.size() >= 3;
  for (std::size_t i = 0, j = h.size() - 1; i < h.size(); j = i++) {
    d = std::min(d, (p - closest_on_segment(p, h[j], h[i])).norm());
    if (cross(h[j], h[i], p) < 0) inside = false;
  }
  return inside ? d : -d;
}

/// The direction in plan in which a solid with its centre of mass's plan at p tips most easily off the hull:
/// from the nearest point of the hull's edge, outward (towards p from outside, away from it from inside).
/// Returns the nearest point; `out` gets the direction.
P2 tipping_edge(const std::vector<P2>& h, const P2& p, P2& out) {
  P2 nearest = h.front(), normal = P2(1, 0);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = h.size() - 1; i < h.size(); j = i++) {
    const P2 ab = h[i] - h[j], q = closest_on_segment(p, h[j], h[i]);
    if ((p - q).norm() < best) {
      best = (p - q).norm();
      nearest = q;
      // outward: the hull runs counter-clockwise
      normal = ab.squaredNorm() > 0 ? P2(ab.y(), -ab.x()).normalized() : P2(1, 0);
    }
  }
  const bool inside = signed_margin(h, p) > 0;
  out = best > 0 ? P2((inside ? nearest - p : p - nearest) / best) : normal;
  return nearest;
}

/// Degrees the solid turns, from where it lies (or, when it stands, from where a tilt of `tilt` degrees over its
/// footprint's edge nearest the centre of mass `g` leaves it), rolling over the edge its centre of mass lies beyond
/// until that is over what touches the bed (the points within `layer` of it): quasi-static, each turn about that edge
/// until the next point meets the bed, at most 100 turns.
double roll_to_rest(const PrintableMesh& m, const Vec3& g, double layer, double tilt) {
  std::vector<char> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (const std::uint32_t i : t) used[i] = 1;
  std::vector<Vec3> p;
  p.reserve(m.vertices.size() + 1);
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    if (used[i]) p.push_back(m.vertices[i]);
  p.push_back(g);  // turned with the rest
  Eigen::Matrix3d turned = Eigen::Matrix3d::Identity();
  Vec3 from = Vec3::UnitZ();  // up when the roll begins: after the tilt that tips it, when it stands
  double extent = 0;
  for (const Vec3& q : p) extent = std::max(extent, (q - p.front()).norm());
  for (int turn = 0; turn < 100; ++turn) {
    double bed = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < p.size(); ++i) bed = std::min(bed, p[i].z());
    std::vector<P2> touching;
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      if (p[i].z() <= bed + layer) touching.emplace_back(p[i].x(), p[i].y());
    const std::vector<P2> hull = convex_hull(touching);
    const P2 centre(p.back().x(), p.back().y());
    if (turn > 0 || tilt <= 0) {
      if (signed_margin(hull, centre) > 0) break;
    }
    P2 out;
    const P2 edge = tipping_edge(hull, centre, out);
    double angle = M_PI / 2;  // nothing beyond the edge: onto its side
    if (turn == 0 && tilt > 0)
      angle = tilt * M_PI / 180 + 1e-6;  // just past the tip
    else
      for (std::size_t i = 0; i + 1 < p.size(); ++i) {
        const double d = (P2(p[i].x(), p[i].y()) - edge).dot(out);
        if (d > 1e-12 * extent) angle = std::min(angle, std::atan2(p[i].z() - bed, d));
      }
    // turning about the horizontal axis z x out takes `out` down
    const Eigen::AngleAxisd r(angle, Vec3(-out.y(), out.x(), 0));
    const Vec3 pivot(edge.x(), edge.y(), bed);
    for (Vec3& q : p) q = pivot + r * (q - pivot);
    turned = r.toRotationMatrix() * turned;
    if (turn == 0 && tilt > 0) from = turned * Vec3::UnitZ();
  }
  return std::acos(std::clamp((turned * Vec3::UnitZ()).dot(from), -1.0, 1.0)) * 180 / M_PI;
}

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// The volume and first moment of a closed surface's solid where z >= cut (every triangle clipped to that
/// half-space; the cap on the cut plane adds nothing, as each tetrahedron's apex lies in that plane), and the
/// plan points of the section (z = cut) or, with `below` set, of the surface where z <= cut.
struct Clipped {
  double volume = 0;
  Vec3 moment = Vec3::Zero();
  std::vector<P2> points;
};

/// With `roots` (per welded vertex, kNone below the cut; `canon` welds) and `volumes`, each triangle's part of
/// the volume is also added to its surface's root (the corners above a cut of one triangle share a root).
Clipped clip(const PrintableMesh& m, double cut, const P2& apex_plan, bool below,
             const std::vector<std::uint32_t>* canon = nullptr, const std::vector<std::uint32_t>* roots = nullptr,
             std::vector<double>* volumes = nullptr) {
  Clipped c;
  const Vec3 apex(apex_plan.x(), apex_plan.y(), cut);
  std::array<Vec3, 4> poly;
  for (const auto& t : m.triangles) {
    const std::array<Vec3, 3> v = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    std::size_t n = 0;
    for (int i = 0; i < 3; ++i) {  // Sutherland-Hodgman against z >= cut (z <= cut if below)
      const Vec3 &a = v[i], &b = v[(i + 1) % 3];
      const double da = below ? cut - a.z() : a.z() - cut, db = below ? cut - b.z() : b.z() - cut;
      if (da >= 0) poly[n++] = a;
      if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
        Vec3 x = a + (b - a) * (da / (da - db));
        x.z() = cut;
        poly[n++] = x;
      }
    }
    if (below) {
      for (std::size_t i = 0; i < n; ++i) c.points.emplace_back(poly[i].x(), poly[i].y());
      continue;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (poly[i].z() == cut) c.points.emplace_back(poly[i].x(), poly[i].y());
    double part = 0;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Vec3 a = poly[0] - apex, b = poly[i] - apex, d = poly[i + 1] - apex;
      const double six = a.dot(b.cross(d));
      part += six / 6;
      c.moment += six / 6 * (apex + (a + b + d) / 4);
    }
    c.volume += part;
    if (volumes && n >= 3)
      for (const std::uint32_t k : t)
        if (const std::uint32_t r = (*roots)[(*canon)[k]]; r != kNone) {
          (*volumes)[r] += part;
          break;
        }
  }
  return c;
}

/// The connected surfaces of the part of a mesh above `cut` (all of it for cut = -infinity), through its
/// triangles' corners above the cut (a triangle's part above the cut joins them): each welded vertex's root
/// (`canon` welds equal positions), kNone for one at or below the cut or used by no triangle.
std::vector<std::uint32_t> roots_above(const PrintableMesh& m, const std::vector<std::uint32_t>& canon, double cut) {
  core::UnionFind sets(m.vertices.size());
  std::vector<char> above(m.vertices.size(), 0);
  for (const auto& t : m.triangles) {
    std::uint32_t first = kNone;
    for (const std::uint32_t v : t)
      if (const std::uint32_t i = canon[v]; m.vertices[i].z() > cut) {
        above[i] = 1;
        if (first == kNone)
          first = i;
        else
          sets.unite(first, i);
      }
  }
  std::vector<std::uint32_t> root(m.vertices.size(), kNone);
  for (std::uint32_t i = 0; i < root.size(); ++i)
    if (above[i]) root[i] = sets.find(i);
  return root;
}

/// The tip angle (degrees) of what lies above `cut`, standing on its section there; NaN when it has no volume,
/// or falls apart: when more of its surfaces above the cut enclose a positive volume there (pieces; the inner
/// face of a shell open downwards encloses a negative one, as a pocket does) than there are pieces of the whole
/// (`whole` roots, `whole_volume` by root) that reach above the cut (a branch joined to the rest only below it).
double tip_above(const PrintableMesh& m, const std::vector<std::uint32_t>& canon,
                 const std::vector<std::uint32_t>& whole, const std::vector<double>& whole_volume, double cut,
                 const P2& centre) {
  const std::vector<std::uint32_t> above = roots_above(m, canon, cut);
  std::vector<double> volume(m.vertices.size(), 0.0);
  const Clipped c = clip(m, cut, centre, false, &canon, &above, &volume);
  if (!(c.volume > 0)) return std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint32_t> reaching;
  std::size_t pieces = 0;
  for (std::uint32_t i = 0; i < above.size(); ++i)
    if (above[i] != kNone) {
      pieces += above[i] == i && volume[i] > 0;
      if (whole_volume[whole[i]] > 0) reaching.push_back(whole[i]);
    }
  std::sort(reaching.begin(), reaching.end());
  if (pieces > static_cast<std::size_t>(std::unique(reaching.begin(), reaching.end()) - reaching.begin()))
    return std::numeric_limits<double>::quiet_NaN();
  const Vec3 g = c.moment / c.volume;
  const double margin = signed_margin(convex_hull(c.points), P2(g.x(), g.y()));
  return std::atan2(margin, g.z() - cut) * 180 / M_PI;
}

struct Box {
  Vec3 lo, hi;
};

Box bounds(const PrintableMesh& m) {
  Box b{Vec3::Constant(std::numeric_limits<double>::infinity()),
        Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (const auto& t : m.triangles)
    for (const std::uint32_t i : t) b.lo = b.lo.cwiseMin(m.vertices[i]), b.hi = b.hi.cwiseMax(m.vertices[i]);
  return b;
}

}  // namespace

Stand stand_on_bed(const PrintableMesh& m, double first_layer) {
  Stand s;
  if (m.triangles.empty()) return s;
  const Box box = bounds(m);
  s.bed_z = box.lo.z();
  const P2 centre((box.lo.x() + box.hi.x()) / 2, (box.lo.y() + box.hi.y()) / 2);
  const Clipped whole = clip(m, s.bed_z, centre, false);
  if (!(whole.volume > 0)) return s;
  s.measured = true;
  s.centre_of_mass = whole.moment / whole.volume;
  const std::vector<P2> footprint = convex_hull(clip(m, s.bed_z + first_layer, centre, true).points);
  s.footprint_area = hull_area(footprint);
  s.margin = signed_margin(footprint, P2(s.centre_of_mass.x(), s.centre_of_mass.y()));
  s.tip_angle = std::atan2(s.margin, s.centre_of_mass.z() - s.bed_z) * 180 / M_PI;
  s.settle_angle = roll_to_rest(m, s.centre_of_mass, first_layer, s.margin > 0 ? s.tip_angle : 0.0);
  return s;
}

double base_cut_to_stand(const PrintableMesh& m, double min_tip_angle, double max_fraction, int heights, int threads) {
  if (m.triangles.empty() || heights < 1) return 0;
  const Box box = bounds(m);
  const P2 centre((box.lo.x() + box.hi.x()) / 2, (box.lo.y() + box.hi.y()) / 2);
  const double height = box.hi.z() - box.lo.z();
  const std::vector<std::uint32_t> canon = weld_positions(m.vertices);
  const std::vector<std::uint32_t> whole = roots_above(m, canon, -std::numeric_limits<double>::infinity());
  std::vector<double> whole_volume(m.vertices.size(), 0.0);  // by root: pieces > 0, pockets < 0
  clip(m, box.lo.z() - 1, centre, false, &canon, &whole, &whole_volume);
  std::vector<double> tip(static_cast<std::size_t>(heights), std::numeric_limits<double>::quiet_NaN());
  core::parallel_for(
      tip.size(), threads,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k)
          tip[k] = tip_above(m, canon, whole, whole_volume,
                             box.lo.z() + height * max_fraction * static_cast<double>(k + 1) / heights, centre);
      },
      1);
  for (std::size_t k = 0; k < tip.size(); ++k)
    if (tip[k] >= min_tip_angle) return height * max_fraction * static_cast<double>(k + 1) / heights;
  return 0;
}

}  // namespace cellform::exporters
