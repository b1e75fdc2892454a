// Tests of export/mesh_clean.h: micrometre edges collapse, and the mesh stays a closed, oriented manifold
// of the same genus and nearly the same volume; collapses that would change its kind are refused.
#include "export/mesh_clean.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "export/mesh_check.h"
#include "tests/export/mesh_fixtures.h"

using namespace cellform;
using namespace cellform::testing;
using core::Vec3;
using exporters::PrintableMesh;

namespace {

/// Splits edge (a, b), shared by two triangles, at a + f (b - a): the four triangles that replace the two
/// keep their winding. As a mesher's corner vertex does, it leaves an edge of f |b - a|.
void split_edge(PrintableMesh& m, std::uint32_t a, std::uint32_t b, double f) {
  const auto p = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back(m.vertices[a] + f * (m.vertices[b] - m.vertices[a]));
  const std::size_t n = m.triangles.size();
  int split = 0;
  for (std::size_t t = 0; t < n; ++t) {
    auto& tri = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = tri[k], v = tri[(k + 1) % 3], w = tri[(k + 2) % 3];
      if (!((u == a && v == b) || (u == b && v == a))) continue;
      tri = {u, p, w};
      m.triangles.push_back({p, v, w});
      ++split;
      break;
    }
  }
  REQUIRE(split == 2);
}

double shortest_edge(const PrintableMesh& m) {
  double s = INFINITY;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) s = std::min(s, (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm());
  return s;
}

}  // namespace

TEST_CASE("micrometre edges collapse and the torus stays a closed oriented manifold of genus 1", "[mesh_clean]") {
  PrintableMesh m = torus(24, 12);
  const exporters::MeshReport before = exporters::check_mesh(m);
  const std::size_t triangles = m.triangles.size();
  // ten edges far apart, each split 1e-4 of its length from one end
  for (int i = 0; i < 10; ++i) {
    const auto a = static_cast<std::uint32_t>(i * 2 * 12 + 3), b = static_cast<std::uint32_t>(a + 12);
    split_edge(m, a, b, 1e-4);
  }
  REQUIRE(m.triangles.size() == triangles + 20);
  REQUIRE(shortest_edge(m) < 1e-3);
  CHECK(exporters::collapse_short_edges(m, 1e-2) == 10);
  CHECK(m.triangles.size() == triangles);
  CHECK(m.vertices.size() == before.vertices);
  CHECK(shortest_edge(m) > 1e-2);
  const exporters::MeshReport after = exporters::check_mesh(m);
  CHECK(after.printable());
  CHECK(after.closed_manifold());
  CHECK(after.consistently_oriented);
  CHECK(after.self_intersections == 0);
  CHECK(after.genus == before.genus);
  CHECK(after.volume == Approx(before.volume).epsilon(1e-6));
  // nothing left to do: a second call changes nothing
  const PrintableMesh again = m;
  CHECK(exporters::collapse_short_edges(m, 1e-2) == 0);
  CHECK(m.triangles == again.triangles);
}

TEST_CASE("collapses that would change the mesh's kind are refused", "[mesh_clean]") {
  // a tiny tetrahedron: every edge is short, but a collapse would leave two triangles back to back
  PrintableMesh tet = tetrahedron(Vec3::Zero(), 1e-6);
  const PrintableMesh copy = tet;
  CHECK(exporters::collapse_short_edges(tet, 1e-3) == 0);
  CHECK(tet.triangles == copy.triangles);
  CHECK(tet.vertices == copy.vertices);
  // an open edge (a sheet's rim) is not collapsed: only edges of two triangles
  PrintableMesh sheet;
  sheet.vertices = {Vec3(0, 0, 0), Vec3(1e-6, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  sheet.triangles = {{0, 1, 2}, {1, 3, 2}};
  CHECK(exporters::collapse_short_edges(sheet, 1e-3) == 0);
  // a triangle that repeats a corner: the mesh is left as it is
  PrintableMesh torn = torus(8, 6);
  split_edge(torn, 0, 6, 1e-5);
  torn.triangles.push_back({1, 2, 2});
  CHECK(exporters::collapse_short_edges(torn, 1e-2) == 0);
  // a vertex whose triangles form two fans (two tetrahedra meeting at a corner) is left alone
  PrintableMesh pair = tetrahedron(Vec3::Zero(), 1);
  append(pair, tetrahedron(Vec3::Zero(), -1));
  for (auto& t : pair.triangles)
    for (auto& i : t)
      if (i == 4) i = 0;  // the second one's corner is the first one's
  split_edge(pair, 0, 1, 1e-7);
  REQUIRE(exporters::check_mesh(pair).nonmanifold_vertices == 1);
  const PrintableMesh pair_copy = pair;
  CHECK(exporters::collapse_short_edges(pair, 1e-3) == 0);
  CHECK(pair.triangles == pair_copy.triangles);
}
