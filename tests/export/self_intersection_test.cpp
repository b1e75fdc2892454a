// Tests of export/self_intersection.cpp: the grid search finds exactly the pairs a test of every pair finds,
// and a counting search stays within bounded memory and time.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "export/mesh_check.h"
#include "tests/export/mesh_fixtures.h"

using namespace cellform;
using namespace cellform::testing;

TEST_CASE("check_mesh finds no false intersections on a 500k-triangle sphere, on any thread count", "[mesh_check]") {
  const auto m = uv_sphere(500, 500);
  REQUIRE(m.triangles.size() > 490000);
  const auto r1 = exporters::check_mesh(m, 1);
  CHECK(r1.printable());
  const auto r2 = exporters::check_mesh(m, 2);
  CHECK(r2.self_intersections == r1.self_intersections);
  CHECK(r2.nonmanifold_vertices == r1.nonmanifold_vertices);
}

TEST_CASE("self_intersecting_pairs equals testing every pair, with fans round one vertex, slivers, far outliers",
          "[mesh_check]") {
  // a soup the grid finds hard: small random triangles, a fan of 400 slivers round one vertex (all in the
  // cells around it), a few long triangles reaching a vertex 1000 away (their extent made the grid one
  // cell), and loose slivers
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  PrintableMesh m;
  auto vertex = [&](const Vec3& p) {
    m.vertices.push_back(p);
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  };
  for (int t = 0; t < 500; ++t) {
    const Vec3 c(u(rng), u(rng), u(rng));
    std::array<std::uint32_t, 3> tri{};
    for (auto& k : tri) k = vertex(c + 0.12 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    m.triangles.push_back(tri);
  }
  const std::uint32_t hub = vertex(Vec3(0.5, 0.5, 0.5));
  for (int t = 0; t < 400; ++t) {
    const double a = 2 * M_PI * t / 400, z = 0.4 * (u(rng) - 0.5);
    const Vec3 rim(0.5 + 0.45 * std::cos(a), 0.5 + 0.45 * std::sin(a), 0.5 + z);
    m.triangles.push_back({hub, vertex(rim), vertex(rim + Vec3(0.01, 0.0, 0.02))});
  }
  for (int t = 0; t < 3; ++t)
    m.triangles.push_back(
        {vertex(Vec3(u(rng), u(rng), 0.5)), vertex(Vec3(u(rng), u(rng), 0.6)), vertex(Vec3(0, 0, 1e3))});
  // loose slivers 0.8 long and 0.004 wide in every direction: held only in the cells they cross, they meet
  // each other and the small triangles held in their whole boxes
  for (int t = 0; t < 150; ++t) {
    const Vec3 a(u(rng), u(rng), u(rng)), d = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    const Vec3 side = d.cross(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)).normalized();
    m.triangles.push_back({vertex(a), vertex(a + 0.8 * d), vertex(a + 0.8 * d + 0.004 * side)});
  }
  const auto found = exporters::self_intersecting_pairs(m, 2);
  const auto all = every_pair(m);  // no grid to miss one
  REQUIRE(all.size() > 100);       // the fan and the outliers cross many others
  std::vector<std::array<std::uint32_t, 2>> missed, extra;
  std::set_difference(all.begin(), all.end(), found.begin(), found.end(), std::back_inserter(missed));
  std::set_difference(found.begin(), found.end(), all.begin(), all.end(), std::back_inserter(extra));
  CHECK(missed.empty());
  CHECK(extra.empty());
  if (!missed.empty()) WARN("missed " << missed.size() << ", first " << missed[0][0] << " " << missed[0][1]);
  if (!extra.empty()) WARN("extra " << extra.size() << ", first " << extra[0][0] << " " << extra[0][1]);
  CHECK(exporters::self_intersecting_pairs(m, 1) == found);
}

TEST_CASE("check_mesh counts millions of crossings in little memory, and does not test a stack for hours",
          "[mesh_check]") {
  // N triangles through the z axis at N angles: every pair crosses (N (N - 1) / 2 pairs)
  auto fan = [](std::uint32_t n) {
    PrintableMesh m;
    for (std::uint32_t k = 0; k < n; ++k) {
      const double a = M_PI * k / n;
      m.vertices.emplace_back(std::cos(a), std::sin(a), 0);
      m.vertices.emplace_back(-std::cos(a), -std::sin(a), 0);
      m.vertices.emplace_back(0, 0, 1 + 1e-3 * k);
      m.triangles.push_back({3 * k, 3 * k + 1, 3 * k + 2});
    }
    return m;
  };
  const PrintableMesh small = fan(300);
  const auto oracle = every_pair(small);
  REQUIRE(oracle.size() == 300 * 299 / 2);
  const auto counted = exporters::count_self_intersections(small.vertices, small.triangles, 16, 1e12);
  CHECK(counted.tested);
  CHECK(counted.count == oracle.size());
  CHECK(counted.examples == std::vector<std::array<std::uint32_t, 2>>(oracle.begin(), oracle.begin() + 16));
  const auto r = exporters::check_mesh(fan(4000));  // 8 million pairs: their list alone took 64 MB
  CHECK(r.self_intersections == 4000u * 3999u / 2);
  CHECK(r.intersecting_pairs.size() == 16);
  // 60,000 triangles stacked 1e-6 apart: the grid cannot part them (1.8e9 candidate pairs): refused untested
  PrintableMesh stack;
  for (std::uint32_t k = 0; k < 60000; ++k) {
    stack.vertices.emplace_back(0, 0, 1e-6 * k);
    stack.vertices.emplace_back(1, 0, 1e-6 * k);
    stack.vertices.emplace_back(0, 1, 1e-6 * k);
    stack.triangles.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  const auto s = exporters::check_mesh(stack);
  // 60,000 slivers round one apex (a fine cone) crowd one cell too, but their pairs share the apex: tested
  PrintableMesh cone;
  cone.vertices.emplace_back(0, 0, 1);
  for (std::uint32_t k = 0; k < 60000; ++k)
    cone.vertices.emplace_back(std::cos(2 * M_PI * k / 60000), std::sin(2 * M_PI * k / 60000), 0);
  for (std::uint32_t k = 0; k < 60000; ++k) cone.triangles.push_back({0, 1 + k, 1 + (k + 1) % 60000});
  const auto c = exporters::check_mesh(cone);
  CHECK(c.intersections_tested);
  CHECK(c.self_intersections == 0);
  CHECK_FALSE(s.intersections_tested);
  CHECK_FALSE(s.printable());
  CHECK_THAT(s.summary(),
             Catch::Contains("self-intersecting pairs not tested") &&
                 Catch::Contains("self-intersections not tested: too many triangles overlap in one place"));
}

TEST_CASE("self_intersecting_pairs equals testing every pair on soups of small triangles and loose slivers",
          "[mesh_check]") {
  // slivers are held only in the cells they cross, small triangles in every cell of their boxes: pairs of
  // each kind and of both are found once
  const auto seed = GENERATE(7, 8, 9);
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> u(0, 1);
  PrintableMesh m;
  auto vertex = [&](const Vec3& p) {
    m.vertices.push_back(p);
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
  };
  for (const double x0 : {0.0, 0.3}) {
    for (int t = 0; t < 250; ++t) {
      const Vec3 c(x0 + u(rng), u(rng), u(rng));
      std::array<std::uint32_t, 3> tri{};
      for (auto& k : tri) k = vertex(c + 0.1 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
      m.triangles.push_back(tri);
    }
    for (int t = 0; t < 120; ++t) {
      const Vec3 a(x0 + u(rng), u(rng), u(rng)), d = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
      const Vec3 side = d.cross(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)).normalized();
      m.triangles.push_back({vertex(a), vertex(a + (0.3 + 0.6 * u(rng)) * d), vertex(a + 0.5 * d + 0.003 * side)});
    }
  }
  const auto all = every_pair(m);
  REQUIRE(all.size() > 40);
  const auto found = exporters::self_intersecting_pairs(m, 2);
  CHECK(found == all);
  CHECK(exporters::self_intersecting_pairs(m, 1) == found);
}

TEST_CASE("triangles round a shared corner that cross beyond it are found, in small cells and in large fans",
          "[mesh_check]") {
  // a crease folded into itself: the second triangle passes through the first beyond their shared corner
  PrintableMesh pair;
  pair.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.2, -0.5}, {0.2, 0.5, 0.5}, {-1, 0.2, 0}, {-0.2, 1, 0}};
  pair.triangles = {{0, 1, 2}, {0, 3, 4}, {0, 6, 5}};  // the third lies beside the first, in its plane: no crossing
  CHECK(exporters::self_intersecting_pairs(pair) == std::vector<std::array<std::uint32_t, 2>>{{0, 1}});
  CHECK(exporters::check_mesh(pair).self_intersections == 1);
  // neighbours across a side are not tested, even folded flat onto each other
  PrintableMesh folded;
  folded.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 0.5, 0}};
  folded.triangles = {{0, 1, 2}, {1, 0, 3}};
  CHECK(exporters::self_intersecting_pairs(folded).empty());
  // soups over few vertices (many pairs share one), and fans of hundreds round one vertex in one grid cell
  // (tested through their sides' directions, not pair by pair): exactly the oracle's pairs
  const auto seed = GENERATE(1, 2, 3);
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> u(0, 1);
  PrintableMesh m;
  for (int k = 0; k < 150; ++k) m.vertices.emplace_back(u(rng), u(rng), u(rng));
  std::uniform_int_distribution<std::uint32_t> pick(0, 149);
  for (int t = 0; t < 400; ++t) {
    const std::uint32_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (a != b && b != c && a != c) m.triangles.push_back({a, b, c});
  }
  const std::uint32_t hub = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.emplace_back(0.5, 0.5, 0.5);
  for (int t = 0; t < 600; ++t) {  // short triangles round the hub, all in its cell, in random directions
    const Vec3 d = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    const Vec3 e = d.cross(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)).normalized();
    m.vertices.push_back(Vec3(0.5, 0.5, 0.5) + 0.01 * d);
    m.vertices.push_back(Vec3(0.5, 0.5, 0.5) + 0.01 * d + 0.004 * e);
    const auto n = static_cast<std::uint32_t>(m.vertices.size());
    m.triangles.push_back({hub, n - 2, n - 1});
  }
  const auto all = every_pair(m);
  std::size_t round_hub = 0, one_corner = 0;
  for (const auto& [i, j] : all) {
    int shared = 0;
    for (const auto a : m.triangles[i])
      for (const auto b : m.triangles[j]) shared += a == b;
    one_corner += shared == 1;
    round_hub += shared == 1 && m.triangles[i][0] == hub && m.triangles[j][0] == hub;
  }
  REQUIRE(one_corner - round_hub > 20);  // crossings round a corner of the soup
  REQUIRE(round_hub > 20);               // and within the fan
  const auto found = exporters::self_intersecting_pairs(m, 2);
  CHECK(found == all);
  CHECK(exporters::self_intersecting_pairs(m, 1) == found);
  const auto counted = exporters::count_self_intersections(m.vertices, m.triangles, 16, 1e12);
  CHECK(counted.count == all.size());
}

TEST_CASE("a large fan is swept along the axis its directions spread in, and a crowded one counts to the budget",
          "[mesh_check]") {
  // a flat disc fanned round its centre, in the plane x = 0: every direction has x = 0, so a sweep along x
  // would pair every triangle with every other (35 s for 100,000, review)
  const std::uint32_t n = 20000;
  PrintableMesh disc;
  disc.vertices.emplace_back(0, 0, 0);
  for (std::uint32_t k = 0; k < n; ++k)
    disc.vertices.emplace_back(0, std::cos(2 * M_PI * k / n), std::sin(2 * M_PI * k / n));
  for (std::uint32_t k = 0; k < n; ++k) disc.triangles.push_back({0, 1 + k, 1 + (k + 1) % n});
  const auto swept = exporters::count_self_intersections(disc.vertices, disc.triangles, 16, 1e6);
  CHECK(swept.tested);  // about n pairs looked at, not n^2 / 2
  CHECK(swept.count == 0);
  // the same fan folded onto itself (each triangle repeated, turned a little about the hub): every pair
  // overlaps in every axis; the sweep's steps count, so a counting search gives up instead of running on
  PrintableMesh crowded;
  crowded.vertices.emplace_back(0, 0, 0);
  for (std::uint32_t k = 0; k < 4000; ++k) {
    const double a = 1e-4 * k;
    crowded.vertices.emplace_back(1, std::cos(a), std::sin(a));
    crowded.vertices.emplace_back(1, std::cos(a + 0.5), std::sin(a + 0.5));
    crowded.triangles.push_back({0, 1 + 2 * k, 2 + 2 * k});
  }
  const auto given_up = exporters::count_self_intersections(crowded.vertices, crowded.triangles, 16, 1e5);
  CHECK_FALSE(given_up.tested);
}

TEST_CASE("a small triangle lying inside a face of a closed tetrahedron intersects it, listed before or after",
          "[mesh_check]") {
  // the tetrahedron's face {0, 2, 1} lies in z = 0; the loose triangle lies inside it, sharing no vertex, so
  // no edges cross: only a corner of one inside the other shows the overlap
  const std::vector<Vec3> small{Vec3(0.2, 0.2, 0), Vec3(0.6, 0.2, 0), Vec3(0.2, 0.6, 0)};
  PrintableMesh after = tetrahedron();
  after.vertices.insert(after.vertices.end(), small.begin(), small.end());
  after.triangles.push_back({4, 5, 6});
  CHECK(exporters::check_mesh(after).self_intersections == 1);  // the one face it lies in
  PrintableMesh before;  // the loose triangle first, the tetrahedron's faces after it
  before.vertices = small;
  before.triangles.push_back({0, 1, 2});
  append(before, tetrahedron());
  CHECK(exporters::check_mesh(before).self_intersections == 1);
}
