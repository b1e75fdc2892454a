// The seeded random streams: the quick stream gives exactly the numbers of the standard engine.
#include <catch2/catch.hpp>

#include <initializer_list>
#include <random>

#include "core/random.h"

using namespace cellform::core;

TEST_CASE("StreamRng gives the numbers of std::mt19937_64, before and after its quick part", "[random]") {
  for (const std::uint64_t seed :
       std::initializer_list<std::uint64_t>{0, 1, 5489, 0x8000000000000000ull, ~0ull, stream_key(7, 3, 11)}) {
    std::mt19937_64 reference(seed);
    StreamRng quick(seed);
    for (int k = 0; k < 100; ++k) {  // 16 from the partial state, then the engine advanced past them
      INFO("seed " << seed << ", number " << k);
      REQUIRE(quick.next() == reference());
    }
  }
}

TEST_CASE("StreamRng's uniform numbers and unit vectors equal Rng's", "[random]") {
  for (std::uint64_t id = 0; id < 200; ++id) {
    const std::uint64_t key = stream_key(42, 9, id);
    Rng full(key);
    StreamRng quick(key);
    REQUIRE(quick.uniform() == full.uniform());
    REQUIRE(quick.uniform(-2, 3) == full.uniform(-2, 3));
    const Vec3 a = quick.unit_vector(), b = full.unit_vector();
    REQUIRE(a == b);
    REQUIRE(a.norm() == Approx(1.0));
  }
}
