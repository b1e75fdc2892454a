// Obstacle constraints: projection out of solids, no crossing of meshes (BVH over triangles).
#include "forms/obstacles.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "core/errors.h"
#include "core/parallel.h"

namespace cellform::forms {

namespace {

using core::InvalidInput;

bool finite(const Vec3& v) { return v.allFinite(); }

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// Cell-obstacle corrections repeat at most this often before a cell falls back to its previous position.
constexpr int kMaxPasses = 8;

// Removes the part of v that points against the outward unit normal n.
void remove_inward(Vec3& v, const Vec3& n) {
  const double vn = v.dot(n);
  if (vn < 0) v -= vn * n;
}

}  // namespace

void validate(const Obstacles& obstacles) {
  for (std::size_t i = 0; i < obstacles.half_spaces.size(); ++i) {
    const HalfSpace& h = obstacles.half_spaces[i];
    const std::string name = "ground " + std::to_string(i);
    if (!finite(h.point)) throw InvalidInput(name + ": point has a non-finite coordinate");
    if (!finite(h.normal) || h.normal.norm() <= 0 || !std::isfinite(h.normal.norm()))
      throw InvalidInput(name + ": normal must be a finite, non-zero vector pointing away from the solid");
  }
  for (std::size_t i = 0; i < obstacles.spheres.size(); ++i) {
    const Sphere& s = obstacles.spheres[i];
    const std::string name = "sphere " + std::to_string(i);
    if (!finite(s.centre)) throw InvalidInput(name + ": centre has a non-finite coordinate");
    if (!(s.radius > 0) || !std::isfinite(s.radius))
      throw InvalidInput(name + ": radius is " + fmt(s.radius) + ", allowed: a finite value > 0 (model units)");
  }
  for (std::size_t i = 0; i < obstacles.boxes.size(); ++i) {
    const Box& b = obstacles.boxes[i];
    const std::string name = "box " + std::to_string(i);
    if (!finite(b.min) || !finite(b.max)) throw InvalidInput(name + ": min or max has a non-finite coordinate");
    for (int k = 0; k < 3; ++k) {
      if (b.min[k] > b.max[k]) {
        const char axis = static_cast<char>('x' + k);
        throw InvalidInput(name + ": min." + axis + " = " + fmt(b.min[k]) + " is greater than max." + axis + " = " +
                           fmt(b.max[k]) + "; allowed: min <= max in every coordinate");
      }
    }
  }
  for (std::size_t i = 0; i < obstacles.meshes.size(); ++i) {
    const TriangleMesh& m = obstacles.meshes[i];
    const std::string name = "mesh " + std::to_string(i);
    for (std::size_t v = 0; v < m.vertices.size(); ++v)
      if (!finite(m.vertices[v])) throw InvalidInput(name + ": vertex " + std::to_string(v) + " is not finite");
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (Index v : m.triangles[t])
        if (v >= m.vertices.size())
          throw InvalidInput(name + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                             " but the mesh has " + std::to_string(m.vertices.size()) + " vertices");
  }
}

// ---------------------------------------------------------------------------------------------------
// Bounding-volume hierarchy over all mesh triangles; answers "first triangle crossed by a segment".

struct PreparedObstacles::MeshIndex {
  struct Triangle {
    Vec3 v0, e1, e2;
    Vec3 normal;  // unit
    double d00, d01, d11, inv_denom;
    std::uint32_t mesh = 0;  // index in Obstacles::meshes
  };
  struct Node {
    Vec3 lo, hi;
    std::uint32_t start = 0, count = 0;  // leaf: triangles [start, start + count)
    std::uint32_t right = 0;             // inner node: left child is this + 1
  };
  struct Hit {           // where a segment crosses a triangle:
    double t;            // along the segment, in [0, 1]
    Vec3 point, normal;  // on the triangle plane; unit normal of the triangle
    std::uint32_t mesh;  // index in Obstacles::meshes
  };

  std::vector<Triangle> triangles;  // in leaf order
  std::vector<Node> nodes;
  double pad = 0;    // bounding boxes grow by this much, model units
  double scale = 1;  // bounding-box diagonal of all meshes, model units

  explicit MeshIndex(const std::vector<TriangleMesh>& meshes) {
    std::vector<Triangle> all;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      const TriangleMesh& m = meshes[k];
      for (const auto& t : m.triangles) {
        const Vec3& a = m.vertices[t[0]];
        const Vec3& b = m.vertices[t[1]];
        const Vec3& c = m.vertices[t[2]];
        Triangle tri;
        tri.v0 = a;
        tri.e1 = b - a;
        tri.e2 = c - a;
        const Vec3 n = tri.e1.cross(tri.e2);
        const double len = n.norm();
        if (!(len > 0) || !std::isfinite(len)) continue;  // degenerate: no area to cross
        tri.normal = n / len;
        tri.d00 = tri.e1.dot(tri.e1);
        tri.d01 = tri.e1.dot(tri.e2);
        tri.d11 = tri.e2.dot(tri.e2);
        const double denom = tri.d00 * tri.d11 - tri.d01 * tri.d01;
        if (!(denom > 0)) continue;
        tri.inv_denom = 1.0 / denom;
        tri.mesh = static_cast<std::uint32_t>(k);
        all.push_back(tri);
        lo = lo.cwiseMin(a).cwiseMin(b).cwiseMin(c);
        hi = hi.cwiseMax(a).cwiseMax(b).cwiseMax(c);
      }
    }
    if (all.empty()) return;
    scale = std::max(1e-300, (hi - lo).norm());
    pad = 1e-9 * scale;

    std::vector<std::uint32_t> order(all.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<Vec3> centroid(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) centroid[i] = all[i].v0 + (all[i].e1 + all[i].e2) / 3.0;
    nodes.reserve(2 * all.size() / 3 + 2);
    build(all, centroid, order, 0, static_cast<std::uint32_t>(all.size()));
    triangles.reserve(all.size());
    for (std::uint32_t i : order) triangles.push_back(all[i]);
  }

  std::uint32_t build(const std::vector<Triangle>& all, const std::vector<Vec3>& centroid,
                      std::vector<std::uint32_t>& order, std::uint32_t begin, std::uint32_t end) {
    const auto self = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Vec3 clo = lo, chi = hi;
    for (std::uint32_t i = begin; i < end; ++i) {
      const Triangle& t = all[order[i]];
      const Vec3 b = t.v0 + t.e1, c = t.v0 + t.e2;
      lo = lo.cwiseMin(t.v0).cwiseMin(b).cwiseMin(c);
      hi = hi.cwiseMax(t.v0).cwiseMax(b).cwiseMax(c);
      clo = clo.cwiseMin(centroid[order[i]]);
      chi = chi.cwiseMax(centroid[order[i]]);
    }
    nodes[self].lo = lo - Vec3::Constant(pad);
    nodes[self].hi = hi + Vec3::Constant(pad);
    Index axis = 0;
    const Vec3 extent = chi - clo;
    extent.maxCoeff(&axis);
    if (end - begin <= 4 || !(extent[axis] > 0)) {
      nodes[self].start = begin;
      nodes[self].count = end - begin;
      return self;
    }
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double ca = centroid[a][axis], cb = centroid[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    build(all, centroid, order, begin, mid);
    const std::uint32_t right = build(all, centroid, order, mid, end);
    nodes[self].right = right;
    return self;
  }

  // Does the segment o + t d, t in [0, t_max], meet the box? inv = 1 / d componentwise (inf where d = 0).
  static bool segment_box(const Vec3& o, const Vec3& d, const Vec3& inv, const Vec3& lo, const Vec3& hi, double t_max) {
    double t0 = 0, t1 = t_max;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0) {
        if (o[k] < lo[k] || o[k] > hi[k]) return false;
        continue;
      }
      double a = (lo[k] - o[k]) * inv[k], b = (hi[k] - o[k]) * inv[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return false;
    }
    return true;
  }

  // A crossing: from strictly on one side of the plane to the other side or onto the plane, through the
  // triangle (edges included, with a tiny tolerance so nothing slips between neighbouring triangles).
  static bool cross(const Triangle& tri, const Vec3& from, const Vec3& to, double& t, Vec3& point) {
    const double d0 = (from - tri.v0).dot(tri.normal);
    const double d1 = (to - tri.v0).dot(tri.normal);
    if (!((d0 > 0 && d1 <= 0) || (d0 < 0 && d1 >= 0))) return false;
    t = d0 / (d0 - d1);
    point = from + t * (to - from);
    return within(tri, point);
  }

  // Whether `point`, on the triangle's plane, lies in the triangle (edges included, tolerance as cross()).
  static bool within(const Triangle& tri, const Vec3& point) {
    const Vec3 w = point - tri.v0;
    const double w1 = w.dot(tri.e1), w2 = w.dot(tri.e2);
    const double v = (tri.d11 * w1 - tri.d01 * w2) * tri.inv_denom;
    const double u = (tri.d00 * w2 - tri.d01 * w1) * tri.inv_denom;
    constexpr double tol = 1e-9;
    return v >= -tol && u >= -tol && u + v <= 1 + tol;
  }

  // The mesh of a triangle that `point` lies on, within `pad` of its plane; the lowest mesh index of those.
  std::optional<std::size_t> mesh_touched(const Vec3& point) const {
    std::optional<std::size_t> found;
    std::vector<std::uint32_t> stack = {0};
    while (!nodes.empty() && !stack.empty()) {
      const Node& node = nodes[stack.back()];
      stack.pop_back();
      if ((point.array() < node.lo.array()).any() || (point.array() > node.hi.array()).any()) continue;
      if (node.count == 0) {
        stack.push_back(node.right);
        stack.push_back(static_cast<std::uint32_t>(&node - nodes.data()) + 1);
        continue;
      }
      for (std::uint32_t i = node.start; i < node.start + node.count; ++i) {
        const Triangle& tri = triangles[i];
        const double d = (point - tri.v0).dot(tri.normal);
        if (std::abs(d) <= pad && within(tri, point - d * tri.normal) && (!found || tri.mesh < *found))
          found = tri.mesh;
      }
    }
    return found;
  }

  // visit(i, t, point) for each triangle i crossed (or touched) at t <= limit; visit may lower `limit` to prune.
  template <class Visit>
  void crossings(const Vec3& from, const Vec3& to, double& limit, Visit&& visit) const {
    if (nodes.empty()) return;
    const Vec3 d = to - from;
    const Vec3 inv = d.cwiseInverse();
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes[stack[--top]];
      if (!segment_box(from, d, inv, node.lo, node.hi, limit)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.start; i < node.start + node.count; ++i) {
          double t;
          Vec3 p;
          if (cross(triangles[i], from, to, t, p)) visit(i, t, p);
        }
      } else {
        const auto self = static_cast<std::uint32_t>(&node - nodes.data());
        // Depth is about log2(T / 4) + a few: 64 is enough for any mesh that fits in memory.
        stack[top++] = node.right;
        stack[top++] = self + 1;
      }
    }
  }

  std::optional<Hit> first_crossing(const Vec3& from, const Vec3& to) const {
    std::optional<Hit> best;
    double best_t = 1.0;
    crossings(from, to, best_t, [&](std::uint32_t i, double t, const Vec3& p) {
      if (!best || t < best->t) best = Hit{t, p, triangles[i].normal, triangles[i].mesh}, best_t = t;
    });
    return best;
  }
};

// ---------------------------------------------------------------------------------------------------

PreparedObstacles::PreparedObstacles(Obstacles obstacles) : obstacles_(std::move(obstacles)) {
  validate(obstacles_);
  for (HalfSpace& h : obstacles_.half_spaces) h.normal.normalize();
  bool any_triangles = false;
  for (const TriangleMesh& m : obstacles_.meshes) any_triangles = any_triangles || !m.triangles.empty();
  if (any_triangles) index_ = std::make_unique<MeshIndex>(obstacles_.meshes);
}

PreparedObstacles::~PreparedObstacles() = default;
PreparedObstacles::PreparedObstacles(PreparedObstacles&&) noexcept = default;
PreparedObstacles& PreparedObstacles::operator=(PreparedObstacles&&) noexcept = default;

namespace {

// Rounding allowance for "inside" tests, model units: relative to the size of the coordinates involved.
double tolerance(const Vec3& p, double margin) { return 1e-12 * (1.0 + p.lpNorm<Eigen::Infinity>() + margin); }

double sphere_tolerance(const Vec3& p, const Sphere& s, double margin) {
  return tolerance(p, margin) + 1e-12 * (s.centre.lpNorm<Eigen::Infinity>() + s.radius);
}

double box_tolerance(const Vec3& p, const Box& b, double margin) {
  return tolerance(p, margin) + 1e-12 * std::max(b.min.lpNorm<Eigen::Infinity>(), b.max.lpNorm<Eigen::Infinity>());
}

double plane_tolerance(const Vec3& p, const HalfSpace& h, double margin) {
  return tolerance(p, margin) + 1e-12 * h.point.lpNorm<Eigen::Infinity>();
}

bool inside(const Vec3& p, const HalfSpace& h, double margin) {
  return (p - h.point).dot(h.normal) < margin - plane_tolerance(p, h, margin);
}

bool inside(const Vec3& p, const Sphere& s, double margin) {
  const double r = s.radius + margin - sphere_tolerance(p, s, margin);
  return (p - s.centre).squaredNorm() < r * r;
}

bool inside(const Vec3& p, const Box& b, double margin) {
  const double tol = box_tolerance(p, b, margin);
  for (int k = 0; k < 3; ++k)
    if (!(p[k] > b.min[k] - margin + tol && p[k] < b.max[k] + margin - tol)) return false;
  return true;
}

// Each constrain_* returns true if it moved the cell.

bool constrain(const HalfSpace& h, double margin, Vec3& p, Vec3& v) {
  if (!inside(p, h, margin)) return false;
  const double d = (p - h.point).dot(h.normal);
  p += (margin - d) * h.normal;
  remove_inward(v, h.normal);
  return true;
}

bool constrain(const Sphere& s, double margin, const Vec3& prev, Vec3& p, Vec3& v) {
  const double radius = s.radius + margin;
  const double tol = sphere_tolerance(p, s, margin);
  bool moved = false;
  const Vec3 d = p - prev;
  const double a = d.squaredNorm();
  const Vec3 oc = prev - s.centre;
  if (a > 0 && oc.norm() >= radius - tol) {
    // Did the move enter the sphere (possibly passing right through it)?
    const double tc = std::clamp(-oc.dot(d) / a, 0.0, 1.0);
    if ((oc + tc * d).norm() < radius - tol) {
      const double b = oc.dot(d);
      const double c = oc.squaredNorm() - radius * radius;
      const double disc = std::max(0.0, b * b - a * c);
      const double t_enter = std::clamp((-b - std::sqrt(disc)) / a, 0.0, 1.0);
      const Vec3 entry = prev + t_enter * d;
      const Vec3 n = (entry - s.centre).normalized();
      // Slide: keep the motion along the tangent plane at the entry point, which lies outside the ball.
      const double into = (p - entry).dot(n);
      if (into < 0) p -= into * n;
      remove_inward(v, n);
      moved = true;
    }
  }
  if (inside(p, s, margin)) {
    Vec3 out = p - s.centre;
    if (!(out.norm() > 0)) out = prev - s.centre;
    if (!(out.norm() > 0)) out = Vec3::UnitZ();
    const Vec3 n = out.normalized();
    p = s.centre + radius * n;
    remove_inward(v, n);
    moved = true;
  }
  return moved;
}

bool constrain(const Box& box, double margin, const Vec3& prev, Vec3& p, Vec3& v) {
  const double tol = box_tolerance(p, box, margin);
  const Vec3 lo = box.min - Vec3::Constant(margin), hi = box.max + Vec3::Constant(margin);
  bool moved = false;
  const Vec3 d = p - prev;
  if (!inside(prev, box, margin) && d.squaredNorm() > 0) {
    // Slab test against the box shrunk by the tolerance: a move that only grazes a face does not enter.
    double t0 = -std::numeric_limits<double>::infinity(), t1 = 1;
    int axis = -1;
    bool hit = true;
    for (int k = 0; k < 3 && hit; ++k) {
      const double l = lo[k] + tol, h = hi[k] - tol;
      if (d[k] == 0) {
        hit = prev[k] > l && prev[k] < h;
        continue;
      }
      double a = (l - prev[k]) / d[k], b = (h - prev[k]) / d[k];
      if (a > b) std::swap(a, b);
      if (a > t0) {
        t0 = a;
        axis = k;
      }
      t1 = std::min(t1, b);
    }
    hit = hit && axis >= 0 && std::max(t0, 0.0) < t1;
    if (hit && axis >= 0) {
      // Entered through a face of `axis`: stop on that face, keep the motion along it.
      const bool low_side = d[axis] > 0;
      p[axis] = low_side ? lo[axis] : hi[axis];
      Vec3 n = Vec3::Zero();
      n[axis] = low_side ? -1.0 : 1.0;
      remove_inward(v, n);
      moved = true;
    }
  }
  if (inside(p, box, margin)) {
    // Out through the nearest face; ties go to the lower axis, then the min side.
    int axis = 0;
    bool low_side = true;
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      if (p[k] - lo[k] < best) {
        best = p[k] - lo[k];
        axis = k;
        low_side = true;
      }
      if (hi[k] - p[k] < best) {
        best = hi[k] - p[k];
        axis = k;
        low_side = false;
      }
    }
    p[axis] = low_side ? lo[axis] : hi[axis];
    Vec3 n = Vec3::Zero();
    n[axis] = low_side ? -1.0 : 1.0;
    remove_inward(v, n);
    moved = true;
  }
  return moved;
}

}  // namespace

void check_outside(const Obstacles& obstacles, const std::vector<Vec3>& positions, const ObstacleNames& names,
                   int threads, const PreparedObstacles* prepared) {
  if (!prepared) validate(obstacles);  // (prepared: validated when it was made)
  // "NAME: N of the M cells lie WHERE (the first at P); WHY", for the cells `holds` says lie there
  auto refuse = [&](const std::vector<std::string>& given, const char* kind, std::size_t index, const char* where,
                    const char* why, const auto& holds) {
    std::size_t count = 0, first = 0;
    for (std::size_t i = positions.size(); i-- > 0;) {
      if (holds(i)) {
        ++count;
        first = i;
      }
    }
    if (count == 0) return;
    const std::string name = index < given.size() ? given[index] : std::string(kind) + " " + std::to_string(index);
    const Vec3& p = positions[first];
    const std::string at = core::point_text(p.x(), p.y(), p.z());
    throw InvalidInput(name + ": " +
                       (positions.size() == 1 ? "the cell at " + at + " lies " + where
                                              : std::to_string(count) + " of the " + std::to_string(positions.size()) +
                                                    (count == 1 ? " cells lies " : " cells lie ") + where +
                                                    " (the first at " + at + ")") +
                       "; " + why);
  };
  auto refuse_if_inside = [&](const auto& solid, const std::vector<std::string>& given, const char* kind,
                              std::size_t index, const char* where) {
    refuse(given, kind, index, where, "obstacles must start outside the cells (touching them is fine)",
           [&](std::size_t i) { return inside(positions[i], solid, 0.0); });
  };
  for (std::size_t i = 0; i < obstacles.half_spaces.size(); ++i) {
    HalfSpace h = obstacles.half_spaces[i];
    h.normal.normalize();
    refuse_if_inside(h, names.half_spaces, "ground", i, "on its solid side");
  }
  for (std::size_t i = 0; i < obstacles.spheres.size(); ++i)
    refuse_if_inside(obstacles.spheres[i], names.spheres, "sphere", i, "inside it");
  for (std::size_t i = 0; i < obstacles.boxes.size(); ++i)
    refuse_if_inside(obstacles.boxes[i], names.boxes, "box", i, "inside it");
  // a cell on a wall is on neither side of it, so no move of it crosses the wall: refused, as inside a solid
  if (std::none_of(obstacles.meshes.begin(), obstacles.meshes.end(),
                   [](const auto& m) { return !m.triangles.empty(); }))
    return;
  std::optional<PreparedObstacles> own;  // built here only without a scene's
  const PreparedObstacles& index = prepared ? *prepared : own.emplace(obstacles);
  std::vector<std::optional<std::size_t>> touched(positions.size());
  core::parallel_for(positions.size(), threads, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) touched[i] = index.mesh_touched(positions[i]);
  });
  for (std::size_t k = 0; k < obstacles.meshes.size(); ++k)
    refuse(names.meshes, "mesh", k, "on its surface",
           "a cell on a mesh is on neither side of it and could pass through it: start the cells off the mesh (a "
           "tenth of a rest length is enough)",
           [&](std::size_t i) { return touched[i] == k; });
}

bool PreparedObstacles::inside_solid(const Vec3& position, double margin) const {
  for (const HalfSpace& h : obstacles_.half_spaces)
    if (inside(position, h, margin)) return true;
  for (const Sphere& s : obstacles_.spheres)
    if (inside(position, s, margin)) return true;
  for (const Box& b : obstacles_.boxes)
    if (inside(position, b, margin)) return true;
  return false;
}

std::optional<std::size_t> PreparedObstacles::mesh_touched(const Vec3& position) const {
  return index_ ? index_->mesh_touched(position) : std::nullopt;
}

bool PreparedObstacles::crosses_mesh(const Vec3& from, const Vec3& to) const {
  return index_ && index_->first_crossing(from, to).has_value();
}

void PreparedObstacles::mesh_crossings(const Vec3& from, const Vec3& to,
                                       std::vector<std::pair<double, std::size_t>>& out) const {
  out.clear();
  double limit = 1.0;
  if (index_)
    index_->crossings(from, to, limit,
                      [&](std::uint32_t i, double t, const Vec3&) { out.emplace_back(t, index_->triangles[i].mesh); });
}

Vec3 PreparedObstacles::stop_at_mesh(const Vec3& from, const Vec3& to, double margin) const {
  if (!index_) return to;
  const auto hit = index_->first_crossing(from, to);
  if (!hit) return to;
  const double side = (from - hit->point).dot(hit->normal) >= 0 ? 1.0 : -1.0;
  const Vec3 back = hit->point + std::max(margin, 1e-9 * index_->scale) * side * hit->normal;
  // in a concave corner that step back can cross another triangle: then halfway to the first crossing,
  // which is on the mother's side by construction
  return index_->first_crossing(from, back) ? Vec3(from + 0.5 * (hit->point - from)) : back;
}

void PreparedObstacles::apply(cells::Cells& cells, const std::vector<Vec3>& previous_positions, double margin,
                              int threads) const {
  if (!(margin >= 0) || !std::isfinite(margin))
    throw InvalidInput("obstacle margin is " + fmt(margin) + ", allowed: a finite value >= 0 (model units)");
  const std::size_t n = cells.size();
  if (previous_positions.size() != n)
    throw InvalidInput("apply_obstacles: " + std::to_string(previous_positions.size()) + " previous positions for " +
                       std::to_string(n) + " cells");
  if (obstacles_.empty()) return;
  const double mesh_backoff = index_ ? std::max(margin, 1e-9 * index_->scale) : margin;

  core::parallel_for(
      n, threads,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          if (cells.fixed[i]) continue;
          const Vec3& prev = previous_positions[i];
          Vec3 p = cells.position[i];
          Vec3 v = cells.velocity[i];
          bool changed = false;
          bool any_change = false;
          for (int pass = 0; pass < kMaxPasses; ++pass) {
            changed = false;
            if (index_) {
              if (const auto hit = index_->first_crossing(prev, p)) {
                // Back on the side the cell came from; crossing requires prev off the plane, so side != 0.
                const double side = (prev - hit->point).dot(hit->normal) >= 0 ? 1.0 : -1.0;
                const Vec3 towards_prev = side * hit->normal;
                p = hit->point + mesh_backoff * towards_prev;
                remove_inward(v, towards_prev);
                changed = true;
              }
            }
            for (const HalfSpace& h : obstacles_.half_spaces) changed |= constrain(h, margin, p, v);
            for (const Sphere& s : obstacles_.spheres) changed |= constrain(s, margin, prev, p, v);
            for (const Box& b : obstacles_.boxes) changed |= constrain(b, margin, prev, p, v);
            any_change |= changed;
            if (!changed) break;
          }
          if (changed && crosses_mesh(prev, p)) {  // (a pass that changed nothing found no crossing)
            // A mesh is never crossed, even where pushing a cell out of a solid would cross one (a cell
            // inside a box that stands on a mesh floor, its nearest way out under the floor): it stays
            p = prev;
            v.setZero();
          } else if (changed && inside_solid(p, margin) && !inside_solid(prev, margin)) {
            // Wedged between obstacles: stay where the cell was, as that was a valid place.
            p = prev;
            v.setZero();
          }
          if (any_change) {
            cells.position[i] = p;
            cells.velocity[i] = v;
          }
        }
      },
      512);
}

void apply_obstacles(cells::Cells& cells, const std::vector<Vec3>& previous_positions, const Obstacles& obstacles,
                     double margin, int threads) {
  if (obstacles.empty()) {
    PreparedObstacles(Obstacles{}).apply(cells, previous_positions, margin, threads);  // argument checks only
    return;
  }
  PreparedObstacles(obstacles).apply(cells, previous_positions, margin, threads);
}

}  // namespace cellform::forms
