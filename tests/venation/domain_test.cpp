// Tests of 3-D source domains: inside tests, closest points, darts, and space colonisation in volumes and on surfaces.
#include "venation/domain.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numbers>

#include "core/errors.h"
#include "tests/venation/eq1_oracle.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Index;
using core::kNoIndex;
using core::Vec3;
namespace v = cellform::venation;

namespace {

/// The octahedron |x| + |y| + |z| <= r: vertices on the axes, so rays along z through its vertices and
/// edges are the degenerate cases of the even-odd rule.
v::Mesh octahedron(double r, bool inward = false) {
  v::Mesh m;
  m.vertices = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
  for (Index x : {0u, 1u})
    for (Index y : {2u, 3u})
      for (Index z : {4u, 5u}) {
        std::array<Index, 3> t{x, y, z};
        if (inward) std::swap(t[1], t[2]);
        m.triangles.push_back(t);
      }
  return m;
}

/// A sphere of radius r: the octahedron subdivided `levels` times, vertices pushed onto the sphere.
v::Mesh icosphere(double r, int levels) {
  v::Mesh m = octahedron(1);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back(((m.vertices[a] + m.vertices[b]) / 2).normalized());
      return mid[key] = static_cast<Index>(m.vertices.size() - 1);
    };
    std::vector<std::array<Index, 3>> next;
    for (const auto& t : m.triangles) {
      const Index a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = next;
  }
  for (Vec3& p : m.vertices) p *= r;
  return m;
}

/// The shell between two octahedra about the origin, the inner one wound as the outer (the even-odd rule does
/// not mind).
v::Mesh hollow_octahedron(double outer, double inner) {
  v::Mesh m = octahedron(outer);
  const v::Mesh in = octahedron(inner);
  for (auto t : in.triangles) m.triangles.push_back({t[0] + 6, t[1] + 6, t[2] + 6});
  m.vertices.insert(m.vertices.end(), in.vertices.begin(), in.vertices.end());
  return m;
}

double l1(const Vec3& p) { return std::abs(p.x()) + std::abs(p.y()) + std::abs(p.z()); }

v::ColonisationParams params3d(v::VenationType type, double birth = 2.5) {
  v::ColonisationParams p;
  p.type = type;
  p.kill_distance = 1;
  p.source_birth_distance = p.vein_birth_distance = birth;
  p.node_distance = 1;
  p.darts_per_area = 0.02;
  p.growth = v::GrowthMode::none;
  p.seed = 5;
  p.max_steps = 2000;
  return p;
}

/// Every node's parent chain ends at a seed node (birth step 0, no parent); parents precede children.
void require_forest_from_seeds(const v::VeinTree& t, std::size_t seeds) {
  REQUIRE(t.size() > seeds);
  for (Index i = 0; i < t.size(); ++i) {
    if (i < seeds) {
      REQUIRE(t.parent[i] == kNoIndex);
      REQUIRE(t.birth_step[i] == 0);
    } else {
      REQUIRE(t.parent[i] != kNoIndex);
      REQUIRE(t.parent[i] < i);  // no cycle: every chain strictly descends to a seed
      REQUIRE(t.birth_step[i] > t.birth_step[t.parent[i]]);
    }
  }
}

}  // namespace

TEST_CASE("mesh volumes: the even-odd inside test agrees with the analytic octahedron, rays through vertices too",
          "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::volume;
  d.mesh = octahedron(1);
  d.initial_nodes = {Vec3::Zero()};
  for (bool inward : {false, true}) {
    d.mesh = octahedron(1, inward);  // orientation does not matter
    const v::PreparedDomain pd(d);
    // a lattice through the vertices and along the edges' projections: every degenerate ray
    int checked = 0;
    for (double x = -1.25; x <= 1.25; x += 0.125)
      for (double y = -1.25; y <= 1.25; y += 0.125)
        for (double z = -1.25; z <= 1.25; z += 0.125) {
          const Vec3 q(x, y, z);
          if (std::abs(l1(q) - 1) < 1e-12) continue;  // on the boundary: either answer is right
          CHECK(pd.contains(q, 0) == (l1(q) < 1));
          ++checked;
        }
    CHECK(checked > 5000);
    core::Rng rng(3);
    for (int i = 0; i < 20000; ++i) {
      const Vec3 q(rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2));
      if (std::abs(l1(q) - 1) < 1e-9) continue;
      REQUIRE(pd.contains(q, 0) == (l1(q) < 1));
    }
  }
  // a hollow octahedron (inner shell): inside is between the two
  d.mesh = hollow_octahedron(1, 0.5);
  d.initial_nodes = {Vec3(0.75, 0, 0)};
  const v::PreparedDomain pd(d);
  for (double x = -1.25; x <= 1.25; x += 0.125)
    for (double z = -1.25; z <= 1.25; z += 0.125) {
      const Vec3 q(x, 0.0625, z);
      if (std::abs(l1(q) - 1) < 1e-12 || std::abs(l1(q) - 0.5) < 1e-12) continue;
      CHECK(pd.contains(q, 0) == (l1(q) < 1 && l1(q) > 0.5));
    }
}

TEST_CASE("a domain's own measure: a box's and a ball's volume, a mesh volume's by lattice, a surface's area",
          "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::box;
  d.box_min = Vec3(0, 0, 0);
  d.box_max = Vec3(2, 3, 4);
  d.initial_nodes = {Vec3(1, 1, 1)};
  CHECK(v::PreparedDomain(d).measure() == 24);
  d.kind = v::DomainKind::ball;
  d.centre = Vec3::Zero();
  d.radius = 2;
  d.initial_nodes = {Vec3::Zero()};
  CHECK(v::PreparedDomain(d).measure() == Approx(32 * std::numbers::pi / 3));
  CHECK(v::PreparedDomain(d).dart_measure() == 64);  // darts are thrown over its box
  d.kind = v::DomainKind::volume;
  d.mesh = octahedron(2);
  CHECK(v::PreparedDomain(d).measure() == Approx(4.0 / 3 * 8).epsilon(0.05));
  d.mesh = hollow_octahedron(2, 1);  // the shell between them
  d.initial_nodes = {Vec3(1.5, 0, 0)};
  CHECK(v::PreparedDomain(d).measure() == Approx(4.0 / 3 * (8 - 1)).epsilon(0.05));
  d.kind = v::DomainKind::surface;
  d.mesh = octahedron(2);
  d.initial_nodes = {Vec3(2, 0, 0)};
  CHECK(v::PreparedDomain(d).measure() == Approx(4 * std::sqrt(3.0) * 4));
}

TEST_CASE("closest points equal a brute-force scan of every triangle", "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::surface;
  d.mesh = icosphere(3, 3);
  d.initial_nodes = {d.mesh.vertices[0]};
  const v::PreparedDomain pd(d);
  core::Rng rng(9);
  for (int i = 0; i < 500; ++i) {
    const Vec3 q(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    double best = 1e300;
    for (const auto& t : d.mesh.triangles) {
      const Vec3 c =
          v::closest_point_on_triangle(q, d.mesh.vertices[t[0]], d.mesh.vertices[t[1]], d.mesh.vertices[t[2]]);
      best = std::min(best, (c - q).squaredNorm());
    }
    REQUIRE((pd.closest_point(q) - q).squaredNorm() == Approx(best).margin(1e-12));
    REQUIRE((pd.project(q) - pd.closest_point(q)).norm() == 0);
  }
}

TEST_CASE("surface darts are area-weighted: counts per triangle pass a chi-square test", "[domain]") {
  // five separate triangles in different planes, areas 1 : 2 : 3 : 4 : 10
  v::Domain d;
  d.kind = v::DomainKind::surface;
  const double areas[] = {1, 2, 3, 4, 10};
  for (int k = 0; k < 5; ++k) {
    const double s = std::sqrt(2 * areas[k]);  // right triangle with legs s: area s^2 / 2
    const Vec3 o(10.0 * k, 0, 0);
    const Vec3 axes[5][2] = {{Vec3::UnitX(), Vec3::UnitY()},
                             {Vec3::UnitY(), Vec3::UnitZ()},
                             {Vec3::UnitX(), Vec3::UnitZ()},
                             {Vec3(1, 1, 0).normalized(), Vec3::UnitZ()},
                             {Vec3::UnitZ(), Vec3(1, 1, 0).normalized()}};
    const Vec3 e1 = axes[k][0], e2 = axes[k][1];
    const auto base = static_cast<Index>(d.mesh.vertices.size());
    d.mesh.vertices.insert(d.mesh.vertices.end(), {o, o + s * e1, o + s * e2});
    d.mesh.triangles.push_back({base, base + 1, base + 2});
  }
  d.initial_nodes = {d.mesh.vertices[0]};
  const v::PreparedDomain pd(d);
  REQUIRE(pd.dart_measure() == Approx(20));
  core::Rng rng(11);
  std::vector<Vec3> darts;
  pd.throw_darts(1000, rng, darts);  // 20000 darts
  REQUIRE(darts.size() == 20000);
  std::vector<double> count(5, 0);
  std::vector<Vec3> mean(5, Vec3::Zero());
  for (const Vec3& q : darts) {
    int k = -1;
    for (int t = 0; t < 5; ++t) {
      const auto& tri = d.mesh.triangles[static_cast<std::size_t>(t)];
      const Vec3 c =
          v::closest_point_on_triangle(q, d.mesh.vertices[tri[0]], d.mesh.vertices[tri[1]], d.mesh.vertices[tri[2]]);
      if ((c - q).norm() < 1e-9) k = t;
    }
    REQUIRE(k >= 0);  // every dart lies on a triangle
    count[static_cast<std::size_t>(k)] += 1;
    mean[static_cast<std::size_t>(k)] += q;
  }
  double chi2 = 0;
  for (int k = 0; k < 5; ++k) {
    const double expected = 20000 * areas[k] / 20;
    chi2 += std::pow(count[static_cast<std::size_t>(k)] - expected, 2) / expected;
  }
  CHECK(chi2 < 18.5);  // 4 degrees of freedom: P(chi2 > 18.5) ~ 0.001
  // uniform within each triangle: the mean dart is the centroid (standard error ~ size / sqrt(18 n))
  for (int k = 0; k < 5; ++k) {
    const auto& tri = d.mesh.triangles[static_cast<std::size_t>(k)];
    const Vec3 centroid = (d.mesh.vertices[tri[0]] + d.mesh.vertices[tri[1]] + d.mesh.vertices[tri[2]]) / 3;
    const double size = std::sqrt(2 * areas[k]);
    CHECK((mean[static_cast<std::size_t>(k)] / count[static_cast<std::size_t>(k)] - centroid).norm() <
          5 * size / std::sqrt(18 * count[static_cast<std::size_t>(k)]) * std::sqrt(3.0));
  }
}

TEST_CASE("volume darts fall inside at rho per unit volume", "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::volume;
  d.mesh = octahedron(1);
  d.initial_nodes = {Vec3::Zero()};
  const v::PreparedDomain pd(d);
  core::Rng rng(2);
  std::vector<Vec3> darts;
  pd.throw_darts(3000, rng, darts);  // 24000 in the bounding box, 4000 expected inside (volume 4/3)
  for (const Vec3& q : darts) REQUIRE(l1(q) <= 1);
  const double sd = std::sqrt(24000 * (1.0 / 6) * (5.0 / 6));
  CHECK(std::abs(static_cast<double>(darts.size()) - 4000) < 4 * sd);
  // box and ball: darts inside, count rho x volume
  v::Domain ball;
  ball.kind = v::DomainKind::ball;
  ball.centre = Vec3(1, 2, 3);
  ball.radius = 2;
  ball.initial_nodes = {ball.centre};
  const v::PreparedDomain pb(ball);
  darts.clear();
  pb.throw_darts(100, rng, darts);  // 6400 in the cube, 3351 expected in the ball
  for (const Vec3& q : darts) REQUIRE((q - ball.centre).norm() <= 2);
  CHECK(std::abs(static_cast<double>(darts.size()) - 100 * 4.0 / 3 * M_PI * 8) <
        4 * std::sqrt(6400 * (M_PI / 6) * (1 - M_PI / 6)));
}

TEST_CASE("a domain's bounding box: the box, the ball's box, the mesh's vertices; none for a leaf", "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::box;
  d.box_min = Vec3(-1, 2, 3);
  d.box_max = Vec3(4, 5, 9);
  CHECK(v::bounding_box(d).min() == d.box_min);
  CHECK(v::bounding_box(d).max() == d.box_max);
  d.kind = v::DomainKind::ball;
  d.centre = Vec3(1, 2, 3);
  d.radius = 2;
  CHECK(v::bounding_box(d).min() == Vec3(-1, 0, 1));
  CHECK(v::bounding_box(d).max() == Vec3(3, 4, 5));
  d.kind = v::DomainKind::surface;
  d.mesh = octahedron(1.5);
  CHECK(v::bounding_box(d).sizes() == Vec3(3, 3, 3));
  d.kind = v::DomainKind::leaf;
  CHECK(v::bounding_box(d).isEmpty());
}

TEST_CASE("open colonisation in 3-D volumes grows a forest from the seeds, inside the volume",
          "[domain][colonisation]") {
  std::vector<v::Domain> domains(3);
  domains[0].kind = v::DomainKind::box;
  domains[0].box_min = Vec3(-6, -6, 0);
  domains[0].box_max = Vec3(6, 6, 14);
  domains[0].initial_nodes = {Vec3(-3, 0, 0), Vec3(3, 0, 0)};  // on the floor
  domains[1].kind = v::DomainKind::ball;
  domains[1].centre = Vec3(0, 0, 7);
  domains[1].radius = 7;
  domains[1].initial_nodes = {Vec3(0, 0, 0)};  // the lowest point of the ball
  domains[2].kind = v::DomainKind::volume;
  domains[2].mesh = octahedron(9);
  domains[2].initial_nodes = {Vec3(0, 0, -9)};  // a vertex
  for (const v::Domain& d : domains) {
    const v::PreparedDomain pd(d);
    const double tol = 1e-9 * (pd.hi() - pd.lo()).norm();
    v::Colonisation c(d, params3d(v::VenationType::open));
    while (!c.done()) {
      c.step();
      for (const Vec3& s : c.sources()) REQUIRE(pd.contains(s, tol));
    }
    const v::VeinTree t = c.tree();
    INFO("domain kind " << static_cast<int>(d.kind));
    CHECK(c.report().finished);
    CHECK(t.anastomoses.empty());
    require_forest_from_seeds(t, d.initial_nodes.size());
    for (const Vec3& p : t.positions) REQUIRE(pd.contains(p, tol));
    double top = 0;
    for (const Vec3& p : t.positions) top = std::max(top, p.z() - pd.lo().z());
    CHECK(top > 0.7 * (pd.hi().z() - pd.lo().z()));  // the veins fill the volume, not only the plane
    for (Index i = 0; i < t.size(); ++i)
      if (t.parent[i] != kNoIndex) REQUIRE((t.positions[i] - t.positions[t.parent[i]]).norm() <= 1 + 1e-12);
  }
}

TEST_CASE("colonisation on a surface keeps sources and vein nodes on it", "[domain][colonisation]") {
  v::Domain d;
  d.kind = v::DomainKind::surface;
  d.mesh = icosphere(8, 3);
  d.initial_nodes = {Vec3(0, 0, -8)};  // the south pole, a vertex
  const v::PreparedDomain pd(d);
  for (v::VenationType type : {v::VenationType::open, v::VenationType::closed}) {
    v::Colonisation c(d, params3d(type, 2));
    while (!c.done()) {
      c.step();
      for (const Vec3& s : c.sources()) REQUIRE((pd.closest_point(s) - s).norm() < 1e-9);
    }
    const v::VeinTree t = c.tree();
    CHECK(t.size() > 100);
    for (const Vec3& p : t.positions) REQUIRE((pd.closest_point(p) - p).norm() < 1e-9);
    require_forest_from_seeds(t, 1);
    double north = -8;
    for (const Vec3& p : t.positions) north = std::max(north, p.z());
    CHECK(north > 6);  // the veins reach round the sphere
    if (type == v::VenationType::open) CHECK(t.anastomoses.empty());
  }
}

TEST_CASE("closed 3-D colonisation steps with the exact relative neighbourhood (brute-force Eq. 2 oracle)",
          "[domain][colonisation]") {
  // no darts: fixed sources, so every step's influence can be recomputed from outside
  v::Domain d;
  d.kind = v::DomainKind::box;
  d.box_min = Vec3(-5, -5, 0);
  d.box_max = Vec3(5, 5, 8);
  d.initial_nodes = {Vec3(-1, 0, 0), Vec3(1.5, 0.5, 0)};
  core::Rng rng(17);
  for (int i = 0; i < 40; ++i)
    d.initial_sources.push_back(Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(1, 8)));
  v::ColonisationParams p = params3d(v::VenationType::closed);
  p.darts_per_area = 0;
  p.kill_distance = 1.5;
  for (int threads : {1, 3}) {
    p.threads = threads;
    v::Colonisation c(d, p);
    std::size_t steps = 0, checked_nodes = 0;
    while (!c.done()) {
      const v::VeinTree before = c.tree();
      const std::vector<Vec3> sources = c.sources();
      const v::testing::Eq1Pulls e = v::testing::eq1_pulls(before.positions, sources, p.kill_distance);
      const std::vector<Vec3>& acc = e.sum;
      const std::vector<char>& touched = e.pulled;
      const std::vector<Index>& nearest_source = e.nearest_source;
      auto retraces = [&](Index u, const Vec3& q) { return v::testing::retraces(before, u, q); };
      auto in_box = [&](const Vec3& q) { return Vec3(q.cwiseMax(d.box_min).cwiseMin(d.box_max)); };
      c.step();
      const v::VeinTree after = c.tree();
      std::map<Index, Vec3> grown = v::testing::grown_by_parent(before, after);
      for (Index u = 0; u < before.size(); ++u) {
        if (!touched[u]) {
          REQUIRE(grown.count(u) == 0);
          continue;
        }
        const bool cancel = acc[u].norm() <= 1e-9;
        Vec3 q = cancel ? before.positions[u] : in_box(before.positions[u] + acc[u].normalized());
        if (cancel || retraces(u, q)) {  // no direction, or Eq. 1 retraces a segment: towards the nearest source alone
          const Vec3 dir = sources[nearest_source[u]] - before.positions[u];
          q = in_box(before.positions[u] + dir / dir.norm());
        }
        if ((q - before.positions[u]).norm() < 0.1 || retraces(u, q)) {  // no progress, no node
          REQUIRE(grown.count(u) == 0);
          continue;
        }
        REQUIRE(grown.count(u) == 1);
        REQUIRE((grown[u] - q).norm() < 1e-12);
        ++checked_nodes;
      }
      ++steps;
    }
    CHECK(steps > 5);
    CHECK(checked_nodes > 50);
    CHECK(c.report().finished);
    CHECK(c.report().loops > 0);
  }
}

TEST_CASE("3-D runs are bitwise identical for any thread count", "[domain][colonisation]") {
  v::Domain d;
  d.kind = v::DomainKind::ball;
  d.centre = Vec3(0, 0, 0);
  d.radius = 8;
  d.initial_nodes = {Vec3(0, 0, -8)};
  v::ColonisationParams p = params3d(v::VenationType::closed);
  p.threads = 1;
  const auto [a, ra] = v::colonise(d, p);
  p.threads = 3;
  const auto [b, rb] = v::colonise(d, p);
  REQUIRE(a.size() == b.size());
  CHECK(a.positions == b.positions);
  CHECK(a.parent == b.parent);
  CHECK(a.anastomoses == b.anastomoses);
  CHECK(ra.loops == rb.loops);
}

TEST_CASE("bad 3-D domains and parameters name what is wrong", "[domain]") {
  v::Domain d;
  d.kind = v::DomainKind::volume;
  d.mesh = octahedron(2);
  d.initial_nodes = {Vec3::Zero()};
  const v::ColonisationParams ok = params3d(v::VenationType::closed);
  REQUIRE_NOTHROW(v::Colonisation(d, ok));

  v::Domain open_mesh = d;
  open_mesh.mesh.triangles.pop_back();
  REQUIRE_THROWS_WITH(v::Colonisation(open_mesh, ok), Contains("domain.volume") && Contains("not closed"));
  v::Domain doubled = d;  // a face twice: its three edges border three triangles each, an odd count
  doubled.mesh.triangles.push_back(doubled.mesh.triangles[0]);
  REQUIRE_THROWS_WITH(v::Colonisation(doubled, ok), Contains("not closed") && Contains("borders 3 triangle(s)"));
  v::Domain as_surface = open_mesh;  // an open mesh is a fine surface
  as_surface.kind = v::DomainKind::surface;
  as_surface.initial_nodes = {Vec3(2, 0, 0)};
  REQUIRE_NOTHROW(v::Colonisation(as_surface, ok));

  v::ColonisationParams dense = ok;  // more darts in one step than memory holds
  dense.darts_per_area = 1e9;
  REQUIRE_THROWS_WITH(v::Colonisation(d, dense), Contains("colonisation.darts") && Contains("2 x 10^7") &&
                                                     Contains("per unit volume"));  // a volume's darts
  REQUIRE_THROWS_WITH(v::Colonisation(as_surface, dense), Contains("per unit area"));

  v::Domain outside = d;
  outside.initial_nodes.push_back(Vec3(1.5, 1.5, 0));  // |x| + |y| = 3 > 2
  REQUIRE_THROWS_AS(v::Colonisation(outside, ok), core::InvalidInput);
  REQUIRE_THROWS_WITH(v::Colonisation(outside, ok), Contains("domain.initial_nodes[2]"));
  // the tolerance is relative (1e-6 of the domain's diagonal, 6.9e-6 here): 1e-4 off is outside, 1e-7 not; in
  // the same octahedron 1000 times larger, 5e-3 off is not
  outside.initial_nodes.back() = Vec3(2 + 1e-4, 0, 0);
  REQUIRE_THROWS_WITH(v::Colonisation(outside, ok), Contains("domain.initial_nodes[2]"));
  outside.initial_nodes.back() = Vec3(2 + 1e-7, 0, 0);
  REQUIRE_NOTHROW(v::Colonisation(outside, ok));
  v::Domain large = d;
  large.mesh = octahedron(2000);
  large.initial_nodes = {Vec3::Zero(), Vec3(2000 + 5e-3, 0, 0)};
  v::ColonisationParams large_params = ok;
  large_params.node_distance = large_params.kill_distance = 100;
  large_params.source_birth_distance = large_params.vein_birth_distance = 200;
  large_params.darts_per_area = 1e-9;
  REQUIRE_NOTHROW(v::Colonisation(large, large_params));
  v::Domain off_surface = as_surface;
  off_surface.initial_nodes = {Vec3(0.5, 0, 0)};  // inside, not on the surface
  REQUIRE_THROWS_WITH(v::Colonisation(off_surface, ok), Contains("domain.initial_nodes[1]") && Contains("surface"));
  v::Domain source_out = d;
  source_out.initial_sources = {Vec3(0, 0, 3)};
  REQUIRE_THROWS_WITH(v::Colonisation(source_out, ok), Contains("domain.initial_sources[1]"));
  v::Domain twice = d;  // seeds on one point cannot grow apart: refused, naming the later one
  twice.initial_nodes = {Vec3(0.5, 0, 0), Vec3::Zero(), Vec3(0, 0.5, 0), Vec3::Zero(), Vec3(0.5, 0, 0)};
  REQUIRE_THROWS_WITH(v::Colonisation(twice, ok),
                      Contains("domain.initial_nodes[4] {0, 0, 0} repeats domain.initial_nodes[2]"));
  twice.initial_nodes[3] = Vec3(0, 0, 1e-12);  // near is fine
  REQUIRE_THROWS_WITH(v::Colonisation(twice, ok),
                      Contains("domain.initial_nodes[5]") && Contains("repeats") && Contains("initial_nodes[1]"));
  v::ColonisationParams open = ok;  // an open pattern grows from the first and leaves the other alone
  open.type = v::VenationType::open;
  REQUIRE_NOTHROW(v::Colonisation(twice, open));
  twice.initial_nodes.pop_back();
  REQUIRE_NOTHROW(v::Colonisation(twice, ok));
  // the earliest repeat of any group, with a group of three: (1, 2), not (0, 3) or (2, 4)
  const std::vector<Vec3> three = {Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  const auto r = v::first_repeat(three);
  REQUIRE(r.has_value());
  CHECK(*r == std::pair<std::size_t, std::size_t>{1, 2});
  CHECK_FALSE(v::first_repeat(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(0, 0, 1e-300)}).has_value());
  v::Domain no_seed = d;
  no_seed.initial_nodes.clear();
  REQUIRE_THROWS_WITH(v::Colonisation(no_seed, ok), Contains("domain.initial_nodes"));

  v::Domain empty = d;
  empty.kind = v::DomainKind::surface;
  empty.mesh = {};
  REQUIRE_THROWS_WITH(v::Colonisation(empty, ok), Contains("domain.surface") && Contains("no triangles"));
  v::Domain bad_index = d;
  bad_index.mesh.triangles[0][1] = 99;
  REQUIRE_THROWS_WITH(v::Colonisation(bad_index, ok), Contains("domain.volume") && Contains("vertex 99"));
  v::Domain box;
  box.kind = v::DomainKind::box;
  box.box_min = Vec3(0, 0, 0);
  box.box_max = Vec3(1, 0, 1);
  box.initial_nodes = {Vec3::Zero()};
  REQUIRE_THROWS_WITH(v::Colonisation(box, ok), Contains("domain.box"));
  v::Domain ball;
  ball.kind = v::DomainKind::ball;
  ball.radius = 0;
  ball.initial_nodes = {Vec3::Zero()};
  REQUIRE_THROWS_WITH(v::Colonisation(ball, ok), Contains("domain.ball"));

  v::ColonisationParams urq = ok;
  urq.neighbourhood = v::Neighbourhood::urquhart;
  REQUIRE_THROWS_WITH(v::Colonisation(d, urq), Contains("colonisation.neighbourhood") && Contains("exact"));
  urq.type = v::VenationType::open;  // open patterns never use the neighbourhood
  REQUIRE_NOTHROW(v::Colonisation(d, urq));
  v::ColonisationParams grow = ok;
  grow.growth = v::GrowthMode::marginal;
  grow.final_scale = 2;
  grow.scale_step = 0.1;
  REQUIRE_THROWS_WITH(v::Colonisation(d, grow), Contains("colonisation.growth"));
  v::ColonisationParams scaled = ok;
  scaled.initial_scale = 2;
  REQUIRE_THROWS_WITH(v::Colonisation(d, scaled), Contains("colonisation.initial_scale"));

  // the leaf kind is the planar algorithm, validated as before
  v::Domain leaf;
  leaf.leaf.outline.points = {{-1, 0}, {1, 0}, {0, 2}};
  leaf.leaf.initial_nodes = {{5, 5}};
  REQUIRE_THROWS_WITH(v::Colonisation(leaf, ok), Contains("leaf.initial_nodes[1]"));
}
