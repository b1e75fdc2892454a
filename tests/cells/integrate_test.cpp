// Integrators, drag, fixed cells and divergence detection.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>

#include "cells/simulation.h"
#include "core/errors.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

TEST_CASE("semi-implicit Euler with drag", "[integrate]") {
  Cells c;
  add_cell(c, Vec3(0, 0, 0));
  c.velocity[0] = Vec3(1, 2, 3);
  c.acceleration[0] = Vec3(10, 0, -10);
  Params p;
  p.drag = Vec3(1.0, 0.5, 0.0);
  p.time_step = 0.1;
  integrate(c, p, 1, 1);
  // v = drag * (v + a dt) = (2, 1, 0); x += v dt
  REQUIRE(c.velocity[0].x() == Approx(2.0));
  REQUIRE(c.velocity[0].y() == Approx(1.0));
  REQUIRE(c.velocity[0].z() == 0.0);
  REQUIRE(c.position[0].x() == Approx(0.2));
  REQUIRE(c.position[0].y() == Approx(0.1));
  REQUIRE(c.position[0].z() == 0.0);
}

TEST_CASE("velocity-only integrator ignores the previous velocity", "[integrate]") {
  Cells c;
  add_cell(c, Vec3(0, 0, 0));
  c.velocity[0] = Vec3(100, 0, 0);
  c.acceleration[0] = Vec3(1, 2, 3);
  Params p;
  p.integrator = Integrator::velocity;
  p.drag = Vec3(0.5, 0.5, 0.5);
  integrate(c, p, 1, 1);
  REQUIRE(c.velocity[0].x() == Approx(0.5));
  REQUIRE(c.position[0].z() == Approx(1.5 * p.time_step));
}

TEST_CASE("velocity-only integrator applies the drag axis by axis", "[integrate]") {
  // v = drag * a per component (no previous velocity), x += v dt: a zero-drag axis never moves
  Cells c;
  const Vec3 x0(0.3, -0.2, 0.7);
  add_cell(c, x0);
  c.velocity[0] = Vec3(5, -5, 5);
  c.acceleration[0] = Vec3(1, 2, 3);
  Params p;
  p.integrator = Integrator::velocity;
  p.drag = Vec3(1.0, 0.5, 0.0);
  const double dt = p.time_step;
  integrate(c, p, 1, 1);
  CHECK(c.velocity[0].x() == Approx(1.0 * 1));
  CHECK(c.velocity[0].y() == Approx(0.5 * 2));
  CHECK(c.velocity[0].z() == 0.0);
  CHECK(c.position[0].x() == Approx(x0.x() + 1.0 * dt));
  CHECK(c.position[0].y() == Approx(x0.y() + 1.0 * dt));
  CHECK(c.position[0].z() == x0.z());
}

TEST_CASE("fixed cells never move", "[integrate]") {
  Params p;
  p.unary = Vec3(0, 0, -1);
  p.division.trigger = DivisionTrigger::age;
  p.division.division_age = 5;
  p.division.min_age = 5;
  p.division.max_cells = 500;
  Simulation sim(p, 3);
  Cells& c = sim.cells();
  c = cellform::testing::hex_sheet(5, 5);
  c.link_stride = p.neighbours;
  c.links.assign(c.size() * 6, kNoIndex);
  for (Index i = 0; i < 5; ++i) c.fixed[i] = 1;
  std::vector<std::pair<std::uint64_t, Vec3>> before;
  for (Index i = 0; i < 5; ++i) before.push_back({c.id[i], c.position[i]});
  for (int s = 0; s < 70; ++s) sim.step();  // includes a spatial reorder at step 32 and 64
  std::size_t seen = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    for (const auto& [id, pos] : before)
      if (c.id[i] == id) {
        REQUIRE(c.position[i] == pos);
        REQUIRE(c.fixed[i] == 1);
        ++seen;
      }
  REQUIRE(seen == 5);
  REQUIRE(c.size() > 25);
}

TEST_CASE("a huge time step diverges with a message naming the cell, positions unchanged", "[integrate]") {
  Cells c = cellform::testing::hex_sheet(10, 10, 0.5);  // compressed: strong springs
  Params p;
  p.time_step = 1e200;  // bypasses validate
  p.max_speed = 1e6;
  cellform::core::PointGrid grid;
  update_links(c, p, grid, 1);
  compute_accelerations(c, p, VeinChildren{}, 1);
  const auto before = c.position;
  const auto velocity = c.velocity;
  try {
    integrate(c, p, 120, 1);
    FAIL("no exception");
  } catch (const cellform::core::SimulationDiverged& e) {
    const std::string msg = e.what();
    INFO(msg);
    REQUIRE(msg.find("step 120") != std::string::npos);
    REQUIRE(msg.find("cell ") != std::string::npos);
  }
  REQUIRE(c.position == before);
  REQUIRE(c.velocity == velocity);
}

TEST_CASE("a NaN position stops the simulation naming that cell", "[integrate]") {
  Params p;
  Simulation sim(p, 1);
  sim.cells() = cellform::testing::hex_sheet(8, 8);
  sim.cells().id[17] = 812;
  sim.cells().position[17].y() = std::nan("");
  std::map<std::uint64_t, Vec3> before;
  for (std::size_t i = 0; i < sim.cells().size(); ++i) before[sim.cells().id[i]] = sim.cells().position[i];
  try {
    sim.step();
    FAIL("no exception");
  } catch (const cellform::core::SimulationDiverged& e) {
    const std::string msg = e.what();
    INFO(msg);
    REQUIRE(msg.find("step 1, cell 812: position is NaN") != std::string::npos);
  }
  REQUIRE(sim.step_count() == 0);
  REQUIRE(sim.cells().size() == before.size());
  for (std::size_t i = 0; i < sim.cells().size(); ++i)
    if (sim.cells().id[i] != 812) REQUIRE(sim.cells().position[i] == before[sim.cells().id[i]]);
}

TEST_CASE("speed above max_speed diverges", "[integrate]") {
  Cells c;
  add_cell(c, Vec3(0, 0, 0));
  add_cell(c, Vec3(1, 0, 0));
  c.id[1] = 99;
  c.acceleration[1] = Vec3(0, 50, 0);
  Params p;
  p.max_speed = 1;
  try {
    integrate(c, p, 7, 1);
    FAIL("no exception");
  } catch (const cellform::core::SimulationDiverged& e) {
    const std::string msg = e.what();
    INFO(msg);
    REQUIRE(msg.find("step 7, cell 99: speed") != std::string::npos);
    REQUIRE(msg.find("cells.max_speed") != std::string::npos);
  }
  REQUIRE(c.position[1] == Vec3(1, 0, 0));
  // just past the limit: enough digits to show it ("1e+06 exceeds cells.max_speed = 1e+06" read as a bug)
  p.max_speed = 1e6;
  p.drag = Vec3::Ones();
  c.acceleration[1] = Vec3(0, 1e6 / p.time_step * (1 + 1e-9), 0);
  c.velocity[1].setZero();
  try {
    integrate(c, p, 8, 1);
    FAIL("no exception");
  } catch (const cellform::core::SimulationDiverged& e) {
    const std::string msg = e.what();
    INFO(msg);
    REQUIRE(msg.find("speed 1e+06 ") == std::string::npos);
    REQUIRE(msg.find("speed 1000000.001 exceeds cells.max_speed = 1000000;") != std::string::npos);
  }
}

TEST_CASE("the divergence said is the same on any number of threads: the worst problem, then the first cell",
          "[integrate]") {
  // a review: each range stopped at its first problem, so one thread named a fast cell where two named a
  // NaN acceleration further on
  for (const int threads : {1, 2, 4}) {
    Cells c;
    for (int i = 0; i < 20000; ++i) add_cell(c, Vec3(i, 0, 0));
    c.acceleration[100] = Vec3(0, 50, 0);  // too fast
    c.acceleration[15000] = Vec3(0, std::nan(""), 0);
    c.acceleration[17000] = Vec3(0, std::nan(""), 0);
    Params p;
    p.max_speed = 1;
    INFO(threads << " threads");
    try {
      integrate(c, p, 3, threads);
      FAIL("no exception");
    } catch (const cellform::core::SimulationDiverged& e) {
      CHECK_THAT(e.what(), Catch::Contains("step 3, cell 15000: acceleration is NaN"));
    }
  }
}
