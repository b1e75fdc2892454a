// Tests of Colonisation::save() and load(): a run saved after any step and continued in a fresh object
// ends exactly as the run that was never interrupted.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <functional>
#include <limits>
#include <string>

#include "core/chunk_file.h"
#include "core/errors.h"
#include "tests/venation/leaf_fixtures.h"
#include "venation/colonisation.h"
#include "venation/domain.h"

using namespace cellform;
using Catch::Matchers::Contains;
using core::Index;
using core::Vec3;
namespace v = cellform::venation;
using namespace cellform::test;

namespace {

/// An ovate blade `length` by `width` model units.
v::Leaf ovate_leaf(double length, double width) { return ellipse_leaf(length, width, v::ShapeKind::ovate); }

v::ColonisationParams leaf_params(v::VenationType type, double kill, double birth) {
  v::ColonisationParams p = params(type, kill, birth);
  p.darts_per_area = 0.02;
  return p;
}

/// |x| + |y| + |z| <= r as a closed triangle mesh.
v::Mesh octahedron(double r) {
  v::Mesh m;
  m.vertices = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
  for (Index x : {0u, 1u})
    for (Index y : {2u, 3u})
      for (Index z : {4u, 5u}) m.triangles.push_back({x, y, z});
  return m;
}

void require_same(const v::Colonisation& a, const v::Colonisation& b) {
  const v::VeinTree ta = a.tree(), tb = b.tree();
  REQUIRE(ta.size() == tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i)  // bitwise: == on doubles, no tolerance
    REQUIRE((ta.positions[i].x() == tb.positions[i].x() && ta.positions[i].y() == tb.positions[i].y() &&
             ta.positions[i].z() == tb.positions[i].z()));
  REQUIRE(ta.parent == tb.parent);
  REQUIRE(ta.birth_step == tb.birth_step);
  REQUIRE(ta.anastomoses == tb.anastomoses);
  REQUIRE(a.sources() == b.sources());
  const v::ColonisationReport &ra = a.report(), &rb = b.report();
  CHECK(ra.steps == rb.steps);
  CHECK(ra.nodes == rb.nodes);
  CHECK(ra.sources == rb.sources);
  CHECK(ra.sources_born == rb.sources_born);
  CHECK(ra.sources_removed == rb.sources_removed);
  CHECK(ra.darts == rb.darts);
  CHECK(ra.loops == rb.loops);
  CHECK(ra.scale == rb.scale);
  CHECK(ra.finished == rb.finished);
  CHECK(ra.stalled == rb.stalled);
  CHECK(ra.hit_max_steps == rb.hit_max_steps);
  // the whole state, neighbourhood caches and random numbers included
  const std::string sa = a.save(), sb = b.save();
  std::size_t at = 0;
  while (at < sa.size() && at < sb.size() && sa[at] == sb[at]) ++at;
  INFO("first difference at byte " << at << " of " << sa.size() << " / " << sb.size());
  CHECK(sa == sb);
}

/// The state of `c` in an older format: format 4 appended the lazy sector modes (per source 18 bytes,
/// five array lengths and the last segment length) to the "state" chunk, and format 6 the darts of the
/// quiet steps (8 bytes); formats 2, 3 and 5 differ in meaning only (5: a leaf step's nodes entered the
/// tree as one batch).
std::string as_version(const v::Colonisation& c, std::uint32_t version) {
  core::ChunkFile f = core::read_chunk_file(c.save(), "COLO", 6, "state");
  REQUIRE(f.version == 6);
  if (version == 6) return c.save();
  std::string& state = f.chunks.at("state");
  REQUIRE(state.size() > 8);
  state.resize(state.size() - 8);
  if (version >= 4) return core::write_chunk_file("COLO", version, f.chunks);
  const std::size_t trailer = 5 * 8 + 18 * c.report().sources_born + 8;
  REQUIRE(state.size() > trailer);
  state.resize(state.size() - trailer);
  return core::write_chunk_file("COLO", version, f.chunks);
}

/// Runs `make()` to the end; then for cuts at step 0, a third, two thirds, the step before the end (deep in the
/// steps that settle the run: their darts are counted), the end and `more`: steps a fresh run to the cut, saves,
/// loads into another object (threads 2) and runs it to the end.
void check_resume(const std::function<v::Colonisation(int threads)>& make,
                  const std::function<v::Colonisation(const std::string&, int threads)>& load,
                  const std::vector<std::size_t>& more = {}) {
  v::Colonisation whole = make(1);
  whole.run();
  const std::size_t n = whole.report().steps;
  INFO("steps " << n << ", nodes " << whole.report().nodes << ", loops " << whole.report().loops);
  REQUIRE(n > 10);
  REQUIRE((whole.report().finished || whole.report().stalled));
  std::vector<std::size_t> cuts = {0, n / 3, 2 * n / 3, n - 1, n};
  cuts.insert(cuts.end(), more.begin(), more.end());
  for (std::size_t cut : cuts) {
    INFO("saved after step " << cut);
    v::Colonisation first = make(1);
    while (first.report().steps < cut) first.step();
    const std::string bytes = first.save();
    v::Colonisation second = load(bytes, 2);
    CHECK(second.report().steps == cut);
    second.run();
    require_same(whole, second);
  }
}

void check_leaf(const v::Leaf& leaf, const v::ColonisationParams& p, const std::vector<std::size_t>& more = {}) {
  check_resume(
      [&](int threads) {
        v::ColonisationParams q = p;
        q.threads = threads;
        return v::Colonisation(leaf, q);
      },
      [&](const std::string& bytes, int threads) {
        v::ColonisationParams q = p;
        q.threads = threads;
        return v::Colonisation::load(leaf, q, bytes);
      },
      more);
}

void check_domain(const v::Domain& d, const v::ColonisationParams& p) {
  check_resume(
      [&](int threads) {
        v::ColonisationParams q = p;
        q.threads = threads;
        return v::Colonisation(d, q);
      },
      [&](const std::string& bytes, int threads) {
        v::ColonisationParams q = p;
        q.threads = threads;
        return v::Colonisation::load(d, q, bytes);
      });
}

}  // namespace

TEST_CASE("a saved leaf run continues bit-identically: open, closed exact and Urquhart", "[checkpoint]") {
  const v::Leaf leaf = ovate_leaf(30, 20);
  SECTION("open") { check_leaf(leaf, leaf_params(v::VenationType::open, 1, 2)); }
  SECTION("closed, exact") { check_leaf(leaf, leaf_params(v::VenationType::closed, 1, 2)); }
  SECTION("closed, Urquhart") {
    v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 2);
    p.neighbourhood = v::Neighbourhood::urquhart;
    check_leaf(leaf, p);
  }
}

namespace {

/// Few darts in a large blade: sources wait far from the veins, most of them in lazy sector mode.
v::ColonisationParams far_sources_params() {
  v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 3);
  p.darts_per_area = 2e-4;
  return p;
}

}  // namespace

TEST_CASE("a run saved while sources are lazy (far from the veins) continues bit-identically", "[checkpoint]") {
  const v::ColonisationParams p = far_sources_params();
  const v::Leaf leaf = ovate_leaf(200, 120);
  v::Colonisation probe(leaf, p);
  std::vector<std::size_t> lazy{0};  // lazy sources after each step
  while (!probe.done()) {
    probe.step();
    lazy.push_back(probe.lazy_sources());
  }
  // cut where most sources are lazy, and halfway to there: lazy modes are saved
  const std::size_t most = static_cast<std::size_t>(std::max_element(lazy.begin(), lazy.end()) - lazy.begin());
  INFO("steps " << probe.report().steps << ", most lazy after step " << most << ": " << lazy[most]);
  REQUIRE(lazy[most] > 20);
  REQUIRE(lazy[most / 2] > 0);
  check_leaf(leaf, p, {most, most / 2});
}

TEST_CASE("a format-3 state (no lazy modes) continues as the run that was never saved", "[checkpoint]") {
  const v::ColonisationParams p = far_sources_params();
  const v::Leaf leaf = ovate_leaf(200, 120);
  v::Colonisation whole(leaf, p);
  whole.run();
  v::Colonisation first(leaf, p);
  while (first.report().steps < 60) first.step();
  REQUIRE(first.lazy_sources() > 20);
  v::Colonisation second = v::Colonisation::load(leaf, p, as_version(first, 3));
  CHECK(second.lazy_sources() == 0);
  second.run();
  const v::VeinTree a = whole.tree(), b = second.tree();
  REQUIRE(a.size() == b.size());
  CHECK(a.positions == b.positions);
  CHECK(a.parent == b.parent);
  CHECK(a.anastomoses == b.anastomoses);
  // format 4: the tree is rebuilt one node at a time, as runs before format 5 built it; same veins
  v::Colonisation third = v::Colonisation::load(leaf, p, as_version(first, 4));
  CHECK(third.lazy_sources() == first.lazy_sources());
  third.run();
  const v::VeinTree c = third.tree();
  REQUIRE(a.size() == c.size());
  CHECK(a.positions == c.positions);
  CHECK(a.parent == c.parent);
  CHECK(a.anastomoses == c.anastomoses);
}

TEST_CASE("a saved growing leaf continues bit-identically: marginal, isogonic, nonuniform", "[checkpoint]") {
  for (v::GrowthMode g : {v::GrowthMode::marginal, v::GrowthMode::uniform}) {
    INFO("growth " << static_cast<int>(g));
    v::ColonisationParams p =
        leaf_params(g == v::GrowthMode::marginal ? v::VenationType::open : v::VenationType::closed, 1, 2);
    p.growth = g;
    p.initial_scale = 0.2;
    p.final_scale = 1;
    p.scale_step = 0.02;
    check_leaf(ovate_leaf(30, 20), p);
  }
  v::ColonisationParams p = leaf_params(v::VenationType::closed, 0.5, 1);
  p.node_distance = 0.5;
  p.darts_per_area = 0.3;
  p.growth = v::GrowthMode::nonuniform;
  p.growth_x = {{0, 10}, {1.03, 1.0}};
  p.growth_y = {{0, 10}, {1.01, 1.04}};
  p.growth_steps = 30;
  check_leaf(ovate_leaf(10, 6), p);
}

TEST_CASE("a saved 3-D run continues bit-identically: mesh volume open and closed, surface", "[checkpoint]") {
  v::ColonisationParams p = leaf_params(v::VenationType::open, 1, 2.5);
  p.seed = 5;
  p.darts_per_area = 0.02;
  v::Domain vol;
  vol.kind = v::DomainKind::volume;
  vol.mesh = octahedron(8);
  vol.initial_nodes = {Vec3(0, 0, -8)};
  check_domain(vol, p);
  p.type = v::VenationType::closed;
  check_domain(vol, p);
  v::Domain surf = vol;
  surf.kind = v::DomainKind::surface;
  p.darts_per_area = 0.1;
  check_domain(surf, p);
}

TEST_CASE("a run stopped by max_steps goes on under a larger limit as if never stopped", "[checkpoint]") {
  const v::Leaf leaf = ovate_leaf(30, 20);
  const v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 2);
  v::Colonisation whole(leaf, p);
  whole.run();
  v::ColonisationParams cut = p;
  cut.max_steps = 17;
  v::Colonisation first(leaf, cut);
  first.run();
  REQUIRE(first.report().hit_max_steps);
  v::Colonisation second = v::Colonisation::load(leaf, p, first.save());
  CHECK_FALSE(second.done());
  second.run();
  require_same(whole, second);
  // loaded under the same small limit, it stays done
  CHECK(v::Colonisation::load(leaf, cut, first.save()).done());
}

TEST_CASE("a leaf outgrowing its veins stops at max_sources and goes on under a larger limit as if never stopped",
          "[checkpoint]") {
  const v::Leaf leaf = ovate_leaf(30, 20);
  const v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 2);
  v::Colonisation whole(leaf, p);
  std::size_t peak = 0;  // the most sources waiting after a step of the whole run
  while (!whole.done()) peak = std::max(peak, whole.step().sources);
  REQUIRE(peak > 20);
  v::ColonisationParams cut = p;
  cut.max_sources = peak / 2;
  v::Colonisation first(leaf, cut);
  std::size_t before = 0;  // sources waiting after each step but the last stay below the limit
  while (!first.done()) {
    CHECK(before < cut.max_sources);
    before = first.step().sources;
  }
  REQUIRE(first.report().hit_max_sources);
  CHECK_FALSE(first.report().hit_max_steps);
  // stopped after a step that left the limit waiting, or before one whose darts would pass it (not taken)
  if (first.report().sources_wanted == 0) {
    CHECK(first.report().sources >= cut.max_sources);
  } else {
    CHECK(first.report().sources < cut.max_sources);
    CHECK(first.report().sources_wanted > cut.max_sources);
  }
  CHECK(first.report().sources == first.sources().size());
  v::Colonisation second = v::Colonisation::load(leaf, p, first.save());
  CHECK_FALSE(second.done());
  second.run();
  require_same(whole, second);
  CHECK_FALSE(second.report().hit_max_sources);
  // loaded under the same small limit, it goes no further
  v::Colonisation again = v::Colonisation::load(leaf, cut, first.save());
  again.step();
  CHECK(again.done());
  CHECK(again.report().steps == first.report().steps);
  CHECK(again.report().nodes == first.report().nodes);
}

TEST_CASE("a step whose darts would make more than max_sources wait is not taken, and a larger limit takes it",
          "[checkpoint]") {
  // a blade that does not grow gets all its sources in the first step
  const v::Leaf leaf = ovate_leaf(60, 40);
  v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 2);
  p.growth = v::GrowthMode::none;
  p.darts_per_area = 0.2;
  v::Colonisation whole(leaf, p);
  const std::size_t first_step = whole.step().sources;
  REQUIRE(first_step > 40);
  while (!whole.done()) whole.step();
  v::ColonisationParams cut = p;
  cut.max_sources = first_step / 2;
  v::Colonisation first(leaf, cut);
  const v::ColonisationReport& r = first.step();
  REQUIRE(first.done());
  CHECK(r.hit_max_sources);
  CHECK(r.steps == 0);  // nothing of the step kept: no source, no dart counted, one seed node
  CHECK(r.sources == 0);
  CHECK(first.sources().empty());
  CHECK(r.sources_born == 0);
  CHECK(r.darts == 0);
  CHECK(first.tree().size() == 1);
  CHECK(r.sources_wanted >= first_step);  // an upper bound of what the step would have made wait
  v::Colonisation second = v::Colonisation::load(leaf, p, first.save());
  second.run();
  require_same(whole, second);
}

TEST_CASE("states refuse other parameters or domains, and corrupt bytes", "[checkpoint]") {
  const v::Leaf leaf = ovate_leaf(30, 20);
  const v::ColonisationParams p = leaf_params(v::VenationType::closed, 1, 2);
  v::Colonisation c(leaf, p);
  for (int i = 0; i < 10; ++i) c.step();
  const std::string bytes = c.save();

  v::ColonisationParams other = p;
  other.kill_distance = 1.5;
  CHECK_THROWS_AS(v::Colonisation::load(leaf, other, bytes), core::InvalidInput);
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, other, bytes), Contains("colonisation parameters"));
  other = p;
  other.seed = 43;
  CHECK_THROWS_AS(v::Colonisation::load(leaf, other, bytes), core::InvalidInput);
  other = p;
  other.settle_steps = p.settle_steps + 1;  // when a quiet pattern ends is part of the run
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, other, bytes), Contains("colonisation parameters"));
  CHECK_THROWS_WITH(v::Colonisation::load(ovate_leaf(31, 20), p, bytes), Contains("domain"));
  v::Domain d;
  d.kind = v::DomainKind::ball;
  d.centre = Vec3(0, 0, 0);
  d.radius = 5;
  d.initial_nodes = {Vec3(0, 0, 0)};
  v::ColonisationParams p3 = p;
  CHECK_THROWS_AS(v::Colonisation::load(d, p3, bytes), core::InvalidInput);
  // the same leaf given as a Domain is the same domain
  v::Domain as_domain;
  as_domain.leaf = leaf;
  CHECK(v::Colonisation::load(as_domain, p, bytes).report().steps == 10);

  std::string bad = bytes;
  bad[bad.size() / 2] ^= 0x10;
  CHECK_THROWS_AS(v::Colonisation::load(leaf, p, bad, "state X"), core::FileError);
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, p, bad, "state X"), Contains("state X"));
  CHECK_THROWS_AS(v::Colonisation::load(leaf, p, bytes.substr(0, bytes.size() - 9)), core::FileError);
  CHECK_THROWS_AS(v::Colonisation::load(leaf, p, "not a state"), core::FileError);
  // a node that is no number, in a state whose checksum was made to match, is refused too
  core::ChunkFile f = core::read_chunk_file(bytes, "COLO", 6, "state");
  std::string& state = f.chunks.at("state");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE(state.size() > 16);
  std::memcpy(state.data() + 8, &nan, sizeof nan);  // after the node count: the first node's x
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, p, core::write_chunk_file("COLO", f.version, f.chunks)),
                    Contains("no number"));
}

TEST_CASE(
    "a marginal-growth state of format 2 (whole-blade darts) is refused; other version-2 states load; format 1 is "
    "refused",
    "[checkpoint]") {
  // format 3 changed what marginal growth does, not the bytes: relabel a state as version 2
  auto as_version_2 = [](const v::Colonisation& c) { return as_version(c, 2); };
  const v::Leaf leaf = ovate_leaf(30, 20);
  v::ColonisationParams p = leaf_params(v::VenationType::open, 1, 2);
  p.growth = v::GrowthMode::marginal;
  p.initial_scale = 0.5;
  p.final_scale = 1;
  p.scale_step = 0.05;
  v::Colonisation c(leaf, p);
  for (int i = 0; i < 3; ++i) c.step();
  CHECK_THROWS_AS(v::Colonisation::load(leaf, p, as_version_2(c), "old state"), core::FileError);
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, p, as_version_2(c), "old state"),
                    Contains("old state") && Contains("whole blade"));
  p.growth = v::GrowthMode::uniform;
  v::Colonisation u(leaf, p);
  for (int i = 0; i < 3; ++i) u.step();
  CHECK(v::Colonisation::load(leaf, p, as_version_2(u)).report().steps == 3);
  // format 1 had no Urquhart cells in its state: refused with its version, not read as garbage
  const std::string v1 = as_version(u, 1);
  CHECK_THROWS_AS(v::Colonisation::load(leaf, p, v1, "old state"), core::FileError);
  CHECK_THROWS_WITH(v::Colonisation::load(leaf, p, v1, "old state"),
                    Contains("old state") && Contains("format version 1") && Contains("run the script again"));
}
