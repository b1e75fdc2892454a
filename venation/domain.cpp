// Source domains of space colonisation: validation, dart throwing, inside tests and closest points in 3-D.
#include "venation/domain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include "core/errors.h"

namespace cellform::venation {

using core::InvalidInput;

namespace {

using core::number_text;

std::string point_text(const Vec3& p) { return core::point_text(p.x(), p.y(), p.z()); }

bool is_3d(DomainKind k) { return k != DomainKind::leaf; }

const char* kind_name(DomainKind k) {
  switch (k) {
    case DomainKind::leaf:
      return "leaf";
    case DomainKind::box:
      return "box";
    case DomainKind::ball:
      return "ball";
    case DomainKind::volume:
      return "volume";
    case DomainKind::surface:
      return "surface";
  }
  return "?";
}

/// Checks what can be checked without indexes: finite values, ranges, mesh indices, closedness.
void validate_shape(const Domain& d) {
  switch (d.kind) {
    case DomainKind::leaf:
      return;
    case DomainKind::box:
      if (!d.box_min.allFinite() || !d.box_max.allFinite())
        throw InvalidInput("domain.box: the corners must be finite");
      if ((d.box_min.array() >= d.box_max.array()).any())
        throw InvalidInput("domain.box: min " + point_text(d.box_min) + " must be below max " + point_text(d.box_max) +
                           " in x, y and z");
      return;
    case DomainKind::ball:
      if (!d.centre.allFinite()) throw InvalidInput("domain.ball: the centre must be finite");
      if (!(d.radius > 0 && std::isfinite(d.radius)))
        throw InvalidInput("domain.ball: the radius must be a positive, finite length in model units, got " +
                           number_text(d.radius));
      return;
    case DomainKind::volume:
    case DomainKind::surface:
      break;
  }
  const char* what = d.kind == DomainKind::volume ? "domain.volume" : "domain.surface";
  const Mesh& m = d.mesh;
  if (m.triangles.empty())
    throw InvalidInput(std::string(what) + ": the mesh has no triangles; a " + kind_name(d.kind) +
                       " needs a triangle mesh");
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    if (!m.vertices[i].allFinite())
      throw InvalidInput(std::string(what) + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (Index v : m.triangles[t])
      if (v >= m.vertices.size())
        throw InvalidInput(std::string(what) + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                           ", but the mesh has " + std::to_string(m.vertices.size()) + " vertices");
  double area = 0;
  for (const auto& t : m.triangles)
    area += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  if (!(area > 0)) throw InvalidInput(std::string(what) + ": every triangle of the mesh is degenerate (zero area)");
  if (d.kind != DomainKind::volume) return;
  // closed for the even-odd rule: every edge (between welded vertices) borders an even number of triangles
  std::vector<Index> order(m.vertices.size());
  std::iota(order.begin(), order.end(), Index{0});
  auto less = [&](Index a, Index b) {
    const Vec3 &p = m.vertices[a], &q = m.vertices[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<Index> weld(m.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    weld[order[i]] = (i > 0 && m.vertices[order[i]] == m.vertices[order[i - 1]]) ? weld[order[i - 1]] : order[i];
  std::vector<std::pair<Index, Index>> edges;
  for (const auto& t : m.triangles) {
    const Index a = weld[t[0]], b = weld[t[1]], c = weld[t[2]];
    if (a == b || b == c || a == c) continue;  // degenerate: no area, no boundary
    for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      edges.emplace_back(std::min(u, v), std::max(u, v));
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if ((j - i) % 2 != 0)
      throw InvalidInput(std::string(what) + ": the mesh is not closed: the edge from " +
                         point_text(m.vertices[edges[i].first]) + " to " + point_text(m.vertices[edges[i].second]) +
                         " borders " + std::to_string(j - i) +
                         " triangle(s); a volume needs a closed (watertight) mesh, or use it as a surface");
    i = j;
  }
}

/// Sign of the orientation of p about the projected edge a -> b in the xy plane, with p moved by
/// (eps, eps^2) (simulation of simplicity): never 0 unless a and b coincide in xy. The edge is evaluated
/// in one canonical direction, so two triangles sharing an edge see the same sign.
int orient_xy(const Vec3& a, const Vec3& b, const Vec3& p) {
  const bool swap = a.x() > b.x() || (a.x() == b.x() && a.y() > b.y());
  const Vec3& u = swap ? b : a;
  const Vec3& v = swap ? a : b;
  const double det = (v.x() - u.x()) * (p.y() - u.y()) - (v.y() - u.y()) * (p.x() - u.x());
  int s = det > 0 ? 1 : det < 0 ? -1 : 0;
  if (s == 0) s = v.y() != u.y() ? (v.y() > u.y() ? -1 : 1) : (v.x() > u.x() ? 1 : v.x() < u.x() ? -1 : 0);
  return swap ? -s : s;
}

}  // namespace

void validate(const Domain& d) {
  if (d.kind == DomainKind::leaf) {
    validate(d.leaf);
    return;
  }
  PreparedDomain prepared(d);  // validates shape, seeds and sources
}

void validate(const Leaf& leaf, const ColonisationParams& p) {
  // closed: seeds on one point never grow apart (a source between them keeps both its nearest, alike), and
  // the pattern stalls at once; open ones grow from the first and leave the others alone, harmlessly
  if (p.type != VenationType::closed) return;
  if (const auto r = first_repeat(leaf.initial_nodes))
    throw InvalidInput("leaf.initial_nodes[" + std::to_string(r->second + 1) + "] repeats leaf.initial_nodes[" +
                       std::to_string(r->first + 1) +
                       "]: the seed vein nodes of a closed pattern must be distinct "
                       "points");
}

Eigen::AlignedBox3d bounding_box(const Domain& d) {
  Eigen::AlignedBox3d box;
  if (d.kind == DomainKind::box) box.extend(d.box_min).extend(d.box_max);
  if (d.kind == DomainKind::ball)
    box.extend(d.centre - Vec3::Constant(d.radius)).extend(d.centre + Vec3::Constant(d.radius));
  if (d.kind == DomainKind::volume || d.kind == DomainKind::surface)
    for (const Vec3& v : d.mesh.vertices) box.extend(v);
  return box;
}

void validate(const Domain& d, const ColonisationParams& p) {
  if (d.kind == DomainKind::leaf) {
    validate(d.leaf, p);
  } else if (p.type == VenationType::closed) {  // as for a leaf
    if (const auto r = first_repeat(d.initial_nodes))
      throw InvalidInput("domain.initial_nodes[" + std::to_string(r->second + 1) + "] " +
                         point_text(d.initial_nodes[r->second]) + " repeats domain.initial_nodes[" +
                         std::to_string(r->first + 1) +
                         "]: the seed vein nodes of a closed pattern must be distinct points");
  }
  if (!is_3d(d.kind)) return;
  const std::string where = std::string("a ") + kind_name(d.kind) + " domain";
  if (p.growth != GrowthMode::none)
    throw InvalidInput("colonisation.growth must be none for " + where +
                       ": the blade growth modes (marginal, uniform, nonuniform) scale a planar leaf outline");
  if (p.initial_scale != 1)
    throw InvalidInput("colonisation.initial_scale must be 1 for " + where +
                       ": a 3-D domain is given in model units and does not grow");
  if (p.type == VenationType::closed && p.neighbourhood == Neighbourhood::urquhart)
    throw InvalidInput(
        "colonisation.neighbourhood = urquhart works only in the plane of a leaf (it needs a planar "
        "Delaunay triangulation); " +
        where + " needs neighbourhood = exact");
}

struct PreparedDomain::Impl {
  Domain d;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  double measure = 0;  // what darts are thrown over
  double own = 0;      // the domain's own volume or area

  // triangles as positions
  std::vector<std::array<Vec3, 3>> tri;
  std::vector<double> cumulative_area;  // surface: prefix sums for area-weighted sampling

  // bounding-volume hierarchy for closest points: node boxes, children or a triangle range
  struct Node {
    Vec3 lo, hi;
    int child[2] = {-1, -1};
    std::uint32_t first = 0, count = 0;  // leaves: order[first, first + count)
  };
  std::vector<Node> nodes;
  std::vector<std::uint32_t> order;

  // volume: a uniform grid over the xy bounding box; each cell lists the triangles whose xy box meets it
  std::vector<std::uint32_t> cell_start, cell_tris;
  int gx = 1, gy = 1;
  double cw = 1, ch = 1;

  explicit Impl(const Domain& domain) : d(domain) {
    switch (d.kind) {
      case DomainKind::box:
        lo = d.box_min;
        hi = d.box_max;
        own = measure = (hi - lo).prod();
        return;
      case DomainKind::ball:
        lo = d.centre - Vec3::Constant(d.radius);
        hi = d.centre + Vec3::Constant(d.radius);
        measure = (hi - lo).prod();
        own = 4 * std::numbers::pi / 3 * d.radius * d.radius * d.radius;
        return;
      default:
        break;
    }
    lo = hi = d.mesh.vertices[d.mesh.triangles[0][0]];
    for (const auto& t : d.mesh.triangles) {
      std::array<Vec3, 3> p{d.mesh.vertices[t[0]], d.mesh.vertices[t[1]], d.mesh.vertices[t[2]]};
      for (const Vec3& q : p) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      tri.push_back(p);
    }
    build_tree();
    if (d.kind == DomainKind::surface) {
      double sum = 0;
      for (const auto& p : tri) {
        sum += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
        cumulative_area.push_back(sum);
      }
      own = measure = sum;
    } else {
      measure = (hi - lo).prod();
      build_grid();
      // the share of a 24^3 lattice of cell centres inside: the even-odd rule's volume, whatever the shells'
      // orientation (which the divergence theorem would need consistent), within a few percent
      constexpr int kLattice = 24;
      int inside = 0;
      for (int i = 0; i < kLattice; ++i)
        for (int j = 0; j < kLattice; ++j)
          for (int k = 0; k < kLattice; ++k)
            inside += inside_mesh(lo + (Vec3(i, j, k).array() + 0.5).matrix().cwiseProduct(hi - lo) / kLattice);
      own = measure * inside / (kLattice * kLattice * kLattice);
    }
  }

  void build_tree() {
    order.resize(tri.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<Vec3> centroid(tri.size());
    for (std::size_t i = 0; i < tri.size(); ++i) centroid[i] = (tri[i][0] + tri[i][1] + tri[i][2]) / 3;
    nodes.reserve(2 * tri.size() / 4 + 2);
    build(0, static_cast<std::uint32_t>(tri.size()), centroid);
  }

  int build(std::uint32_t first, std::uint32_t last, const std::vector<Vec3>& centroid) {
    const int id = static_cast<int>(nodes.size());
    nodes.emplace_back();
    Vec3 blo = tri[order[first]][0], bhi = blo, clo = centroid[order[first]], chi = clo;
    for (std::uint32_t i = first; i < last; ++i) {
      for (const Vec3& q : tri[order[i]]) {
        blo = blo.cwiseMin(q);
        bhi = bhi.cwiseMax(q);
      }
      clo = clo.cwiseMin(centroid[order[i]]);
      chi = chi.cwiseMax(centroid[order[i]]);
    }
    nodes[id].lo = blo;
    nodes[id].hi = bhi;
    if (last - first <= 4) {
      nodes[id].first = first;
      nodes[id].count = last - first;
      return id;
    }
    int dim = 0;
    (chi - clo).maxCoeff(&dim);
    const std::uint32_t mid = first + (last - first) / 2;
    std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + last,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centroid[a][dim] < centroid[b][dim] || (centroid[a][dim] == centroid[b][dim] && a < b);
                     });
    const int l = build(first, mid, centroid);
    const int r = build(mid, last, centroid);
    nodes[id].child[0] = l;
    nodes[id].child[1] = r;
    return id;
  }

  static double box_d2(const Node& n, const Vec3& q) { return (q.cwiseMax(n.lo).cwiseMin(n.hi) - q).squaredNorm(); }

  Vec3 closest(const Vec3& q) const {
    double best_d2 = std::numeric_limits<double>::infinity();
    std::uint32_t best_t = 0;
    Vec3 best = q;
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const Node& n = nodes[stack.back()];
      stack.pop_back();
      if (box_d2(n, q) > best_d2) continue;
      if (n.child[0] < 0) {
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
          const std::uint32_t t = order[i];
          const Vec3 c = closest_point_on_triangle(q, tri[t][0], tri[t][1], tri[t][2]);
          const double d2 = (c - q).squaredNorm();
          if (d2 < best_d2 || (d2 == best_d2 && t < best_t)) {
            best_d2 = d2;
            best_t = t;
            best = c;
          }
        }
        continue;
      }
      const double a = box_d2(nodes[n.child[0]], q), b = box_d2(nodes[n.child[1]], q);
      // nearer child on top of the stack
      if (a <= b) {
        stack.push_back(n.child[1]);
        stack.push_back(n.child[0]);
      } else {
        stack.push_back(n.child[0]);
        stack.push_back(n.child[1]);
      }
    }
    return best;
  }

  int cell_x(double x) const { return std::clamp(static_cast<int>(std::floor((x - lo.x()) / cw)), 0, gx - 1); }
  int cell_y(double y) const { return std::clamp(static_cast<int>(std::floor((y - lo.y()) / ch)), 0, gy - 1); }

  void build_grid() {
    const double n = std::max(1.0, std::sqrt(static_cast<double>(tri.size())));
    const Vec3 ext = (hi - lo).cwiseMax(Vec3::Constant(1e-300));
    const double side = std::sqrt(ext.x() * ext.y() / n);
    gx = std::clamp(static_cast<int>(std::ceil(ext.x() / side)), 1, 4096);
    gy = std::clamp(static_cast<int>(std::ceil(ext.y() / side)), 1, 4096);
    cw = ext.x() / gx;
    ch = ext.y() / gy;
    std::vector<std::uint32_t> count(static_cast<std::size_t>(gx) * gy + 1, 0);
    auto range = [&](const std::array<Vec3, 3>& t, int& x0, int& x1, int& y0, int& y1) {
      x0 = cell_x(std::min({t[0].x(), t[1].x(), t[2].x()}));
      x1 = cell_x(std::max({t[0].x(), t[1].x(), t[2].x()}));
      y0 = cell_y(std::min({t[0].y(), t[1].y(), t[2].y()}));
      y1 = cell_y(std::max({t[0].y(), t[1].y(), t[2].y()}));
    };
    for (const auto& t : tri) {
      int x0, x1, y0, y1;
      range(t, x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) ++count[static_cast<std::size_t>(y) * gx + x + 1];
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    cell_start = count;
    cell_tris.resize(count.back());
    for (std::uint32_t i = 0; i < tri.size(); ++i) {
      int x0, x1, y0, y1;
      range(tri[i], x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) cell_tris[count[static_cast<std::size_t>(y) * gx + x]++] = i;
    }
  }

  /// Even-odd rule along the ray from q towards +z, with q perturbed by (eps, eps^2, 0) so that rays
  /// through vertices and edges count every crossing once.
  bool inside_mesh(const Vec3& q) const {
    if ((q.array() < lo.array()).any() || (q.array() > hi.array()).any()) return false;
    const std::size_t c = static_cast<std::size_t>(cell_y(q.y())) * gx + cell_x(q.x());
    bool inside = false;
    for (std::uint32_t k = cell_start[c]; k < cell_start[c + 1]; ++k) {
      const auto& t = tri[cell_tris[k]];
      const double area2 =
          (t[1].x() - t[0].x()) * (t[2].y() - t[0].y()) - (t[1].y() - t[0].y()) * (t[2].x() - t[0].x());
      if (area2 == 0) continue;  // vertical: the perturbed ray misses it
      const int s = area2 > 0 ? 1 : -1;
      if (orient_xy(t[0], t[1], q) != s || orient_xy(t[1], t[2], q) != s || orient_xy(t[2], t[0], q) != s) continue;
      // height of the triangle's plane above (x, y)
      const double w0 = ((t[1].x() - q.x()) * (t[2].y() - q.y()) - (t[1].y() - q.y()) * (t[2].x() - q.x())) / area2;
      const double w1 = ((t[2].x() - q.x()) * (t[0].y() - q.y()) - (t[2].y() - q.y()) * (t[0].x() - q.x())) / area2;
      const double z = w0 * t[0].z() + w1 * t[1].z() + (1 - w0 - w1) * t[2].z();
      if (z > q.z()) inside = !inside;
    }
    return inside;
  }

  bool inside(const Vec3& q) const {
    switch (d.kind) {
      case DomainKind::box:
        return (q.array() >= lo.array()).all() && (q.array() <= hi.array()).all();
      case DomainKind::ball:
        return (q - d.centre).squaredNorm() <= d.radius * d.radius;
      case DomainKind::volume:
        return inside_mesh(q);
      default:
        return false;
    }
  }

  Vec3 project(const Vec3& q) const {
    switch (d.kind) {
      case DomainKind::box:
        return q.cwiseMax(lo).cwiseMin(hi);
      case DomainKind::ball: {
        const Vec3 r = q - d.centre;
        const double n = r.norm();
        return n <= d.radius ? q : Vec3(d.centre + r * (d.radius / n));
      }
      case DomainKind::volume:
        return inside_mesh(q) ? q : closest(q);
      default:
        return closest(q);
    }
  }

  double distance_outside(const Vec3& q) const {
    switch (d.kind) {
      case DomainKind::surface:
        return (closest(q) - q).norm();
      default:
        return inside(q) ? 0.0 : (project(q) - q).norm();
    }
  }
};

PreparedDomain::PreparedDomain(const Domain& domain) {
  if (domain.kind == DomainKind::leaf)
    throw InvalidInput("domain: a leaf is planar and needs no PreparedDomain (use the Leaf constructor)");
  validate_shape(domain);
  impl_ = std::make_unique<Impl>(domain);
  const double tol = 1e-6 * (impl_->hi - impl_->lo).norm();
  const char* on = domain.kind == DomainKind::surface ? "on the surface" : "inside the domain";
  if (domain.initial_nodes.empty())
    throw InvalidInput(std::string("domain.initial_nodes: a ") + kind_name(domain.kind) +
                       " domain needs at least one seed vein node " + on);
  auto check = [&](const std::vector<Vec3>& pts, const char* name) {
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!pts[i].allFinite() || !(impl_->distance_outside(pts[i]) <= tol)) {
        // how far, and (on a surface) where the nearest point is: a point picked in a modeller and typed with
        // three decimals is off by more than the tolerance
        const std::string off =
            !pts[i].allFinite()
                ? std::string()
                : ": it is " + number_text(impl_->distance_outside(pts[i])) + " model units off" +
                      (domain.kind == DomainKind::surface && !impl_->tri.empty()
                           ? ", the nearest point of the surface is " + point_text(impl_->closest(pts[i]))
                           : std::string());
        throw InvalidInput(std::string("domain.") + name + "[" + std::to_string(i + 1) + "] " + point_text(pts[i]) +
                           " is not " + on + " (" + kind_name(domain.kind) +
                           "; tolerance 1e-6 of the bounding-box diagonal, in model units)" + off);
      }
  };
  check(domain.initial_nodes, "initial_nodes");
  check(domain.initial_sources, "initial_sources");
}
PreparedDomain::~PreparedDomain() = default;
PreparedDomain::PreparedDomain(PreparedDomain&&) noexcept = default;
PreparedDomain& PreparedDomain::operator=(PreparedDomain&&) noexcept = default;

void PreparedDomain::throw_darts(double rho, core::Rng& rng, std::vector<Vec3>& out) const {
  const Impl& I = *impl_;
  const double expected = rho * I.measure;
  auto count = static_cast<std::size_t>(std::floor(expected));
  if (rng.uniform() < expected - std::floor(expected)) ++count;
  if (I.d.kind == DomainKind::surface) {
    const double total = I.cumulative_area.back();
    for (std::size_t k = 0; k < count; ++k) {
      const double u = rng.uniform() * total;
      auto it = std::upper_bound(I.cumulative_area.begin(), I.cumulative_area.end(), u);
      if (it == I.cumulative_area.end()) --it;
      const auto& t = I.tri[static_cast<std::size_t>(it - I.cumulative_area.begin())];
      const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
      out.push_back((1 - r1) * t[0] + r1 * (1 - r2) * t[1] + r1 * r2 * t[2]);
    }
    return;
  }
  for (std::size_t k = 0; k < count; ++k) {
    const double x = rng.uniform(I.lo.x(), I.hi.x());
    const double y = rng.uniform(I.lo.y(), I.hi.y());
    const double z = rng.uniform(I.lo.z(), I.hi.z());
    const Vec3 q(x, y, z);
    if (I.inside(q)) out.push_back(q);
  }
}

double PreparedDomain::dart_measure() const { return impl_->measure; }

double PreparedDomain::measure() const { return impl_->own; }

bool PreparedDomain::contains(const Vec3& q, double tolerance) const { return impl_->distance_outside(q) <= tolerance; }

Vec3 PreparedDomain::project(const Vec3& q) const { return impl_->project(q); }

Vec3 PreparedDomain::closest_point(const Vec3& q) const {
  if (impl_->tri.empty()) return impl_->project(q);
  return impl_->closest(q);
}

const Vec3& PreparedDomain::lo() const { return impl_->lo; }
const Vec3& PreparedDomain::hi() const { return impl_->hi; }
const Domain& PreparedDomain::domain() const { return impl_->d; }

}  // namespace cellform::venation
