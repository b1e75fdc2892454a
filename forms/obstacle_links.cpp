// Whether the links of the cells cross a mesh obstacle: a mesh cut through the starting cells (forms/obstacles.h).
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/parallel.h"
#include "forms/obstacles.h"

namespace cellform::forms {

using core::InvalidInput;

namespace {

// The lowest index of a mesh that the segment from `a` to `b` crosses an odd number of times: its ends lie on the
// two sides of it. All crossings are found along the segment itself (no stepping from one to the next, which lost
// its way far from the origin); per mesh, crossings within a millionth of the segment of each other count once:
// the two triangles of an edge it passes through, a vertex's fan.
std::optional<std::size_t> mesh_between(const PreparedObstacles& obstacles, const Vec3& a, const Vec3& b,
                                        std::vector<std::pair<double, std::size_t>>& hits) {
  constexpr double kSame = 1e-6;
  obstacles.mesh_crossings(a, b, hits);
  std::sort(hits.begin(), hits.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second < y.second : x.first < y.first;
  });
  for (std::size_t k = 0; k < hits.size();) {
    std::size_t count = 0, end = k;
    for (double last = -1; end < hits.size() && hits[end].second == hits[k].second; last = hits[end++].first)
      if (hits[end].first - last > kSame) ++count;
    if (count % 2 == 1) return hits[k].second;
    k = end;
  }
  return std::nullopt;
}

}  // namespace

void check_links_clear(const PreparedObstacles& obstacles, const cells::Cells& cells, const ObstacleNames& names,
                       int threads) {
  const std::size_t n = cells.size(), k = static_cast<std::size_t>(std::max(cells.link_stride, 0));
  if (obstacles.obstacles().meshes.empty() || k == 0 || cells.links.size() != n * k) return;
  constexpr std::uint32_t kClear = ~std::uint32_t{0};
  std::vector<std::uint32_t> crossed(n * k, kClear);  // per link slot: the mesh it crosses first
  core::parallel_for(n, threads, [&](std::size_t first, std::size_t last) {
    std::vector<std::pair<double, std::size_t>> hits;  // (scratch of mesh_between)
    for (std::size_t i = first; i < last; ++i)
      for (std::size_t s = 0; s < k; ++s) {
        const std::size_t j = cells.links[i * k + s];
        if (j >= n) continue;
        const auto row = cells.links.begin() + static_cast<std::ptrdiff_t>(j * k);
        if (j < i && std::find(row, row + static_cast<std::ptrdiff_t>(k), static_cast<Index>(i)) != row + k)
          continue;  // a mutual link, tested from j
        if (const auto m = mesh_between(obstacles, cells.position[i], cells.position[j], hits))
          crossed[i * k + s] = static_cast<std::uint32_t>(*m);
      }
  });
  for (std::size_t m = 0; m < obstacles.obstacles().meshes.size(); ++m) {
    const auto first = std::find(crossed.begin(), crossed.end(), static_cast<std::uint32_t>(m));
    if (first == crossed.end()) continue;
    const auto count = std::count(first, crossed.end(), static_cast<std::uint32_t>(m));
    const auto slot = static_cast<std::size_t>(first - crossed.begin());
    const Vec3 &a = cells.position[slot / k], &b = cells.position[cells.links[slot]];
    const std::string name = m < names.meshes.size() ? names.meshes[m] : "mesh " + std::to_string(m);
    throw InvalidInput(name + ": " + std::to_string(count) + (count == 1 ? " link" : " links") +
                       " between neighbouring cells " + (count == 1 ? "crosses" : "cross") + " it (the first from " +
                       core::point_text(a.x(), a.y(), a.z()) + " to " + core::point_text(b.x(), b.y(), b.z()) +
                       "): neighbours on the two sides of a mesh are pulled onto it from both and grow through its "
                       "edges; obstacles must start clear of the cells, with all of them on one side of each mesh "
                       "(inside a mould, or beside a wall)");
  }
}

}  // namespace cellform::forms
