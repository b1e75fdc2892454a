// Helpers shared by the tests of the printable solid (printable_test.cpp, printable_shell_test.cpp).
#pragma once

#include <array>
#include <catch2/catch.hpp>
#include <vector>

#include "export/mesh_check.h"
#include "export/printable.h"

namespace cellform::testing {

/// Shell triangles as the thickening takes them.
using Shell = std::vector<std::array<core::Vec3, 3>>;

/// 1 mm per model unit, a fine voxel, no radius raising: geometry as given.
inline exporters::ThickenParams exact(double voxel = 0.05) {
  exporters::ThickenParams p;
  p.scale = 1;
  p.voxel_size = voxel;
  p.min_radius = voxel;
  p.adaptivity = 0;
  return p;
}

/// check_mesh's report of `m`, checking that it is printable: closed, manifold, outward, no crossings.
inline exporters::MeshReport require_printable(const exporters::PrintableMesh& m) {
  const auto r = exporters::check_mesh(m);
  INFO(r.summary());
  CHECK(r.printable());
  CHECK(r.boundary_edges == 0);
  CHECK(r.nonmanifold_edges == 0);
  CHECK(r.nonmanifold_vertices == 0);
  CHECK(r.consistently_oriented);
  CHECK(r.self_intersections == 0);
  CHECK(r.volume > 0);
  return r;
}

}  // namespace cellform::testing
