// Short-edge collapse on an indexed triangle mesh (see mesh_clean.h).
#include "export/mesh_clean.h"

#include <algorithm>
#include <numeric>
#include <tuple>
#include <vector>

namespace cellform::exporters {

using core::Vec3;

namespace {

Vec3 normal_of(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

/// One round: collapses short edges whose one-rings no earlier collapse of the round touched.
std::size_t collapse_round(PrintableMesh& mesh, double min2) {
  const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
  auto& tris = mesh.triangles;
  auto& pos = mesh.vertices;
  std::vector<std::tuple<double, std::uint32_t, std::uint32_t>> cand;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
      const double l2 = (pos[a] - pos[b]).squaredNorm();
      if (l2 < min2) cand.emplace_back(l2, a, b);
    }
  if (cand.empty()) return 0;  // (most meshes, after a round or two: no adjacency to build)
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  // the triangles around each vertex: around[start[v]] .. around[start[v + 1] - 1]
  std::vector<std::uint32_t> start(nv + 1, 0), around(3 * nt);
  for (const auto& t : tris)
    for (const std::uint32_t i : t) ++start[i + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
      for (const std::uint32_t i : tris[t]) around[fill[i]++] = static_cast<std::uint32_t>(t);
  }

  std::vector<char> locked(nv, 0), dead(nt, 0);
  std::vector<std::uint32_t> ring_a, ring_b;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> fan;
  // the vertices around v other than v, sorted; false unless v is a manifold vertex of a closed, oriented
  // mesh: its triangles (v, p, q) chain p -> q into one cycle through all of them
  auto ring = [&](std::uint32_t v, std::vector<std::uint32_t>& out) {
    out.clear();
    fan.clear();
    for (std::uint32_t s = start[v]; s < start[v + 1]; ++s) {
      const auto& t = tris[around[s]];
      const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
      fan.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
      out.push_back(t[(k + 1) % 3]);
    }
    std::sort(fan.begin(), fan.end());
    std::sort(out.begin(), out.end());
    if (std::adjacent_find(out.begin(), out.end()) != out.end()) return false;  // a p twice: no single cycle
    std::uint32_t at = fan.front().first;
    for (std::size_t k = 0; k < fan.size(); ++k) {  // follow p -> q; back at the start after exactly all
      const auto it = std::lower_bound(fan.begin(), fan.end(), std::make_pair(at, std::uint32_t{0}));
      if (it == fan.end() || it->first != at) return false;
      at = it->second;
      if (at == fan.front().first && k + 1 < fan.size()) return false;
    }
    return at == fan.front().first;
  };
  std::size_t done = 0;
  for (const auto& [l2, a, b] : cand) {
    if (locked[a] || locked[b]) continue;
    std::uint32_t shared[2], opposite[2], n_shared = 0;
    for (std::uint32_t s = start[a]; s < start[a + 1]; ++s) {
      const auto& t = tris[around[s]];
      if (t[0] != b && t[1] != b && t[2] != b) continue;
      if (n_shared == 2) {
        n_shared = 3;
        break;
      }
      shared[n_shared] = around[s];
      for (const std::uint32_t i : t)
        if (i != a && i != b) opposite[n_shared] = i;
      ++n_shared;
    }
    if (n_shared != 2 || opposite[0] == opposite[1]) continue;
    if (!ring(a, ring_a) || !ring(b, ring_b)) continue;
    std::vector<std::uint32_t> common;
    std::set_intersection(ring_a.begin(), ring_a.end(), ring_b.begin(), ring_b.end(), std::back_inserter(common));
    if (common.size() != 2 || !std::binary_search(common.begin(), common.end(), opposite[0]) ||
        !std::binary_search(common.begin(), common.end(), opposite[1]))
      continue;
    if (start[opposite[0] + 1] - start[opposite[0]] <= 3 || start[opposite[1] + 1] - start[opposite[1]] <= 3) continue;
    const Vec3 mid = 0.5 * (pos[a] + pos[b]);
    bool turns = false;
    for (const std::uint32_t v : {a, b})
      for (std::uint32_t s = start[v]; s < start[v + 1] && !turns; ++s) {
        const std::uint32_t t = around[s];
        if (t == shared[0] || t == shared[1]) continue;
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = tris[t][k] == v ? mid : pos[tris[t][k]];
        const Vec3 before = normal_of(pos[tris[t][0]], pos[tris[t][1]], pos[tris[t][2]]);
        const Vec3 after = normal_of(p[0], p[1], p[2]);
        turns = !(after.dot(before) > 0) || !(after.squaredNorm() > 0);
      }
    if (turns) continue;
    pos[a] = mid;
    for (std::uint32_t s = start[b]; s < start[b + 1]; ++s)
      for (std::uint32_t& i : tris[around[s]])
        if (i == b) i = a;
    dead[shared[0]] = dead[shared[1]] = 1;
    for (const std::uint32_t v : ring_a) locked[v] = 1;
    for (const std::uint32_t v : ring_b) locked[v] = 1;
    locked[a] = locked[b] = 1;
    ++done;
  }
  std::size_t w = 0;
  for (std::size_t t = 0; t < nt; ++t)
    if (!dead[t]) tris[w++] = tris[t];
  tris.resize(w);
  return done;
}

}  // namespace

std::size_t collapse_short_edges(PrintableMesh& mesh, double min_length) {
  if (!(min_length > 0)) return 0;
  for (const auto& t : mesh.triangles)  // a triangle with a repeated corner: not a mesh this is for
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return 0;
  std::size_t total = 0;
  for (int round = 0; round < 8; ++round) {
    const std::size_t n = collapse_round(mesh, min_length * min_length);
    total += n;
    if (n == 0) break;
  }
  if (total > 0) drop_unused_vertices(mesh);
  return total;
}

void drop_unused_vertices(PrintableMesh& mesh) {
  std::vector<std::uint32_t> index(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles)
    for (const std::uint32_t i : t) index[i] = 1;
  std::uint32_t next = 0;
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (!index[v]) continue;
    mesh.vertices[next] = mesh.vertices[v];
    index[v] = next++;
  }
  mesh.vertices.resize(next);
  for (auto& t : mesh.triangles)
    for (std::uint32_t& i : t) i = index[i];
}

}  // namespace cellform::exporters
