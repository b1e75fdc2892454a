// Tests of export/primitives.cpp: the vein graph and the cell sheet as printing primitives.
#include <catch2/catch.hpp>

#include "cells/surface.h"
#include "export/printable.h"

using namespace cellform;
using core::Vec3;

TEST_CASE("vein_segments and shell_triangles turn the model into primitives", "[printable]") {
  venation::VeinGraph g;
  g.position = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
  g.radius = {0.3, 0.2, 0.1, 0.4};
  g.cell = {0, 1, 2, 3};
  g.flow = {3, 2, 1, 1};
  g.order = {1, 1, 1, 1};
  g.edges = {{1, 0}, {2, 1}};
  const auto s = exporters::vein_segments(g);
  REQUIRE(s.size() == 2);  // the lone node (a petiole without veins) is no part of the form
  CHECK(s[0].a == g.position[1]);
  CHECK(s[0].b == g.position[0]);
  CHECK(s[0].ra == 0.2);
  CHECK(s[0].rb == 0.3);
  CHECK(s[1].a == g.position[2]);
  CHECK(s[1].rb == 0.2);
  // a side branch (order 2 off an order-1 vein) starts at its own radius, not flared to its parent's
  g.position.push_back({1, 1, 0});
  g.radius.push_back(0.05);
  g.cell.push_back(4);
  g.flow.push_back(0.1);
  g.order.push_back(2);
  g.edges.push_back({4, 1});
  const auto b = exporters::vein_segments(g);
  REQUIRE(b.size() == 3);
  CHECK(b[2].a == g.position[4]);
  CHECK(b[2].b == g.position[1]);
  CHECK(b[2].ra == 0.05);
  CHECK(b[2].rb == 0.05);
  CHECK(b[1].rb == 0.2);  // the main child still tapers from its parent
  // a sheet's triangles become their corners' positions, in order
  cells::Cells c;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1)}) cells::add_cell(c, p);
  cells::Surface surface;
  surface.triangles = {{0, 1, 2}, {1, 3, 2}};
  const auto t = exporters::shell_triangles(c, surface);
  REQUIRE(t.size() == 2);
  CHECK(t[1][0] == Vec3(1, 0, 0));
  CHECK(t[1][1] == Vec3(1, 1, 1));
  CHECK(t[1][2] == Vec3(0, 1, 0));
}
