// Meshes whose defects, genus and intersections are known by construction, shared by the tests of the mesh
// checks (mesh_check_test.cpp, self_intersection_test.cpp).
#pragma once

#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/triangle_intersection.h"
#include "export/mesh_check.h"

namespace cellform::testing {

using core::Vec3;
using exporters::PrintableMesh;
namespace fs = std::filesystem;

inline fs::path temp_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("cellform-meshcheck-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Every pair of triangles that meet other than along a side they share (no grid): the oracle. Pairs sharing
/// no vertex by triangles_intersect(), pairs round one shared corner by triangles_cross_beyond_corner().
inline std::vector<std::array<std::uint32_t, 2>> every_pair(const PrintableMesh& m) {
  std::vector<std::array<std::uint32_t, 2>> all;
  const auto corners = [&](std::uint32_t t) {
    return std::array<Vec3, 3>{m.vertices[m.triangles[t][0]], m.vertices[m.triangles[t][1]],
                               m.vertices[m.triangles[t][2]]};
  };
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i)
    for (std::uint32_t j = i + 1; j < m.triangles.size(); ++j) {
      int shared = 0, at_i = 0, at_j = 0;
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
          if (m.triangles[i][p] == m.triangles[j][q]) ++shared, at_i = p, at_j = q;
      // neighbours across a side meet only there; round one corner, they may cross beyond it
      if (shared == 0 ? core::triangles_intersect(corners(i), corners(j))
                      : shared == 1 && core::triangles_cross_beyond_corner(corners(i), at_i, corners(j), at_j))
        all.push_back({i, j});
    }
  return all;
}

inline PrintableMesh tetrahedron(const Vec3& shift = Vec3::Zero(), double size = 1) {
  PrintableMesh m;
  m.vertices = {shift, shift + size * Vec3::UnitX(), shift + size * Vec3::UnitY(), shift + size * Vec3::UnitZ()};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

inline void append(PrintableMesh& to, const PrintableMesh& m) {
  const auto base = static_cast<std::uint32_t>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
  for (auto t : m.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// A torus of n x m quads (genus 1), outward.
inline PrintableMesh torus(int n, int m, double R = 3, double r = 1) {
  PrintableMesh t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      t.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                              r * std::sin(v));
    }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      t.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

// A UV sphere: `rings` x `sectors`, poles as single vertices, outward.
inline PrintableMesh uv_sphere(int rings, int sectors, double radius = 1) {
  PrintableMesh s;
  s.vertices.emplace_back(0, 0, radius);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      s.vertices.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::sin(th) * std::sin(ph),
                              radius * std::cos(th));
    }
  s.vertices.emplace_back(0, 0, -radius);
  const auto south = static_cast<std::uint32_t>(s.vertices.size() - 1);
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * sectors + (j % sectors)); };
  for (int j = 0; j < sectors; ++j) s.triangles.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 0; j < sectors; ++j) s.triangles.push_back({south, id(rings - 1, j + 1), id(rings - 1, j)});
  return s;
}

}  // namespace cellform::testing
