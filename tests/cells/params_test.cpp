// validate() names the offending parameter; stable_time_step accepts the defaults.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>

#include "cells/cells.h"
#include "cells/params.h"
#include "core/errors.h"

using namespace cellform::cells;

namespace {

void rejects(const std::function<void(Params&)>& change, const std::string& name) {
  Params p;
  change(p);
  try {
    validate(p);
    FAIL("accepted a bad " << name);
  } catch (const cellform::core::InvalidInput& e) {
    const std::string msg = e.what();
    INFO(msg);
    REQUIRE(msg.find(name) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("defaults and common settings are valid", "[params]") {
  Params p;
  REQUIRE_NOTHROW(validate(p));
  p.time_step = 0.5;
  REQUIRE_NOTHROW(validate(p));
  REQUIRE(stable_time_step(Params{}) > 0.5);
  p.integrator = Integrator::velocity;
  p.time_step = 0.1;
  REQUIRE_NOTHROW(validate(p));
  p.division.direction = SplitDirection::circumferential;
  REQUIRE_NOTHROW(validate(p));
}

TEST_CASE("validate rejects each bad parameter by name", "[params]") {
  rejects([](Params& p) { p.rest_length = 0; }, "cells.rest_length");
  rejects([](Params& p) { p.rest_length = -1; }, "cells.rest_length");
  rejects([](Params& p) { p.rest_length = INFINITY; }, "cells.rest_length");
  rejects([](Params& p) { p.rest_length = NAN; }, "cells.rest_length");
  rejects([](Params& p) { p.neighbours = 2; }, "cells.neighbours");
  rejects([](Params& p) { p.neighbours = 33; }, "cells.neighbours");
  rejects([](Params& p) { p.drag = Vec3(0.9, 1.1, 0.9); }, "cells.drag");
  rejects([](Params& p) { p.drag = Vec3(-0.1, 0.9, 0.9); }, "cells.drag");
  rejects([](Params& p) { p.time_step = 0; }, "cells.time_step");
  rejects([](Params& p) { p.time_step = -0.1; }, "cells.time_step");
  rejects([](Params& p) { p.time_step = 5; }, "cells.time_step");
  rejects(
      [](Params& p) {
        p.integrator = Integrator::velocity;
        p.time_step = 1.0;
      },
      "cells.time_step");
  rejects([](Params& p) { p.weights[2].spring = -1; }, "cells.vein.spring");
  rejects([](Params& p) { p.weights[0].planar = NAN; }, "cells.planar");
  rejects([](Params& p) { p.unary = Vec3(0, NAN, 0); }, "cells.unary");
  rejects([](Params& p) { p.vein_cohesion_factor = -1; }, "cells.vein_cohesion");
  rejects([](Params& p) { p.vein_separation_factor = NAN; }, "cells.vein_separation");
  rejects([](Params& p) { p.weights[1].separation = INFINITY; }, "cells.petiole.separation");
  rejects([](Params& p) { p.max_speed = 0; }, "cells.max_speed");
  rejects([](Params& p) { p.division.probability = 0; }, "cells.division.probability");
  rejects([](Params& p) { p.division.probability = 1.5; }, "cells.division.probability");
  rejects([](Params& p) { p.division.radius = 0; }, "cells.division.radius");
  rejects([](Params& p) { p.division.min_neighbours = 0; }, "cells.division.min_neighbours");
  rejects([](Params& p) { p.division.max_cells = 0; }, "cells.division.max_cells");
  rejects(
      [](Params& p) {
        p.division.direction = SplitDirection::axis;
        p.division.axis = Vec3::Zero();
      },
      "cells.division.axis");
  rejects(
      [](Params& p) {
        p.division.direction = SplitDirection::circumferential;
        p.division.axis = Vec3::Zero();
      },
      "cells.division.axis");
}

TEST_CASE("stable time step shrinks with stiffer weights", "[params]") {
  Params p;
  const double base = stable_time_step(p);
  p.weights[0].spring = 4;
  REQUIRE(stable_time_step(p) < base);
  p.integrator = Integrator::velocity;
  REQUIRE(stable_time_step(p) < base);
  Params none;
  for (auto& w : none.weights) w = ForceWeights{0, 0, 0, 0};
  REQUIRE(std::isinf(stable_time_step(none)));
}

TEST_CASE("without canalisation the vein cells' weights do not bound the time step", "[params]") {
  // a sheet in millimetres (rest length 0.001): the vein type's cohesion 0.05 bounds the step to
  // 2 / sqrt(2 * 0.05 / 1e-6) = 0.0063 when veins can grow, and nothing when they cannot
  Params p;
  p.rest_length = 0.001;
  for (auto& w : p.weights) w = ForceWeights{1, 0.5, 0, 0};
  p.weights[static_cast<int>(CellType::vein)].cohesion = 0.05;
  p.vein_cohesion_factor = p.vein_separation_factor = 0;
  p.time_step = 0.1;
  p.vein_trees = true;
  REQUIRE(stable_time_step(p) == Approx(2 / std::sqrt(2 * 1.0 + 2 * 0.5 + 2 * 0.05 / 1e-6)));
  CHECK_THROWS_WITH(validate(p), Catch::Matchers::Contains("cells.vein.cohesion 0.05"));
  p.vein_trees = false;
  CHECK(stable_time_step(p) == Approx(2 / std::sqrt(2 * 1.0 + 2 * 0.5)));
  CHECK_NOTHROW(validate(p));
}
