// Tests of forms/attractors.h against closed-form accelerations.
#include "forms/attractors.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/errors.h"

using namespace cellform;
using cells::Cells;
using core::Vec3;
using forms::Attractor;

TEST_CASE("an attractor pulls with its strength, straight at itself", "[forms][attractors]") {
  Cells cells;
  cells::add_cell(cells, Vec3(3, 4, 0));   // 5 from the origin
  cells::add_cell(cells, Vec3(0, 0, -2));  // 2 from the origin
  cells::add_cell(cells, Vec3(1, 1, 1));
  cells.acceleration[2] = Vec3(0.5, 0, 0);  // pre-existing acceleration is added to, not replaced
  forms::apply_attractors(cells, {Attractor{Vec3::Zero(), 2.0, 0.0}});
  CHECK(cells.acceleration[0].isApprox(Vec3(-1.2, -1.6, 0), 1e-15));
  CHECK(cells.acceleration[1] == Vec3(0, 0, 4.0 / 2.0));
  CHECK(cells.acceleration[0].norm() == Approx(2.0).epsilon(1e-15));
  const Vec3 expected = Vec3(0.5, 0, 0) - 2.0 * Vec3(1, 1, 1).normalized();
  CHECK((cells.acceleration[2] - expected).norm() < 1e-15);
}

TEST_CASE("attractor range, repulsion, sums, dead zone and fixed cells", "[forms][attractors]") {
  Cells cells;
  cells::add_cell(cells, Vec3(1, 0, 0));
  cells::add_cell(cells, Vec3(3, 0, 0));
  cells::add_cell(cells, Vec3(0, 0, 0));                                  // exactly on the attractor: no NaN, no pull
  cells::add_cell(cells, Vec3(2, 0, 0), cells::CellType::general, true);  // fixed
  const std::vector<Attractor> attractors = {
      {Vec3::Zero(), 1.0, 2.0},    // reaches cells within distance 2 (boundary included)
      {Vec3(0, 5, 0), -0.5, 0.0},  // repels, unlimited range
  };
  forms::apply_attractors(cells, attractors);
  const auto away = [](const Vec3& p) -> Vec3 { return 0.5 * (p - Vec3(0, 5, 0)).normalized(); };
  CHECK((cells.acceleration[0] - (Vec3(-1, 0, 0) + away(Vec3(1, 0, 0)))).norm() < 1e-15);
  CHECK((cells.acceleration[1] - away(Vec3(3, 0, 0))).norm() < 1e-15);  // out of range of the first
  CHECK((cells.acceleration[2] - away(Vec3(0, 0, 0))).norm() < 1e-15);
  CHECK(cells.acceleration[2].allFinite());
  CHECK(cells.acceleration[3] == Vec3::Zero());

  Cells edge;
  cells::add_cell(edge, Vec3(0, 2, 0));
  forms::apply_attractors(edge, {attractors[0]});
  CHECK(edge.acceleration[0] == Vec3(0, -1, 0));
}

TEST_CASE("attractor validation", "[forms][attractors]") {
  CHECK_NOTHROW(forms::validate(std::vector<Attractor>{{}}));
  CHECK_THROWS_AS(forms::validate(std::vector<Attractor>{{Vec3::Zero(), std::nan(""), 0}}), core::InvalidInput);
  CHECK_THROWS_WITH(forms::validate(std::vector<Attractor>{{}, {Vec3(0, INFINITY, 0), 1, 0}}),
                    Catch::Contains("attractor 1"));
}
