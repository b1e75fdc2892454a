// Each force kernel alone on tiny configurations, against closed-form values.
#include "cells/forces.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "cells/simulation.h"
#include "core/random.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

namespace {
const std::vector<Index> kOne = {1};
}

TEST_CASE("spring: zero at rest length, repulsive below, attractive above", "[forces]") {
  const double d = 1.5;
  for (double dist : {1.5, 1.0, 2.5}) {
    const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(dist, 0, 0)};
    const Vec3 a = spring_kernel(pos, 0, kOne, d);
    // acceleration on cell 0 is (|P - C| - d) along +x
    REQUIRE(a.x() == Approx(dist - d).margin(1e-15));
    REQUIRE(a.y() == 0.0);
    REQUIRE(a.z() == 0.0);
    const Vec3 b = spring_kernel(pos, 1, std::vector<Index>{0}, d);
    REQUIRE(b.x() == -a.x());  // equal and opposite
  }
  const std::vector<Vec3> at_rest = {Vec3(0, 0, 0), Vec3(0, 1.5, 0)};
  REQUIRE(spring_kernel(at_rest, 0, kOne, d).norm() == 0.0);
  const std::vector<Vec3> close = {Vec3(0, 0, 0), Vec3(0, 1.0, 0)};
  REQUIRE(spring_kernel(close, 0, kOne, d).y() < 0);  // pushed away from the neighbour
  const std::vector<Vec3> far = {Vec3(0, 0, 0), Vec3(0, 2.0, 0)};
  REQUIRE(spring_kernel(far, 0, kOne, d).y() > 0);  // pulled towards it
}

TEST_CASE("spring averages over the neighbours", "[forces]") {
  const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0)};
  const Vec3 a = spring_kernel(pos, 0, std::vector<Index>{1, 2}, 1.0);
  REQUIRE(a.x() == Approx(0.5 * 1.0));
  REQUIRE(a.y() == Approx(0.5 * 2.0));
}

TEST_CASE("spring on coincident cells is finite and pushes them apart symmetrically", "[forces]") {
  const std::vector<Vec3> pos = {Vec3(1, 1, 1), Vec3(1, 1, 1)};
  const Vec3 a = spring_kernel(pos, 0, kOne, 1.0);
  const Vec3 b = spring_kernel(pos, 1, std::vector<Index>{0}, 1.0);
  REQUIRE(a.allFinite());
  REQUIRE(a.norm() == Approx(1.0));
  REQUIRE((a + b).norm() == 0.0);
  REQUIRE(cohesion_kernel(pos, 0, kOne).norm() == 0.0);
  REQUIRE(separation_kernel(pos, 0, kOne).norm() == 0.0);
  // a pile of coincident cells: each pair has its own direction (all along x made a line of them), spread over
  // the sphere
  const std::vector<Vec3> pile(64, Vec3(1, 1, 1));
  Vec3 sum_abs = Vec3::Zero();
  std::vector<Vec3> seen;
  for (Index i = 0; i < 64; ++i)
    for (Index j = i + 1; j < 64; ++j) {
      const Vec3 d = spring_kernel(pile, i, std::vector<Index>{j}, 1.0);
      REQUIRE(d.norm() == Approx(1.0));
      REQUIRE((d + spring_kernel(pile, j, std::vector<Index>{i}, 1.0)).norm() == 0.0);
      sum_abs += d.cwiseAbs();
      seen.push_back(d);
    }
  const double pairs = static_cast<double>(seen.size());  // 2,016: |component| averages 1/2 on the sphere
  for (int k = 0; k < 3; ++k) CHECK(sum_abs[k] / pairs == Approx(0.5).margin(0.03));
}

TEST_CASE("planar: towards the plane of three neighbours with magnitude = height", "[forces]") {
  const Vec3 p1(0, 0, 2), p2(1, 0, 2), p3(0, 1, 2);
  for (double h : {0.5, -0.25, 3.0}) {
    const Vec3 c(0.3, 0.4, 2 + h);
    const Vec3 a = planar_kernel(c, p1, p2, p3);
    REQUIRE(a.x() == Approx(0).margin(1e-15));
    REQUIRE(a.y() == Approx(0).margin(1e-15));
    REQUIRE(a.z() == Approx(-h));
  }
  // tilted plane: the acceleration moves C exactly onto the plane
  const Vec3 q1(0, 0, 0), q2(1, 0, 1), q3(0, 1, 1);
  const Vec3 c(0.2, 0.7, 3.0);
  const Vec3 onto = c + planar_kernel(c, q1, q2, q3);
  const Vec3 normal = (q2 - q1).cross(q3 - q1);
  REQUIRE((onto - q1).dot(normal) == Approx(0).margin(1e-12));
  REQUIRE(planar_kernel(c, q1, q2, q3).cross(normal).norm() == Approx(0).margin(1e-12));
}

TEST_CASE("planar: zero on the plane and for collinear neighbours", "[forces]") {
  REQUIRE(planar_kernel(Vec3(0.5, 0.5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)).norm() == 0.0);
  REQUIRE(planar_kernel(Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)).norm() == 0.0);
  REQUIRE(planar_kernel(Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)).norm() == 0.0);
}

TEST_CASE("cohesion and separation: closed form, equal and opposite for two cells", "[forces]") {
  const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(0, 0, 2)};
  const Vec3 c0 = cohesion_kernel(pos, 0, kOne);
  const Vec3 c1 = cohesion_kernel(pos, 1, std::vector<Index>{0});
  REQUIRE(c0.z() == Approx(0.5));  // (P - C) / |P - C|^2 = 2 / 4
  REQUIRE((c0 + c1).norm() == 0.0);
  const Vec3 s0 = separation_kernel(pos, 0, kOne);
  const Vec3 s1 = separation_kernel(pos, 1, std::vector<Index>{0});
  REQUIRE(s0.z() == Approx(-0.5));
  REQUIRE((s0 + s1).norm() == 0.0);
  REQUIRE((s0 + c0).norm() == 0.0);
}

TEST_CASE("cohesion closer than `near` weakens with the distance, continuously", "[forces]") {
  for (const double d : {0.0, 0.25, 0.5, 0.999, 1.0, 1.5, 3.0}) {
    const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(d, 0, 0)};
    const Vec3 f = cohesion_kernel(pos, 0, kOne, 1.0);
    INFO("distance " << d);
    CHECK(f.y() == 0.0);
    CHECK(f.z() == 0.0);
    CHECK(f.x() == Approx(d < 1.0 ? d : 1.0 / d));  // d / near^2 within near, the printed 1 / d beyond
    if (d >= 1.0) CHECK(f.x() == cohesion_kernel(pos, 0, kOne).x());
  }
}

TEST_CASE("second ring excludes the cell and its direct neighbours, without duplicates", "[forces]") {
  Cells c = cellform::testing::hex_sheet(7, 7);
  cellform::testing::link_lattice(c);
  const Index centre = 3 * 7 + 3;
  std::vector<Index> direct, ring;
  direct_neighbours(c, VeinChildren{}, centre, direct);
  REQUIRE(direct.size() == 6);
  second_ring(c, centre, direct, ring);
  REQUIRE(ring.size() == 12);  // the second hexagonal ring
  for (const Index r : ring) {
    REQUIRE(r != centre);
    REQUIRE(std::find(direct.begin(), direct.end(), r) == direct.end());
    REQUIRE(std::count(ring.begin(), ring.end(), r) == 1);
    const double dist = (c.position[r] - c.position[centre]).norm();
    REQUIRE(dist > 1.5);
    REQUIRE(dist < 2.01);
  }
}

TEST_CASE("cell_acceleration's separation is Eq. 5 over the reference second ring, on a random sheet", "[forces]") {
  // cell_acceleration finds the second ring its own faster way (a stamp per cell, kept between cells and
  // steps); on a random cloud with its k-nearest links, vein chains and some one-way links, it must agree with
  // second_ring() and separation_kernel() for every cell, the cell itself and its direct neighbours never in
  // the ring however the cells were visited before
  cellform::core::Rng rng(3);
  Cells c;
  for (int i = 0; i < 600; ++i) add_cell(c, Vec3(rng.uniform(0, 12), rng.uniform(0, 12), rng.uniform(-0.2, 0.2)));
  Params p;
  cellform::core::PointGrid grid;
  update_links(c, p, grid, 1);
  for (Index i = 1; i < 40; ++i) {  // a vein chain
    c.type[i] = CellType::vein;
    c.vein_parent[i] = i - 1;
  }
  const VeinChildren vc = vein_children(c);
  for (auto& w : p.weights) w = ForceWeights{0.0, 0.0, 0.0, 0.7};  // separation alone
  p.vein_separation_factor = 0;
  ForceScratch s;
  std::vector<Index> direct, ring;
  for (int pass = 0; pass < 2; ++pass)  // the second pass with the stamps the first left
    for (Index i = 0; i < static_cast<Index>(c.size()); ++i) {
      direct_neighbours(c, vc, i, direct);
      second_ring(c, i, direct, ring);
      const Vec3 expected = 0.7 * separation_kernel(c.position, i, ring);
      const Vec3 a = cell_acceleration(c, p, vc, i, s);
      INFO("cell " << i);
      REQUIRE((a - expected).norm() <= 1e-12 * (1 + expected.norm()));
    }
}

TEST_CASE("vein parent and children always count as direct neighbours", "[forces]") {
  Cells c;
  for (int i = 0; i < 5; ++i) add_cell(c, Vec3(i, 0, 0), CellType::vein);
  // links: nobody linked to anybody
  c.vein_parent = {kNoIndex, 0, 1, 2, 3};
  c.links[1 * 6] = 2;  // 1 links 2 already: must not be duplicated
  const VeinChildren vc = vein_children(c);
  std::vector<Index> direct;
  direct_neighbours(c, vc, 1, direct);
  REQUIRE(direct == std::vector<Index>{2, 0});
  std::vector<Index> ring;
  vein_second_ring(c, vc, 2, ring);
  REQUIRE(ring == std::vector<Index>{0, 4});
}

TEST_CASE("flat hex sheet at rest: zero acceleration in the interior", "[forces]") {
  Cells c = cellform::testing::hex_sheet(9, 9);
  cellform::testing::link_lattice(c);
  Params p;
  p.weights[0].cohesion = 0.3;
  p.weights[0].separation = 0.2;
  compute_accelerations(c, p, VeinChildren{}, 1);
  // every term cancels by symmetry for a cell two rings or more from the rim (separation reaches the
  // second ring; planar: it lies in the plane), whichever way its row is shifted
  for (int row = 2; row < 7; ++row)
    for (int col = 2; col < 7; ++col) {
      INFO("row " << row << ", column " << col);
      REQUIRE(c.acceleration[static_cast<std::size_t>(row * 9 + col)].norm() == Approx(0).margin(1e-12));
    }
  // the whole sheet stays in its plane
  for (const Vec3& a : c.acceleration) REQUIRE(a.z() == 0.0);
}

TEST_CASE("cell_acceleration adds weighted terms and the unary force", "[forces]") {
  // a cell 0.5 above the plane of its three neighbours, which sit at distance > rest
  Cells c;
  add_cell(c, Vec3(0, 0, 0.5));
  add_cell(c, Vec3(1, 0, 0));
  add_cell(c, Vec3(-0.5, 0.9, 0));
  add_cell(c, Vec3(-0.5, -0.9, 0));
  c.link_stride = 6;
  c.links.assign(4 * 6, kNoIndex);
  c.links[0] = 1;
  c.links[1] = 2;
  c.links[2] = 3;
  Params p;
  p.weights[0] = ForceWeights{0.0, 0.7, 0.0, 0.0};
  p.unary = Vec3(0, 0, -0.1);
  ForceScratch s;
  const Vec3 a = cell_acceleration(c, p, VeinChildren{}, 0, s);
  REQUIRE(a.x() == Approx(0).margin(1e-15));
  REQUIRE(a.y() == Approx(0).margin(1e-15));
  REQUIRE(a.z() == Approx(-0.7 * 0.5 - 0.1));
  c.fixed[0] = 1;
  REQUIRE(cell_acceleration(c, p, VeinChildren{}, 0, s).norm() == 0.0);
}

TEST_CASE(
    "vein straightening: cohesion pulls a bent vein cell towards its parent and child, separation pushes "
    "it from its grandparent and grandchild",
    "[forces]") {
  Cells c;
  add_cell(c, Vec3(-2, 0, 0), CellType::vein);
  add_cell(c, Vec3(-1, 0, 0), CellType::vein);
  add_cell(c, Vec3(0, 0.3, 0), CellType::vein);  // the bent one
  add_cell(c, Vec3(1, 0, 0), CellType::vein);
  add_cell(c, Vec3(2, 0, 0), CellType::vein);
  c.vein_parent = {kNoIndex, 0, 1, 2, 3};
  Params p;
  p.weights[2] = ForceWeights{0.0, 0.0, 1.0, 1.0};
  const VeinChildren vc = vein_children(c);
  ForceScratch s;
  auto acceleration = [&](double cohesion, double separation, Index i) {
    p.vein_cohesion_factor = cohesion;
    p.vein_separation_factor = separation;
    return cell_acceleration(c, p, vc, i, s);
  };
  const Vec3 without = acceleration(0, 0, 2);
  // each term on its own, against Eqs. 4 and 5 over {parent, child} and {grandparent, grandchild}, times 4:
  // cohesion 4 * ((-1, -0.3) + (1, -0.3)) / 1.09 / 2, separation 4 * ((2, 0.3) + (-2, 0.3)) / 4.09 / 2
  const Vec3 cohesion = acceleration(4, 0, 2) - without, separation = acceleration(0, 4, 2) - without;
  CHECK(cohesion.x() == Approx(0).margin(1e-12));
  CHECK(cohesion.y() == Approx(-4 * 0.6 / 1.09 / 2));  // towards the line of parent and child
  CHECK(separation.x() == Approx(0).margin(1e-12));
  CHECK(separation.y() == Approx(4 * 0.6 / 4.09 / 2));  // the bent cell itself is pushed off the line...
  // ...but the vein's ends are pushed apart along it, which straightens a free vein (tests/cells/simulation_test)
  const Vec3 end = acceleration(0, 4, 0) - acceleration(0, 0, 0);
  CHECK(end.x() == Approx(4 * -2.0 / 4.09));
  CHECK(end.y() == Approx(4 * -0.3 / 4.09));
  CHECK(acceleration(4, 4, 2).y() < 0);  // together (the defaults) the bent cell is pulled back
  // each factor multiplies its own weight (the equal weights above would hide the two swapped)
  p.weights[2] = ForceWeights{0.0, 0.0, 0.5, 2.0};
  const Vec3 base = acceleration(0, 0, 2);
  CHECK((acceleration(4, 0, 2) - base).y() == Approx(-0.5 * 4 * 0.6 / 1.09 / 2));
  CHECK((acceleration(0, 4, 2) - base).y() == Approx(2.0 * 4 * 0.6 / 4.09 / 2));
}
