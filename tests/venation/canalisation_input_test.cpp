// Tests of venation/canalisation.h: bad parameters and bad cells refused with a clear message.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "cells/simulation.h"
#include "core/errors.h"
#include "tests/fixtures.h"
#include "tests/venation/canalisation_fixtures.h"
#include "venation/canalisation.h"

using namespace cellform;
using namespace cellform::test;  // chain, attr, grow, leaf
using Catch::Matchers::Contains;
using cells::CellType;
using core::Index;
using core::kNoIndex;

TEST_CASE("bad input is refused with a clear message", "[venation]") {
  venation::Params p;
  for (double t : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    p.threshold = t;
    CHECK_THROWS_WITH(venation::validate(p), Contains("venation.threshold must be a number > 0"));
  }
  p = {};
  p.murray_exponent = 0;
  CHECK_THROWS_WITH(venation::validate(p), Contains("venation.murray_exponent"));
  // each bound, just past it and just within it
  const auto refused = [](auto set, const std::string& name) {
    venation::Params q;
    set(q);
    CHECK_THROWS_WITH(venation::validate(q), Contains("venation." + name + " must be "));
  };
  refused([](venation::Params& q) { q.source = -1e-9; }, "source");
  refused([](venation::Params& q) { q.source = std::nan(""); }, "source");
  refused([](venation::Params& q) { q.radius_scale = 0; }, "radius_scale");
  refused([](venation::Params& q) { q.radius_scale = HUGE_VAL; }, "radius_scale");
  refused([](venation::Params& q) { q.murray_exponent = 4.0001; }, "murray_exponent");
  refused([](venation::Params& q) { q.min_radius = 1e39; }, "min_radius");  // past a float
  refused([](venation::Params& q) { q.every = 0; }, "every");               // Scene::step takes the step modulo it
  venation::Params edge;
  edge.source = 0;
  edge.murray_exponent = 4;
  edge.min_radius = 3e38;
  edge.every = 1;
  CHECK_NOTHROW(venation::validate(edge));
  cells::Cells c = chain(5);
  c.type[0] = CellType::general;
  venation::Workspace ws;
  CHECK_THROWS_WITH(venation::canalise(c, {}, {}, ws), Contains("needs at least one petiole"));
  c.type[0] = CellType::petiole;
  for (std::size_t i = 0; i < c.size(); ++i) c.id[i] = 100 + i;  // ids, which the user sees, are not indices
  const venation::SourceRule bad = [](const cells::Cells& cc, Index i) { return cc.id[i] == 103 ? -1.0 : 1.0; };
  CHECK_THROWS_WITH(venation::canalise(c, {}, bad, ws), Contains("cell 103 got -1"));
  const venation::SourceRule nan = [](const cells::Cells& cc, Index i) { return cc.id[i] == 102 ? std::nan("") : 1.0; };
  CHECK_THROWS_WITH(venation::canalise(c, {}, nan, ws), Contains("cell 102 got NaN"));
  // finite sources whose sum overflows would write infinite flows and radii
  const venation::SourceRule huge = [](const cells::Cells&, Index) { return 1e308; };
  CHECK_THROWS_WITH(venation::canalise(c, {}, huge, ws), Contains("venation.source") && Contains("range"));
  venation::Params big;
  big.source = 1e308;
  CHECK_THROWS_WITH(venation::canalise(c, big, {}, ws), Contains("venation.source") && Contains("overflows"));
  // finite as doubles, but beyond the 32-bit flows of the cell and vein files (they would read inf)
  const venation::SourceRule vast = [](const cells::Cells&, Index) { return 1e300; };
  CHECK_THROWS_WITH(venation::canalise(c, {}, vast, ws), Contains("venation.source") && Contains("32-bit"));
  big.source = 1e38;
  CHECK_THROWS_WITH(venation::canalise(c, big, {}, ws), Contains("venation.source") && Contains("32-bit"));
  big.source = 1e30;  // five cells: 5e30, well inside
  CHECK_NOTHROW(venation::canalise(c, big, {}, ws));
  // radii beyond the files' 32-bit numbers: a minimum radius refused at once, a scale when a flow needs it
  p = {};
  p.min_radius = 1e39;
  CHECK_THROWS_WITH(venation::validate(p), Contains("venation.min_radius") && Contains("3.4e38"));
  p.min_radius = 3e38;
  CHECK_NOTHROW(venation::validate(p));
  venation::Params wide;
  wide.radius_scale = 1e300;
  CHECK_THROWS_WITH(venation::canalise(c, wide, {}, ws), Contains("venation.radius_scale") && Contains("32-bit"));
  wide.radius_scale = 1e30;  // five cells: 5^(1/3) 1e30
  CHECK_NOTHROW(venation::canalise(c, wide, {}, ws));
  wide.radius_scale = 2.5e38;  // one cell's flow would fit (2.5e38), the five cells' (4.3e38) not
  CHECK_THROWS_WITH(venation::canalise(c, wide, {}, ws), Contains("venation.radius_scale") && Contains("32-bit"));
  CHECK(attr(c, venation::kRadius)[0] <= std::numeric_limits<float>::max());
}
