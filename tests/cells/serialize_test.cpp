// save/load round trips bit for bit and rejects damaged bytes.
#include "cells/serialize.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>

#include "cells/simulation.h"
#include "core/errors.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

namespace {

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(a[i].data(), b[i].data(), 24) != 0) return false;
  return true;
}

}  // namespace

TEST_CASE("round trip is bit-exact", "[serialize]") {
  Params p;
  p.division.division_age = 6;
  p.division.min_age = 3;
  Simulation sim(p, 4);
  sim.cells() = cellform::testing::hex_sheet(6, 6);
  attribute(sim.cells(), "flow", 0.25);
  sim.cells().type[3] = CellType::vein;
  sim.cells().vein_parent[3] = 2;
  sim.cells().fixed[0] = 1;
  for (int s = 0; s < 15; ++s) sim.step();
  const Cells& c = sim.cells();
  const std::string bytes = save(c);
  const Cells d = load(bytes, "test checkpoint");
  REQUIRE(same_bits(c.position, d.position));
  REQUIRE(same_bits(c.velocity, d.velocity));
  REQUIRE(same_bits(c.acceleration, d.acceleration));
  REQUIRE(c.age == d.age);
  REQUIRE(c.generation == d.generation);
  REQUIRE(c.type == d.type);
  REQUIRE(c.fixed == d.fixed);
  REQUIRE(c.id == d.id);
  REQUIRE(c.vein_parent == d.vein_parent);
  REQUIRE(c.links == d.links);
  REQUIRE(c.link_stride == d.link_stride);
  REQUIRE(c.next_id == d.next_id);
  REQUIRE(c.attributes == d.attributes);
  REQUIRE(save(d) == bytes);

  REQUIRE(save(load(save(Cells{}), "empty")) == save(Cells{}));
}

TEST_CASE("damaged bytes throw FileError naming the source", "[serialize]") {
  Cells c = cellform::testing::hex_sheet(3, 3);
  const std::string bytes = save(c);
  for (std::size_t cut : {std::size_t{0}, std::size_t{5}, bytes.size() / 2, bytes.size() - 1}) {
    try {
      load(bytes.substr(0, cut), "cells.bin");
      FAIL("accepted truncated bytes");
    } catch (const cellform::core::FileError& e) {
      REQUIRE(std::string(e.what()).find("cells.bin") != std::string::npos);
    }
  }
  std::string bad = bytes;
  bad[0] = 'X';
  REQUIRE_THROWS_AS(load(bad, "x"), cellform::core::FileError);
  // a state with a non-finite position (only a forged or damaged one has it) is refused, not simulated
  Cells nan = c;
  nan.position[4].y() = std::nan("");
  CHECK_THROWS_WITH(load(save(nan), "nan.bin"), Catch::Matchers::Contains("non-finite cell position"));
  // so is a non-finite attribute (a run writes finite flows, radii and orders only)
  for (const double v : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    Cells flow = c;
    attribute(flow, "flow", 1.0)[5] = v;
    CHECK_THROWS_WITH(load(save(flow), "flow.bin"),
                      Catch::Matchers::Contains("flow.bin is corrupt (non-finite value of attribute 'flow')"));
  }
  // a next id no run reaches would wrap the ids of the cells born after it (and repeat the first ones)
  Cells wrap = c;
  wrap.next_id = ~std::uint64_t{0};
  CHECK_THROWS_WITH(load(save(wrap), "wrap.bin"), Catch::Matchers::Contains("wrap.bin is corrupt (next cell id"));
  wrap.next_id = std::uint64_t{1} << 62;  // the largest accepted
  CHECK(load(save(wrap), "wrap.bin").next_id == wrap.next_id);
  // indices one past the end, and an id equal to the next one (which the next cell born would repeat)
  const auto n = static_cast<Index>(c.size());
  Cells parent = c;
  parent.vein_parent[2] = n;
  CHECK_THROWS_WITH(load(save(parent), "p.bin"), Catch::Matchers::Contains("vein parent out of range"));
  parent.vein_parent[2] = n - 1;  // the last cell: fine
  CHECK(load(save(parent), "p.bin").vein_parent[2] == n - 1);
  // a cell its own vein parent, or a cycle of them, is no forest (review: it pushed itself); a chain is one
  parent.vein_parent[n - 1] = 2;
  CHECK_THROWS_WITH(load(save(parent), "p.bin"), Catch::Matchers::Contains("lead back to it"));
  parent.vein_parent[n - 1] = kNoIndex;
  parent.vein_parent[0] = 0;
  CHECK_THROWS_WITH(load(save(parent), "p.bin"),
                    Catch::Matchers::Contains("the vein parents of cell " + std::to_string(parent.id[0])));
  parent.vein_parent[0] = 2;  // 0 -> 2 -> n - 1, a root
  CHECK(load(save(parent), "p.bin").vein_parent[0] == 2);
  Cells link = c;
  link.links[3] = n;
  CHECK_THROWS_WITH(load(save(link), "l.bin"), Catch::Matchers::Contains("link out of range"));
  Cells id = c;
  id.id[4] = id.next_id;
  CHECK_THROWS_WITH(load(save(id), "i.bin"), Catch::Matchers::Contains("cell id not below next id"));
  id.next_id += 1;  // an id no other cell has, just below the next id
  id.id[4] = id.next_id - 1;
  CHECK(load(save(id), "i.bin").id[4] == id.next_id - 1);
}
