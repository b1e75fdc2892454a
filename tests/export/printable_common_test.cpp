// Tests of export/printable_common.cpp: the volume a dilated sheet takes, which the shell's memory estimate
// counts (analytic volumes of Steiner's formula), and what it does to the estimate of a folded sheet.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/errors.h"
#include "export/printable.h"
#include "export/printable_internal.h"

using namespace cellform;
using core::Vec3;
using Triangles = std::vector<std::array<Vec3, 3>>;

namespace {
/// A square of side `side` in the plane z = `z`, as two triangles.
void add_square(Triangles& t, double side, double z) {
  const Vec3 a(0, 0, z), b(side, 0, z), c(side, side, z), d(0, side, z);
  t.push_back({a, b, c});
  t.push_back({a, c, d});
}
}  // namespace

TEST_CASE("a dilated square takes Steiner's volume; two close squares take their union's", "[printable]") {
  using exporters::detail::dilated_volume;
  // a flat convex set of area A and perimeter P dilated by d: 2 d A + (pi / 2) d^2 P + (4 pi / 3) d^3
  Triangles one;
  add_square(one, 20, 0);
  const double steiner = 2 * 400 + M_PI / 2 * 80 + 4 * M_PI / 3;
  CHECK(dilated_volume(one, 1, 1) == Approx(steiner).epsilon(0.02));
  // the scale applies before the dilation: 10 mm per unit makes a 200 mm square
  CHECK(dilated_volume(one, 10, 1) == Approx(2 * 40000 + M_PI / 2 * 800 + 4 * M_PI / 3).epsilon(0.02));
  // two squares 0.5 apart: a slab 2.5 thick, its rim's section the union of two half discs 0.5 apart
  // (pi - lens / 2 with lens = 2 acos(0.25) - 0.25 sqrt(3.75)), and a little more at the corners
  Triangles two = one;
  add_square(two, 20, 0.5);
  const double lens = 2 * std::acos(0.25) - 0.25 * std::sqrt(3.75);
  const double slab = 400 * 2.5 + 80 * (M_PI - lens / 2);
  const double both = dilated_volume(two, 1, 1);
  CHECK(both > slab);
  CHECK(both < slab + 4 * M_PI / 3 * 1.5);
  CHECK(both < 0.65 * 2 * dilated_volume(one, 1, 1));  // far less than the two dilations' sum
  // far apart they do not overlap: exactly twice one (the same grid cells, shifted by whole cells)
  Triangles apart = one;
  add_square(apart, 20, 50);
  CHECK(dilated_volume(apart, 1, 1) == Approx(2 * dilated_volume(one, 1, 1)).epsilon(0.01));
  CHECK(dilated_volume({}, 1, 1) == 0);
  // a grid held to fewer cells is coarsened, and says so (closing_overlap then trusts no share below 1)
  bool coarsened = true;
  dilated_volume(two, 1, 1, &coarsened);
  CHECK_FALSE(coarsened);
  dilated_volume(two, 1, 1, &coarsened, 1000);
  CHECK(coarsened);
}

TEST_CASE("the overlap of a sheet's dilations is their union's share, at most 1", "[printable]") {
  using exporters::detail::closing_overlap;
  Triangles one, two;
  add_square(one, 20, 0);
  two = one;
  add_square(two, 20, 0.5);
  CHECK(closing_overlap(one, 1, 400, 1, 1) == 1);  // the rim adds to the union of one square: 1
  const double share = closing_overlap(two, 1, 800, 1, 1);
  CHECK(share == Approx(exporters::detail::dilated_volume(two, 1, 1) / 1600));
  CHECK(share < 0.75);
  // the larger of the two dilations' shares: at 3 the squares overlap more, so 1's share decides
  CHECK(closing_overlap(two, 1, 800, 1, 3) == share);
  CHECK(closing_overlap({}, 1, 0, 1, 1) == 1);
}

TEST_CASE("a folded sheet's shell fits a memory limit the same sheet unfolded does not", "[printable]") {
  // two squares of 200 mm (at 1 mm per unit), 0.5 mm apart or 50 mm apart, closed with a radius of 5 mm (on
  // squares of 20 mm the rims would outweigh the overlap): the plan is told before any voxel is made, and the
  // print stopped there. The overlap is counted only where the dilations' sum is over the limit.
  exporters::ThickenParams p;
  p.scale = 1;
  p.voxel_size = 0.1;
  p.close_holes = 5;  // mm: the closing's grid, through 2 (0.3 + 5 + 0.6) mm of each square, outweighs the bands
  p.min_radius = 0.2;
  p.max_memory_bytes = 1e15;
  double estimate = 0;
  p.planned = [&](const exporters::ThickenReport& r) {
    estimate = r.estimated_bytes;
    throw core::Cancelled();
  };
  const auto planned = [&](const Triangles& t) {
    estimate = 0;
    CHECK_THROWS_AS(exporters::thicken({}, t, p), core::Cancelled);
    return estimate;
  };
  Triangles folded, apart;
  add_square(folded, 200, 0);
  add_square(folded, 200, 0.5);
  add_square(apart, 200, 0);
  add_square(apart, 200, 50);
  // under a limit they both fit, the sum of the dilations is the estimate: the same for both
  const double sum = planned(apart);
  CHECK(planned(folded) == sum);
  // a limit of 0.7 times that: the folded sheet's dilations overlap, its union fits; the unfolded one's does not
  p.max_memory_bytes = 0.7 * sum;
  const double near = planned(folded);
  INFO(near << " " << sum);
  CHECK(near < 0.7 * sum);  // the union of the dilations is about 12.3 mm thick, their sum 23.6 mm
  CHECK(near > 0.5 * sum);  // the bands around both squares stay
  CHECK_THROWS_WITH(exporters::thicken({}, apart, p), Catch::Matchers::Contains("more than the limit"));
}

TEST_CASE("a print the process cannot hold is refused before any voxel, never coarsened to fit", "[printable]") {
  // an estimate over ThickenParams::available_bytes (what ulimit -v leaves, say) is refused with that bound's name;
  // the automatic voxel follows max_memory_bytes only, so the same parameters print alike on any machine
  exporters::ThickenParams p;
  p.scale = 1;
  p.min_radius = 0.2;  // the automatic voxel: 0.1 mm
  double estimate = 0, voxel = 0;
  p.planned = [&](const exporters::ThickenReport& r) {
    estimate = r.estimated_bytes;
    voxel = r.voxel_size;
    throw core::Cancelled();
  };
  Triangles sheet;
  add_square(sheet, 200, 0);
  p.shell_thickness = 0.6;
  CHECK_THROWS_AS(exporters::thicken({}, sheet, p), core::Cancelled);
  const double need = estimate, fine = voxel;
  REQUIRE(need > 1e6);
  p.available_bytes = 1.01 * need;  // just enough: planned as before
  CHECK_THROWS_AS(exporters::thicken({}, sheet, p), core::Cancelled);
  CHECK(voxel == fine);
  p.available_bytes = 0.5 * need;
  p.available_name = "what the test leaves";
  voxel = 0;
  const std::string mb = std::to_string(static_cast<long>(std::floor(0.5 * need / 1e6)));
  CHECK_THROWS_WITH(exporters::thicken({}, sheet, p),
                    Catch::Matchers::Contains("more than what the test leaves") &&
                        Catch::Matchers::Contains("lower the memory limit to " + mb + " MB or less"));
  CHECK(voxel == 0);  // refused at the plan: nothing was voxelised
  // a limit at what the message says makes the automatic voxel coarsen to fit, and the print go on
  p.max_memory_bytes = std::stod(mb) * 1e6;
  CHECK_THROWS_AS(exporters::thicken({}, sheet, p), core::Cancelled);
  CHECK(voxel > fine);
  CHECK(estimate <= p.available_bytes);
  // where even the coarsest voxel (the thinnest member) would not fit, a lower limit cannot help: said so
  p.max_memory_bytes = 2e9;
  p.available_bytes = 1e6;
  CHECK_THROWS_WITH(exporters::thicken({}, sheet, p),
                    Catch::Matchers::Contains("use a smaller scale or size (no voxel coarse enough fits") &&
                        !Catch::Matchers::Contains("lower the memory limit"));
  // a voxel size given is not changed: a coarser one is asked for
  p.max_memory_bytes = 1e15;
  p.voxel_size = fine;
  CHECK_THROWS_WITH(exporters::thicken({}, sheet, p), Catch::Matchers::Contains("use a coarser voxel size"));
}
