// Tests of forms/shapes.h: lattice counts and spacing, and shapes too large to build refused clearly.
#include "forms/shapes.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/errors.h"

using namespace cellform;
using core::Vec3;

namespace {

const Vec3 kO = Vec3::Zero();
const Vec3 kZ = Vec3::UnitZ();

}  // namespace

TEST_CASE("shapes place cells spacing apart on the shape", "[forms][shapes]") {
  const std::vector<Vec3> disc = forms::hex_disc(kO, kZ, 5.0, 1.0);
  // a hexagonal lattice covers sqrt(3)/2 spacing^2 per cell
  CHECK(static_cast<double>(disc.size()) == Approx(std::numbers::pi * 25 / (std::sqrt(3.0) / 2)).epsilon(0.1));
  for (const Vec3& p : disc) CHECK(p.norm() <= 5.0 + 1e-9);
  CHECK(forms::hex_rectangle(kO, kZ, 4.0, 0.5, 1.0).size() == 5);  // one row, x = -2 ... 2
  const std::vector<Vec3> sphere = forms::sphere_points(kO, 3.0, 1.0);
  for (const Vec3& p : sphere) CHECK(p.norm() == Approx(3.0));
  CHECK(forms::line_points(kO, Vec3(3, 0, 0), 1.0).size() == 4);
  CHECK(forms::line_points(kO, kO, 1.0).size() == 1);
}

TEST_CASE("shapes lie where their centre and normal put them, evenly spaced", "[forms][shapes]") {
  const Vec3 c(3, -2, 5), n = Vec3(1, 2, 2) / 3;  // a tilted plane away from the origin
  const std::vector<Vec3> disc = forms::hex_disc(c, n, 4.0, 0.5);
  REQUIRE(disc.size() > 200);
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : disc) {
    CHECK(std::abs((p - c).dot(n)) < 1e-12);  // in the plane of the normal through the centre
    CHECK((p - c).norm() <= 4.0 + 1e-9);
    mean += p / static_cast<double>(disc.size());
  }
  CHECK((mean - c).norm() < 0.05);  // the lattice is symmetric about its centre
  // brute force: every cell's nearest other cell is one spacing away, in the plane
  for (std::size_t i = 0; i < disc.size(); ++i) {
    double nearest = INFINITY;
    for (std::size_t j = 0; j < disc.size(); ++j)
      if (j != i) nearest = std::min(nearest, (disc[i] - disc[j]).norm());
    CHECK(nearest == Approx(0.5));
  }
  // a sphere about its centre: every cell on it, their mean at the centre (the spiral's heights are symmetric
  // about the equator), and cells about one spacing from their nearest
  const std::vector<Vec3> sphere = forms::sphere_points(c, 3.0, 0.5);
  REQUIRE(sphere.size() > 300);
  mean = Vec3::Zero();
  for (const Vec3& p : sphere) {
    CHECK((p - c).norm() == Approx(3.0));
    mean += p / static_cast<double>(sphere.size());
  }
  CHECK(std::abs(mean.z() - c.z()) < 1e-9);
  CHECK((mean - c).norm() < 0.01);
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    double nearest = INFINITY;
    for (std::size_t j = 0; j < sphere.size(); ++j)
      if (j != i) nearest = std::min(nearest, (sphere[i] - sphere[j]).norm());
    CHECK(nearest > 0.3);
    CHECK(nearest < 0.7);
  }
}

TEST_CASE("shapes too large to build are refused with the cell limit, never built wrong", "[forms][shapes]") {
  using Catch::Contains;
  const double big_int = static_cast<double>(std::numeric_limits<long long>::max());  // Lua's math.maxinteger
  // Each would overflow a long if its cell count were cast before the limit is checked.
  for (const double radius : {1e18, big_int, 1e300, 1e308}) {
    INFO("disc radius " << radius);
    CHECK_THROWS_AS(forms::hex_disc(kO, kZ, radius, 1.0), core::InvalidInput);
    CHECK_THROWS_WITH(forms::hex_disc(kO, kZ, radius, 1.0),
                      Contains("more than 50 million") && Contains("radius") && !Contains("-"));
    INFO("sphere radius " << radius);
    CHECK_THROWS_AS(forms::sphere_points(kO, radius, 1.0), core::InvalidInput);
    CHECK_THROWS_WITH(forms::sphere_points(kO, radius, 1.0),
                      Contains("more than 50 million") && Contains("radius") && !Contains("-"));
  }
  CHECK_THROWS_WITH(forms::hex_disc(kO, kZ, 1.0, 1e-300), Contains("more than 50 million") && Contains("spacing"));
  CHECK_THROWS_WITH(forms::sphere_points(kO, 1.0, 1e-300), Contains("more than 50 million") && Contains("spacing"));
  CHECK_THROWS_WITH(forms::hex_rectangle(kO, kZ, 2.0, 3.0, 1e-300),
                    Contains("more than 50 million") && Contains("spacing"));
  CHECK_THROWS_WITH(forms::hex_rectangle(kO, kZ, 1e300, 0.1, 1.0), Contains("more than 50 million"));
  CHECK_THROWS_WITH(forms::line_points(kO, Vec3(1, 0, 0), 1e-300),
                    Contains("more than 50 million") && Contains("spacing"));
  CHECK_THROWS_WITH(forms::line_points(Vec3(-1e300, 0, 0), Vec3(1e300, 0, 0), 1.0), Contains("more than 50 million"));
  // just under the limit in one dimension still builds
  CHECK(forms::line_points(kO, Vec3(1e6, 0, 0), 1.0).size() == 1'000'001);
}

TEST_CASE("a disc too large to build names its own cell count, not its bounding square's", "[forms][shapes]") {
  using Catch::Contains;
  // at spacing 1 a disc of radius R holds about pi R^2 / (sqrt(3) / 2) cells; the square around it
  // 4 / pi times as many. Radius 5000: 90.7 million (the square would say 115 million).
  const double count = std::numbers::pi * 5000.0 * 5000.0 / (std::sqrt(3.0) / 2);
  std::string message;
  try {
    forms::hex_disc(kO, kZ, 5000.0, 1.0);
  } catch (const core::InvalidInput& e) {
    message = e.what();
  }
  INFO(message);
  const auto at = message.find("about ");
  REQUIRE(at != std::string::npos);
  const double said = std::stod(message.substr(at + 6));
  CHECK(said == Approx(count).epsilon(0.01));
  // and the estimate is the count a smaller disc really gets, within the boundary's cells
  for (const double radius : {20.0, 60.0}) {
    const double n = static_cast<double>(forms::hex_disc(kO, kZ, radius, 1.0).size());
    CHECK(n == Approx(std::numbers::pi * radius * radius / (std::sqrt(3.0) / 2)).epsilon(2.5 / radius));
  }
}

TEST_CASE("the cell counts found without building a shape agree with the shapes built", "[forms][shapes]") {
  // a caller refuses shapes beyond its own limit from these before building them
  for (const double spacing : {0.3, 1.0, 1.7})
    for (const double w : {0.2, 0.9, 1.0, 1.5, 2.0, 3.3, 10.0, 41.0})
      for (const double h : {0.1, 1.0, 2.6, 7.0, 30.0}) {
        CAPTURE(spacing, w, h);
        CHECK(forms::hex_rectangle_cells(w, h, spacing) ==
              static_cast<double>(forms::hex_rectangle(kO, kZ, w, h, spacing).size()));
      }
  for (const double r : {0.5, 1.0, 2.5, 7.0, 20.0}) {
    CAPTURE(r);
    CHECK(forms::sphere_cells(r, 0.7) == static_cast<double>(forms::sphere_points(kO, r, 0.7).size()));
    CHECK(forms::line_cells(kO, Vec3(r, r, 0), 0.7) ==
          static_cast<double>(forms::line_points(kO, Vec3(r, r, 0), 0.7).size()));
    // a disc's count is its area over a lattice cell's: off by at most about its rim
    const double disc = static_cast<double>(forms::hex_disc(kO, kZ, r, 0.7).size());
    CHECK(std::abs(forms::hex_disc_cells(r, 0.7) - disc) <= 2 * std::numbers::pi * r / 0.7 + 2);
  }
}
