// Tests of export/stand.h against closed forms: a box, a leaning block, a cube on one edge (its footprint, its
// centre of mass, the tilt that tips it, and the lowest cut that makes it stand).
#include "export/stand.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <vector>

#include "core/polygon.h"
#include "export/mesh_check.h"

using namespace cellform;
using core::Vec3;
using exporters::PrintableMesh;

namespace {

constexpr double kDeg = 180 / M_PI;

// The unit cube's corners (corner i at (i & 1, i & 2, i & 4)) mapped by `at` (orientation kept), wound outward.
PrintableMesh hexahedron(const std::function<Vec3(const Vec3&)>& at) {
  PrintableMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(at(Vec3(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0)));
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

// A cube of side a turned by theta about the y axis, standing on its edge along y through the origin.
PrintableMesh cube_on_edge(double a, double theta) {
  return hexahedron([&](const Vec3& p) {
    return Vec3(a * (p.x() * std::cos(theta) - p.z() * std::sin(theta)), a * p.y(),
                a * (p.x() * std::sin(theta) + p.z() * std::cos(theta)));
  });
}

// That cube's tip angle (degrees) above a cut at height z below its lower corners (z <= a min(sin, cos)): the
// triangle under the cut, with corners (0, 0), (-z tan, z), (z cot, z) in xz, is taken off the square.
double cube_tip_above(double a, double theta, double z) {
  const double t = std::tan(theta), cot = 1 / t;
  const double square = a * a, cx = a * (std::cos(theta) - std::sin(theta)) / 2,
               cz = a * (std::sin(theta) + std::cos(theta)) / 2;
  const double cut = z * z * (t + cot) / 2, tx = z * (cot - t) / 3, tz = 2 * z / 3;
  const double gx = (square * cx - cut * tx) / (square - cut), gz = (square * cz - cut * tz) / (square - cut);
  const double margin = std::min({z * cot - gx, gx + z * t, a / 2});
  return std::atan2(margin, gz - z) * kDeg;
}

// The polygon `xz` (counter-clockwise in x, z) drawn out `depth` along y, wound outward.
PrintableMesh prism(const std::vector<std::array<double, 2>>& xz, double depth) {
  PrintableMesh m;
  const auto n = static_cast<std::uint32_t>(xz.size());
  for (const double y : {0.0, depth})
    for (const auto& p : xz) m.vertices.emplace_back(p[0], y, p[1]);
  const std::vector<Vec3> front(m.vertices.begin(), m.vertices.begin() + n);
  for (const auto& t : core::triangulate_polygon(front)) {  // counter-clockwise in x, z faces -y
    m.triangles.push_back(t);
    m.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({i, i + n, j + n});
    m.triangles.push_back({i, j + n, j});
  }
  return m;
}

}  // namespace

TEST_CASE("a box stands on its base: the base is the footprint, the centre its middle", "[stand]") {
  const PrintableMesh box =
      hexahedron([](const Vec3& p) { return Vec3(2 + 30 * p.x(), -5 + 10 * p.y(), 1 + 40 * p.z()); });
  const exporters::Stand s = exporters::stand_on_bed(box);
  REQUIRE(s.measured);
  CHECK(s.bed_z == 1);
  CHECK(s.footprint_area == Approx(300));
  CHECK(s.centre_of_mass.x() == Approx(17));
  CHECK(s.centre_of_mass.y() == Approx(0).margin(1e-12));
  CHECK(s.centre_of_mass.z() == Approx(21));
  CHECK(s.margin == Approx(5));  // to the nearer long side
  CHECK(s.tip_angle == Approx(std::atan2(5.0, 20.0) * kDeg));
  CHECK(s.settle_angle == Approx(90 - s.tip_angle).margin(1e-6));  // tipped past that, it rolls onto its side
  CHECK_FALSE(exporters::falls(s));                                // but stands firm
  // what is left above a cut at z tips at atan(5 / ((40 - z) / 2)): past 10 degrees from the first cut (z = 0.4,
  // a fiftieth of half the height), past 15 degrees from z = 2.68, the seventh
  CHECK(exporters::base_cut_to_stand(box, 10) == Approx(0.4));
  CHECK(exporters::base_cut_to_stand(box, 15) == Approx(2.8));
  CHECK(exporters::base_cut_to_stand(box, 27) == 0);  // 26.6 degrees at half its height, the highest cut tried
}

TEST_CASE("a leaning block stands while its centre of mass is over its footprint", "[stand]") {
  // base 10 x 10 on the bed, its top moved `lean` along x at height 10; the first layer's sides lean out too
  for (const double lean : {4.0, 14.0, -14.0}) {
    CAPTURE(lean);
    const PrintableMesh block =
        hexahedron([&](const Vec3& p) { return Vec3(10 * p.x() + lean * p.z(), 10 * p.y(), 10 * p.z()); });
    const exporters::Stand s = exporters::stand_on_bed(block, 0.2);
    REQUIRE(s.measured);
    const double g = 5 + lean / 2;
    CHECK(s.centre_of_mass.x() == Approx(g));
    CHECK(s.centre_of_mass.z() == Approx(5));
    const double lo = std::min(0.0, lean * 0.02), hi = 10 + std::max(0.0, lean * 0.02);  // the first layer's plan
    CHECK(s.footprint_area == Approx((hi - lo) * 10));
    const double margin =
        g >= lo && g <= hi ? std::min({g - lo, hi - g, 5.0}) : -std::min(std::abs(g - lo), std::abs(g - hi));
    CHECK(s.margin == Approx(margin));
    CHECK((s.margin > 0) == (std::abs(lean) < 10));
    CHECK(s.tip_angle == Approx(std::atan2(margin, 5.0) * kDeg));
    // leaning over, it turns about its base's far edge until its top corners, |lean| beyond it and 10 up, meet
    // the bed, and lies on its side (the turns go by the corners within the first layer)
    if (std::abs(lean) > 10) CHECK(s.settle_angle == Approx(std::atan2(10, std::abs(lean)) * kDeg));
    CHECK(exporters::falls(s) == (std::abs(lean) > 10));
  }
}

TEST_CASE("a cube on one edge does not stand, and the lowest cut that makes it is found", "[stand]") {
  const double a = 10, theta = M_PI / 6, layer = 0.2;
  const PrintableMesh cube = cube_on_edge(a, theta);
  const exporters::Stand s = exporters::stand_on_bed(cube, layer);
  REQUIRE(s.measured);
  const double t = std::tan(theta);
  CHECK(s.bed_z == Approx(0).margin(1e-12));
  CHECK(s.footprint_area == Approx(a * layer * (t + 1 / t)));  // a strip along the edge
  CHECK(s.centre_of_mass.x() == Approx(a * (std::cos(theta) - std::sin(theta)) / 2));
  CHECK(s.centre_of_mass.z() == Approx(a * (std::sin(theta) + std::cos(theta)) / 2));
  CHECK(s.margin == Approx(layer / t - s.centre_of_mass.x()));
  CHECK(s.margin < 0);
  CHECK(s.tip_angle == Approx(std::atan2(s.margin, s.centre_of_mass.z()) * kDeg));
  // it turns about the edge it stands on until its next lower corner meets the bed: 30 degrees, onto a face
  CHECK(s.settle_angle == Approx(30));
  CHECK(exporters::falls(s));

  // cuts at k / 50 of 0.35 of the height, all below the lower corners, where the analytic tip angle holds
  const double height = a * (std::sin(theta) + std::cos(theta)), step = 0.35 * height / 50;
  for (const double wanted : {5.0, 10.0, 20.0}) {
    CAPTURE(wanted);
    const double cut = exporters::base_cut_to_stand(cube, wanted, 0.35, 50, 2);
    REQUIRE(cut > step);
    CHECK(cut == exporters::base_cut_to_stand(cube, wanted, 0.35, 50, 1));  // any thread count
    const int k = static_cast<int>(std::lround(cut / step));
    CHECK(cut == Approx(k * step));
    CHECK(cube_tip_above(a, theta, cut) >= wanted - 1e-9);
    CHECK(cube_tip_above(a, theta, (k - 1) * step) < wanted);  // the lowest such cut
  }
  CHECK(exporters::base_cut_to_stand(cube, 60, 0.35, 50) == 0);  // no cut up to 0.35 of it tips only past 60
}

TEST_CASE("a cut that would part the solid into pieces does not count", "[stand]") {
  // a narrow V 40 high on its point, legs 10 degrees off the vertical and 2 wide across, their crotch at
  // z = 40 - 5.05 / tan 10 = 11.4: just below it the section is 4 wide against a centre of mass some 15 above,
  // 7 degrees; a cut above it would stand on both legs, but leaves two pieces
  const double t = std::tan(10 / kDeg), top = 40 * t, crotch = 40 - (top - 2) / t;
  const PrintableMesh v = prism({{0, 0}, {top, 40}, {top - 2, 40}, {0, crotch}, {2 - top, 40}, {-top, 40}}, 20);
  const exporters::MeshReport r = exporters::check_mesh(v);
  REQUIRE(r.printable());
  REQUIRE(r.parts == 1);
  const exporters::Stand s = exporters::stand_on_bed(v);
  CHECK(s.margin == Approx(exporters::kFirstLayer * t));  // over its point
  CHECK(s.tip_angle < 1);
  const double cut = exporters::base_cut_to_stand(v, 5);  // below the crotch: one piece
  CHECK(cut > 0);
  CHECK(cut < crotch);
  CHECK(exporters::base_cut_to_stand(v, 10) == 0);  // only above it, in two
  // as much with a sealed pocket in a leg above the crotch (its surface reaches above the cut, but is no piece
  // of the whole), or a vertex no triangle uses
  PrintableMesh pocket = v;
  const PrintableMesh hole = hexahedron([](const Vec3& p) { return Vec3(1.2 + 0.6 * p.x(), 5 + p.y(), 15 + p.z()); });
  for (const auto& f : hole.triangles)
    pocket.triangles.push_back({f[0] + 12, f[2] + 12, f[1] + 12});  // wound into the pocket
  pocket.vertices.insert(pocket.vertices.end(), hole.vertices.begin(), hole.vertices.end());
  REQUIRE(exporters::check_mesh(pocket).cavities == 1);
  CHECK(exporters::base_cut_to_stand(pocket, 10) == 0);
  PrintableMesh stray = v;
  stray.vertices.emplace_back(0, 10, 1);
  CHECK(exporters::base_cut_to_stand(stray, 10) == 0);
}

TEST_CASE("a cut through a shell open downwards leaves one piece", "[stand]") {
  // a cup upside down: a box 10 wide and high, hollow 8 wide and 9 high from its open bottom; above a cut its
  // outer and inner faces join only through the cut's cap, and the inner one encloses a negative volume
  PrintableMesh cup;
  for (const double w : {0.0, 1.0})
    for (int i = 0; i < 8; ++i) cup.vertices.emplace_back(i & 1 ? 10 - w : w, i & 2 ? 10 - w : w, i & 4 ? 10 - w : 0);
  const std::uint32_t sides[5][4] = {{4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : sides) {
    cup.triangles.push_back({q[0], q[1], q[2]});
    cup.triangles.push_back({q[0], q[2], q[3]});
    cup.triangles.push_back({q[0] + 8, q[2] + 8, q[1] + 8});  // the hollow's faces look into it
    cup.triangles.push_back({q[0] + 8, q[3] + 8, q[2] + 8});
  }
  const std::uint32_t rim[5] = {0, 2, 3, 1, 0};  // the bottom square, facing down
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t a = rim[k], b = rim[k + 1];
    cup.triangles.push_back({a, b, b + 8});
    cup.triangles.push_back({a, b + 8, a + 8});
  }
  const exporters::MeshReport r = exporters::check_mesh(cup);
  REQUIRE(r.printable());
  REQUIRE(r.pieces == 1);
  CHECK(exporters::base_cut_to_stand(cup, 1) == Approx(0.1));  // the first cut tried, a fiftieth of half of 10
}

TEST_CASE("a flat plate lying a degree off the bed rocks onto its underside rather than falling", "[stand]") {
  // 40 x 40 x 2, turned 1 degree about y: it touches along an edge, its centre 20 mm off, and lies flat after a
  // turn of one degree about its low edge, onto its face
  const double turn = 1 / kDeg;
  const PrintableMesh plate = hexahedron([&](const Vec3& p) {
    const Vec3 q(40 * p.x(), 40 * p.y(), 2 * p.z());
    return Vec3(q.x() * std::cos(turn) - q.z() * std::sin(turn), q.y(),
                q.x() * std::sin(turn) + q.z() * std::cos(turn));
  });
  const exporters::Stand s = exporters::stand_on_bed(plate);
  REQUIRE(s.measured);
  CHECK(s.margin < 0);
  CHECK(s.settle_angle == Approx(1));
  CHECK_FALSE(exporters::falls(s));
}

TEST_CASE("a surface that bounds no solid is not measured", "[stand]") {
  PrintableMesh sheet;
  sheet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  sheet.triangles = {{0, 1, 2}};
  CHECK_FALSE(exporters::stand_on_bed(sheet).measured);
  CHECK_FALSE(exporters::stand_on_bed(PrintableMesh{}).measured);
  PrintableMesh inward = hexahedron([](const Vec3& p) { return p; });
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  CHECK_FALSE(exporters::stand_on_bed(inward).measured);
  CHECK(exporters::base_cut_to_stand(inward, 1) == 0);
}
