// PointGrid against a brute-force oracle: nearest (with ties), within and count_within.
#include "core/spatial_index.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <span>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/random.h"

using cellform::core::Index;
using cellform::core::kNoIndex;
using cellform::core::PointGrid;
using cellform::core::Rng;
using cellform::core::Vec3;

namespace {

std::vector<std::pair<double, Index>> oracle(const std::vector<Vec3>& pts, const Vec3& q, Index self) {
  std::vector<std::pair<double, Index>> all;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (static_cast<Index>(i) != self) all.push_back({(pts[i] - q).squaredNorm(), static_cast<Index>(i)});
  std::sort(all.begin(), all.end());
  return all;
}

void check_nearest(const std::vector<Vec3>& pts, double cell, int k) {
  PointGrid grid;
  grid.build(pts, cell);
  std::vector<Index> idx(static_cast<std::size_t>(k));
  std::vector<double> d2(static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto self = static_cast<Index>(i);
    const auto expected = oracle(pts, pts[i], self);
    const int found = grid.nearest(pts[i], self, k, idx.data(), d2.data());
    REQUIRE(found == static_cast<int>(std::min<std::size_t>(expected.size(), static_cast<std::size_t>(k))));
    for (int j = 0; j < found; ++j) {
      INFO("query " << i << " rank " << j);
      REQUIRE(idx[j] == expected[j].second);
      REQUIRE(d2[j] == expected[j].first);
      REQUIRE(idx[j] != self);
    }
  }
}

std::vector<Vec3> random_cloud(std::uint64_t seed, std::size_t n, double extent) {
  Rng rng(seed);
  std::vector<Vec3> pts(n);
  for (auto& p : pts)
    p = Vec3(rng.uniform(-extent, extent), rng.uniform(-extent, extent), rng.uniform(-extent, extent));
  return pts;
}

}  // namespace

TEST_CASE("nearest equals the brute-force oracle on random clouds", "[spatial_index]") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    check_nearest(random_cloud(seed, 800, 5.0), 1.0, 6);
    check_nearest(random_cloud(seed + 10, 500, 5.0), 0.3, 12);  // many shells needed
    check_nearest(random_cloud(seed + 20, 300, 50.0), 1.0, 7);  // sparse: brute-force fallback
  }
}

TEST_CASE("nearest breaks exact distance ties by index", "[spatial_index]") {
  std::vector<Vec3> pts;
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y)
      for (int z = -1; z <= 1; ++z) pts.emplace_back(x, y, z);
  // shuffle deterministically so index order differs from position order
  Rng rng(7);
  for (std::size_t i = pts.size() - 1; i > 0; --i) std::swap(pts[i], pts[rng.next() % (i + 1)]);
  check_nearest(pts, 1.0, 6);
  check_nearest(pts, 1.0, 13);
  check_nearest(pts, 0.5, 8);
  check_nearest(pts, 2.0, 20);
}

TEST_CASE("nearest with fewer points than k returns all of them", "[spatial_index]") {
  const std::vector<Vec3> pts = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 3, 0)};
  check_nearest(pts, 1.0, 6);
  PointGrid grid;
  grid.build(pts, 1.0);
  Index idx[6];
  double d2[6];
  REQUIRE(grid.nearest(Vec3(0.1, 0, 0), kNoIndex, 6, idx, d2) == 3);
  REQUIRE(idx[0] == 0);
  REQUIRE(idx[1] == 1);
  REQUIRE(idx[2] == 2);
  const std::vector<Vec3> single = {Vec3(1, 1, 1)};
  grid.build(single, 1.0);
  REQUIRE(grid.nearest(single[0], 0, 6, idx, d2) == 0);
}

TEST_CASE("nearest without self exclusion finds the point itself first", "[spatial_index]") {
  const auto pts = random_cloud(11, 200, 3.0);
  PointGrid grid;
  grid.build(pts, 1.0);
  Index idx[4];
  double d2[4];
  for (std::size_t i = 0; i < pts.size(); ++i) {
    REQUIRE(grid.nearest(pts[i], kNoIndex, 4, idx, d2) == 4);
    REQUIRE(idx[0] == i);
    REQUIRE(d2[0] == 0.0);
  }
}

namespace {

/// within() and count_within() (also with limits) of every `step`-th point against a brute-force scan:
/// the same points, none twice.
void check_within(const PointGrid& grid, const std::vector<Vec3>& pts, double radius, std::size_t step) {
  std::vector<Index> got;
  for (std::size_t i = 0; i < pts.size(); i += step) {
    const auto self = static_cast<Index>(i);
    std::vector<Index> expected;
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (j != i && (pts[j] - pts[i]).squaredNorm() <= radius * radius) expected.push_back(static_cast<Index>(j));
    got.clear();
    grid.within(pts[i], radius, self, got);
    std::sort(got.begin(), got.end());
    INFO("point " << i << ", radius " << radius);
    REQUIRE(got == expected);
    REQUIRE(grid.count_within(pts[i], radius, self) == static_cast<int>(expected.size()));
    for (int limit : {0, 1, 5, 8})  // a count stops at its limit
      REQUIRE(grid.count_within(pts[i], radius, self, limit) == std::min(limit, static_cast<int>(expected.size())));
  }
}

}  // namespace

TEST_CASE("within and count_within equal brute force", "[spatial_index]") {
  const auto pts = random_cloud(5, 1000, 4.0);
  PointGrid grid;
  grid.build(pts, 0.7);
  for (double radius : {0.0, 0.5, 1.5, 3.0, 100.0}) check_within(grid, pts, radius, 7);
}

TEST_CASE("within and count_within are exact and see each point once in the hashed layout", "[spatial_index]") {
  // two far clusters make the grid hashed: grid cells of both share buckets, and a radius query spans many
  auto pts = random_cloud(11, 600, 4.0);
  for (const Vec3& p : random_cloud(12, 600, 4.0)) pts.push_back(p + Vec3(1e5, 0, 0));
  PointGrid grid;
  grid.build(pts, 0.5);
  REQUIRE_FALSE(grid.dense());
  for (double radius : {0.7, 2.0, 6.0}) check_within(grid, pts, radius, 13);
}

TEST_CASE("within counts a point exactly at the radius across a grid-cell boundary", "[spatial_index]") {
  // q + radius rounds below p.x, which lies in the next grid cell, yet |p - q|^2 == radius^2 exactly
  const double qx = 0.07217818566878155, px = 0.22007173913148523, radius = 0.14789355346270366;
  const std::vector<Vec3> pts{Vec3(px, 0, 0)};
  REQUIRE((pts[0] - Vec3(qx, 0, 0)).squaredNorm() == radius * radius);
  PointGrid grid;
  grid.build(pts, 0.44014347826297051);
  CHECK(grid.count_within(Vec3(qx, 0, 0), radius, kNoIndex) == 1);
}

TEST_CASE("within counts points exactly at the radius on a lattice", "[spatial_index]") {
  std::vector<Vec3> pts;
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y) pts.emplace_back(x, y, 0);
  PointGrid grid;
  grid.build(pts, 1.0);
  REQUIRE(grid.count_within(Vec3(0, 0, 0), 1.0, 12) == 4);  // index 12 is the centre
  REQUIRE(grid.count_within(Vec3(0, 0, 0), 1.0, kNoIndex) == 5);
}

TEST_CASE("build rejects a bad cell size", "[spatial_index]") {
  PointGrid grid;
  const std::vector<Vec3> pts = {Vec3::Zero()};
  REQUIRE_THROWS_AS(grid.build(pts, 0.0), cellform::core::InvalidInput);
  REQUIRE_THROWS_AS(grid.build(pts, -1.0), cellform::core::InvalidInput);
}

TEST_CASE("spatial_order is a permutation", "[spatial_index]") {
  const auto pts = random_cloud(9, 500, 10.0);
  auto perm = cellform::core::spatial_order(pts, 1.0);
  std::sort(perm.begin(), perm.end());
  for (std::size_t i = 0; i < perm.size(); ++i) REQUIRE(perm[i] == i);
}

TEST_CASE("nearest_all equals nearest for every point, for any thread count", "[spatial_index]") {
  std::vector<std::vector<Vec3>> clouds = {random_cloud(21, 6000, 12.0), random_cloud(22, 400, 60.0)};
  std::vector<Vec3> lattice;  // a flat lattice on grid planes: exact ties everywhere
  for (int x = 0; x < 90; ++x)
    for (int y = 0; y < 60; ++y) lattice.emplace_back(x, y, 0);
  clouds.push_back(lattice);
  std::vector<Vec3> clustered = random_cloud(23, 3000, 0.5);              // crowded cells: capacity fallback
  for (int i = 0; i < 50; ++i) clustered.push_back(Vec3(100 + i, 0, 0));  // isolated chain: far fallback
  clouds.push_back(clustered);
  for (const auto& pts : clouds) {
    // oracle: the 11 nearest of every point (partial sort keeps this linear per point)
    std::vector<std::vector<std::pair<double, Index>>> best(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      std::vector<std::pair<double, Index>> all;
      all.reserve(pts.size());
      for (std::size_t j = 0; j < pts.size(); ++j)
        if (j != i) all.push_back({(pts[j] - pts[i]).squaredNorm(), static_cast<Index>(j)});
      const std::size_t keep = std::min<std::size_t>(11, all.size());
      std::partial_sort(all.begin(), all.begin() + static_cast<long>(keep), all.end());
      all.resize(keep);
      best[i] = std::move(all);
    }
    for (double cell : {0.5, 1.0, 1.5}) {
      for (int k : {3, 6, 11}) {
        PointGrid grid;
        grid.build(pts, cell);
        std::vector<Index> one(pts.size() * static_cast<std::size_t>(k)), two(pts.size() * static_cast<std::size_t>(k));
        grid.nearest_all(k, one.data(), 1);
        grid.nearest_all(k, two.data(), 2);
        REQUIRE(one == two);
        for (std::size_t i = 0; i < pts.size(); ++i) {
          const auto& expected = best[i];
          for (int j = 0; j < k; ++j) {
            const Index want = static_cast<std::size_t>(j) < expected.size() ? expected[j].second : kNoIndex;
            if (one[i * static_cast<std::size_t>(k) + j] != want) {
              INFO("cloud of " << pts.size() << ", cell " << cell << ", k " << k << ", point " << i << ", rank " << j);
              REQUIRE(one[i * static_cast<std::size_t>(k) + j] == want);
            }
          }
        }
      }
    }
  }
}

TEST_CASE("spatial_order tolerates non-finite points", "[spatial_index]") {
  std::vector<Vec3> pts = random_cloud(3, 100, 5.0);
  pts[10] = Vec3(NAN, 0, 0);
  pts[20] = Vec3(INFINITY, 1, 1);
  auto perm = cellform::core::spatial_order(pts, 1.0);
  REQUIRE((perm[98] == 10 || perm[99] == 10));
  std::sort(perm.begin(), perm.end());
  for (std::size_t i = 0; i < perm.size(); ++i) REQUIRE(perm[i] == i);
}

TEST_CASE("nearest_all with a hint equals the oracle for good, stale and invalid hints", "[spatial_index]") {
  std::vector<Vec3> pts;  // a jittered sheet (the dense layout) with a far cluster (a sparse box: hashed)
  Rng rng(31);
  for (int x = 0; x < 60; ++x)
    for (int y = 0; y < 50; ++y)
      pts.emplace_back(x + 0.1 * rng.uniform(-1, 1), y + 0.1 * rng.uniform(-1, 1), 0.05 * rng.uniform(-1, 1));
  const std::size_t sheet = pts.size();
  const int k = 6;
  const auto stride = static_cast<std::size_t>(k);
  for (double cell : {0.7, 1.0, 1.5}) {
    PointGrid grid;
    grid.build(std::span<const Vec3>(pts.data(), sheet), cell);
    REQUIRE(grid.dense());
    std::vector<Index> plain(sheet * stride), hinted(sheet * stride);
    grid.nearest_all(k, plain.data(), 1);
    for (std::size_t i = 0; i < sheet; ++i) {  // nearest_all without a hint is checked against nearest above
      std::vector<Index> idx(stride);
      std::vector<double> d2(stride);
      grid.nearest(pts[i], static_cast<Index>(i), k, idx.data(), d2.data());
      REQUIRE(std::equal(idx.begin(), idx.end(), plain.begin() + static_cast<long>(i * stride)));
    }
    // exact hint, in place (hint == out)
    hinted = plain;
    grid.nearest_all(k, hinted.data(), 2, hinted.data());
    REQUIRE(hinted == plain);
    // stale hints: rows of other points, shuffled rows, repeats, self, kNoIndex, out of range
    for (int variant = 0; variant < 5; ++variant) {
      std::vector<Index> hint(sheet * stride);
      for (std::size_t i = 0; i < sheet; ++i)
        for (std::size_t j = 0; j < stride; ++j) {
          Index h = plain[((i + 7 * static_cast<std::size_t>(variant)) % sheet) * stride + (j * 5 + 1) % stride];
          if (variant == 1 && j > 0) h = plain[i * stride];                     // repeats of the nearest
          if (variant == 2 && j == 3) h = static_cast<Index>(i);                // itself
          if (variant == 3 && j == 5) h = kNoIndex;                             // padding
          if (variant == 4) h = static_cast<Index>((i + j * 977 + 1) % sheet);  // far away
          hint[i * stride + j] = h;
        }
      std::vector<Index> got(sheet * stride);
      grid.nearest_all(k, got.data(), 2, hint.data());
      INFO("cell " << cell << ", hint variant " << variant);
      REQUIRE(got == plain);
    }
  }
  // a sparse set is hashed; the hint is then ignored but harmless
  for (int i = 0; i < 40; ++i) pts.emplace_back(1e4 + i, 0, 0);
  PointGrid grid;
  grid.build(pts, 1.0);
  REQUIRE_FALSE(grid.dense());
  std::vector<Index> plain(pts.size() * stride), hinted(pts.size() * stride, 0);
  grid.nearest_all(k, plain.data(), 1);
  grid.nearest_all(k, hinted.data(), 2, hinted.data());
  REQUIRE(hinted == plain);
}
