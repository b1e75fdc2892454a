// The private tests of the one-layer surface (cells/surface_detail.h) against brute force.
#include "cells/surface_detail.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/random.h"

using namespace cellform::cells;

TEST_CASE("diagonals_cross: closest points inside both segments, nearer than a quarter of the shorter", "[surface]") {
  // pairs of segments of unequal lengths crossing near their middles at random heights over each other; the
  // closest points by a grid search over both parameters (then a finer one round the best), away from the
  // rule's edges (parameters near 0.02 or 0.98, a gap near the threshold), where the grid could err
  cellform::core::Rng rng(11);
  int crossing = 0, apart = 0, between = 0, checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 u = rng.unit_vector(), v = rng.unit_vector();
    const double l1 = rng.uniform(0.5, 2), l2 = l1 * rng.uniform(0.3, 3), a1 = rng.uniform(-0.2, 1.2),
                 a2 = rng.uniform(-0.2, 1.2);
    const Vec3 p = c - a1 * l1 * u, q = p + l1 * u;
    const Vec3 r = c + rng.uniform(0, 0.8) * std::min(l1, l2) * rng.unit_vector() - a2 * l2 * v, s = r + l2 * v;
    const auto gap2 = [&](double t1, double t2) { return (p + t1 * (q - p) - (r + t2 * (s - r))).squaredNorm(); };
    double b1 = 0, b2 = 0, best = gap2(0, 0);
    for (int i = 0; i <= 100; ++i)
      for (int j = 0; j <= 100; ++j)
        if (gap2(i / 100.0, j / 100.0) < best) best = gap2(b1 = i / 100.0, b2 = j / 100.0);
    // then finer, each level repeated while it moves (a narrow valley can lead far from the coarse best)
    for (const double step : {1e-3, 1e-4, 1e-5})
      for (bool moved = true; moved;) {
        moved = false;
        const double c1 = b1, c2 = b2;
        for (int i = -20; i <= 20; ++i)
          for (int j = -20; j <= 20; ++j) {
            const double t1 = std::clamp(c1 + i * step, 0.0, 1.0), t2 = std::clamp(c2 + j * step, 0.0, 1.0);
            if (gap2(t1, t2) < best) {
              best = gap2(b1 = t1, b2 = t2);
              moved = true;
            }
          }
      }
    const double shorter2 = std::min(l1, l2) * std::min(l1, l2), longer2 = std::max(l1, l2) * std::max(l1, l2);
    const auto near = [](double t, double edge) { return std::abs(t - edge) < 0.002; };
    if (near(b1, 0.02) || near(b1, 0.98) || near(b2, 0.02) || near(b2, 0.98) ||
        std::abs(best - shorter2 / 16) < 0.02 * shorter2)
      continue;
    const bool inside = b1 > 0.02 && b1 < 0.98 && b2 > 0.02 && b2 < 0.98;  // (the square's minimum is the lines'
    const bool expected = inside && best < shorter2 / 16;                  // when it lies inside it)
    ++checked;
    crossing += expected;
    apart += !expected;
    between += inside && best > shorter2 / 16 && best < longer2 / 16;  // crossing by the longer's measure only
    INFO("trial " << trial << ": t = " << b1 << ", " << b2 << ", gap^2 " << best << ", shorter^2 " << shorter2);
    REQUIRE(detail::diagonals_cross(p, q, r, s) == expected);
    REQUIRE(detail::diagonals_cross(r, s, p, q) == expected);  // either way round
  }
  CHECK(checked > 2000);
  CHECK(crossing > 200);
  CHECK(apart > 200);
  CHECK(between > 100);
  // parallel segments never cross, however near
  CHECK_FALSE(detail::diagonals_cross(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0.01, 0), Vec3(1, 0.01, 0)));
}
