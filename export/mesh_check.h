// Is a mesh printable? Topology, orientation, self-intersection and volume checks (export/mesh_read.h reads
// meshes back).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "export/mesh.h"

namespace cellform::exporters {

/// What check_mesh() found. Topology is judged after welding vertices at exactly equal positions, the
/// way a slicer sees an STL file. Lengths are in the mesh's units (mm for cellform output).
struct MeshReport {
  std::size_t triangles = 0;             ///< triangles in the input
  std::size_t vertices = 0;              ///< distinct vertex positions after welding
  std::size_t welded_vertices = 0;       ///< input vertices merged into an equal-position vertex
  std::size_t parts = 0;                 ///< connected components (through shared vertices)
  std::size_t pieces = 0;                ///< parts of positive signed volume: separate solid pieces
  std::size_t cavities = 0;              ///< parts of negative signed volume: walls of closed pockets inside a piece
  std::size_t boundary_edges = 0;        ///< edges used by one triangle (holes)
  std::size_t nonmanifold_edges = 0;     ///< edges used by three or more triangles
  std::size_t nonmanifold_vertices = 0;  ///< vertices whose triangles form more than one fan
  std::size_t misoriented_edges = 0;     ///< edges whose two triangles run them in the same direction
  bool consistently_oriented = true;     ///< misoriented_edges == 0
  /// Closed parts facing the wrong way for where they lie: one inside a solid must face into its pocket (the
  /// other parts wind once round it), one outside every solid or inside a pocket must face out (they wind
  /// zero times). Checked on closed, consistently oriented meshes of several parts.
  std::size_t misnested_parts = 0;
  /// false: too many parts inside others' boxes (over 20,000, or 3e8 solid angles); not printable then, as when
  /// the intersections are not tested
  bool nesting_tested = true;
  std::size_t self_intersections = 0;  ///< pairs of triangles without a shared vertex that intersect
  bool intersections_tested = true;    ///< false: too many overlapping triangles to test (not printable)
  std::vector<std::array<std::uint32_t, 2>>
      intersecting_pairs;                ///< up to 16 examples (triangle indices), deterministic
  std::size_t degenerate_triangles = 0;  ///< triangles with repeated (welded) vertices or zero area
  double volume = 0;                     ///< signed enclosed volume (units^3); positive when wound outward
  double area = 0;                       ///< surface area (units^2)
  core::Vec3 bbox_min = core::Vec3::Zero(), bbox_max = core::Vec3::Zero();  ///< bounding box
  std::vector<int> genus;  ///< per part: genus from Euler's formula, -1 if the part is not a closed manifold

  /// No holes, no non-manifold edges or vertices.
  bool closed_manifold() const { return boundary_edges == 0 && nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  /// Bounds a solid: closed manifold, consistently oriented, also as its parts nest (and that was tested).
  bool solid() const { return closed_manifold() && consistently_oriented && nesting_tested && misnested_parts == 0; }
  /// solid(), no self-intersections (tested), no degenerate triangles, positive volume.
  bool printable() const {
    return triangles > 0 && solid() && intersections_tested && self_intersections == 0 && degenerate_triangles == 0 &&
           volume > 0;
  }
  /// Why the mesh is not printable, one phrase each ("not closed: 12 boundary edges", "inside out: ..."); empty
  /// when printable().
  std::vector<std::string> problems() const;
  /// A few lines a user can read (the caller prints them; nothing here prints).
  std::string summary() const;
};

/// Checks a mesh for 3D printing. Self-intersections use a uniform grid over triangle bounding boxes and
/// an orientation-predicate triangle-triangle test (in double precision); triangles round a shared corner are
/// tested beyond it, neighbours across a side not at all. About a second for 500k triangles. `threads`: 0 = all cores;
/// the report does not depend on it.
MeshReport check_mesh(const PrintableMesh& mesh, int threads = 0);

/// Every pair of intersecting triangles (lower index first), in a deterministic order: pairs that share no
/// vertex index and meet, and pairs round one shared corner that cross beyond it (a crease folded into
/// itself; neighbours across a side are not tested). The test check_mesh() uses, without welding.
/// Zero-area triangles are skipped.
std::vector<std::array<std::uint32_t, 2>> self_intersecting_pairs(const PrintableMesh& mesh, int threads = 0);
/// The same for a subset of a mesh's triangles; pairs index into `triangles`.
std::vector<std::array<std::uint32_t, 2>> self_intersecting_pairs(
    const std::vector<core::Vec3>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
    int threads = 0);

/// What count_self_intersections() found.
struct SelfIntersectionCount {
  std::size_t count = 0;                               ///< intersecting pairs (as self_intersecting_pairs)
  std::vector<std::array<std::uint32_t, 2>> examples;  ///< the smallest pairs, up to the number asked for
  bool tested = true;                                  ///< false: more candidate pairs than max_tests, none tested
};
/// The same pairs as self_intersecting_pairs(), counted in memory independent of their number (a file of
/// thousands of triangles crossing one line has millions of pairs), and given up, untested, when one cell of
/// the grid leaves more than `max_tests` candidate pairs to test, its fans round a shared vertex peeled off (a
/// stack of parallel triangles: time ~ its square).
SelfIntersectionCount count_self_intersections(const std::vector<core::Vec3>& vertices,
                                               const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                               std::size_t examples, double max_tests, int threads = 0);

/// Solid angle (steradians, signed by the winding) of the triangle a, b, c seen from the origin (Van Oosterom and
/// Strackee): summed over a closed surface, 4 pi times the times it winds round the origin.
double solid_angle(const core::Vec3& a, const core::Vec3& b, const core::Vec3& c);

/// Signed volume by the divergence theorem (units^3): positive for a closed mesh wound outward.
double signed_volume(const PrintableMesh& mesh);
/// Sum of triangle areas (units^2).
double surface_area(const PrintableMesh& mesh);
/// Each vertex's connected component through shared vertex indices (no welding), named by its smallest vertex
/// index (a vertex no triangle uses is a component of its own).
std::vector<std::uint32_t> part_labels(const PrintableMesh& mesh);
/// Connected components through shared vertex indices (no welding).
std::size_t count_parts(const PrintableMesh& mesh);

/// Canonical vertex index per input vertex: the first input vertex at exactly the same position
/// (bitwise equal coordinates; the weld of STL soups and of the checks).
std::vector<std::uint32_t> weld_positions(const std::vector<core::Vec3>& positions);

}  // namespace cellform::exporters
