// Solids and surfaces the cells cannot enter or cross (ground, spheres, boxes, triangle meshes).
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cells/cells.h"
#include "core/types.h"

namespace cellform::forms {

using core::Index;
using core::Vec3;

class PreparedObstacles;

/// The solid side of a plane: cells stay on the side `normal` points to. A ground plane is a half-space.
struct HalfSpace {
  Vec3 point = Vec3::Zero();    ///< any point of the plane, model units
  Vec3 normal = Vec3::UnitZ();  ///< points away from the solid (need not be unit length, must not be zero)
};

/// A solid ball; cells stay outside.
struct Sphere {
  Vec3 centre = Vec3::Zero();  ///< model units
  double radius = 1.0;         ///< model units, > 0
};

/// A solid axis-aligned box; cells stay outside.
struct Box {
  Vec3 min = Vec3::Zero();  ///< lowest corner, model units
  Vec3 max = Vec3::Ones();  ///< highest corner, model units; min <= max in every coordinate
};

/// A triangle surface, open or closed, manifold or not: cells cannot cross it in either direction.
struct TriangleMesh {
  std::vector<Vec3> vertices;                   ///< model units
  std::vector<std::array<Index, 3>> triangles;  ///< indices into vertices
};

/// Every obstacle of a scene.
struct Obstacles {
  std::vector<HalfSpace> half_spaces;
  std::vector<Sphere> spheres;
  std::vector<Box> boxes;
  std::vector<TriangleMesh> meshes;

  bool empty() const { return half_spaces.empty() && spheres.empty() && boxes.empty() && meshes.empty(); }
};

/// How error messages name each obstacle, by kind and index in Obstacles (e.g. "leaf.lua:4: ball{...}", which
/// says where it was asked for). An obstacle without a name here is "ground 0", "sphere 2", "box 1" or "mesh 0".
struct ObstacleNames {
  std::vector<std::string> half_spaces, spheres, boxes, meshes;
};

/// Throws core::InvalidInput naming the obstacle ("ground 0", "sphere 2", "box 1", "mesh 0") and what is
/// allowed, for a zero or non-finite normal, a radius <= 0, a box with min > max, non-finite coordinates,
/// or a mesh triangle index out of range.
void validate(const Obstacles& obstacles);

/// Throws core::InvalidInput if one of `positions` (model units) lies inside a solid obstacle: on the solid
/// side of a half space, or inside a sphere or a box, deeper than a rounding tolerance; a position on the
/// surface is outside. Obstacles only stop cells that cross their surface (and push them out across it), so
/// cells that start inside would be thrown to the far side of the solid: obstacles must start outside the
/// cells. The message names the first such obstacle (half spaces, then spheres, then boxes) as `names` does,
/// how many positions it holds and the first of them. A position on a mesh triangle (within a rounding
/// tolerance, see PreparedObstacles::mesh_touched) is refused too: it is on neither side of the mesh, so no
/// move of it would count as crossing. Also throws as validate() does. `threads` (0 = all cores) search the
/// meshes; the result is the same for any value. `prepared`, if given, is `obstacles` prepared (a scene's),
/// whose mesh hierarchy is searched instead of building one (and which validated them when it was made).
void check_outside(const Obstacles& obstacles, const std::vector<Vec3>& positions, const ObstacleNames& names = {},
                   int threads = 0, const PreparedObstacles* prepared = nullptr);

/// Throws core::InvalidInput if a link of `cells` (its neighbourhood, cells::Cells::links) joins cells on the two
/// sides of a mesh obstacle of `obstacles` (it crosses the mesh's triangles an odd number of times; crossings within
/// a millionth of the link of each other, as through an edge, count once): such neighbours are pulled onto it from both
/// sides, and the sheet they make grows through it (a mesh cut through the cells, a mould smaller than the form). Cells
/// all on one side of each mesh pass, as inside a mould, beside a wall or hugging a rock (a link that dips into it and
/// out again). The message names the first such mesh (as `names` does), how many links cross it (a mutual link once)
/// and the first of them, by its cells' positions. `threads` (0 = all cores) test the links; the result is the same for
/// any value.
void check_links_clear(const PreparedObstacles& obstacles, const cells::Cells& cells, const ObstacleNames& names = {},
                       int threads = 0);

/// Obstacles prepared for repeated use: a bounding-volume hierarchy over every mesh triangle.
/// Build once per scene and call apply() every step; apply_obstacles() builds one per call.
class PreparedObstacles {
 public:
  /// Copies the obstacles and builds the mesh hierarchy (O(T log T) for T triangles).
  /// Throws core::InvalidInput as validate() does.
  explicit PreparedObstacles(Obstacles obstacles);
  ~PreparedObstacles();
  PreparedObstacles(PreparedObstacles&&) noexcept;
  PreparedObstacles& operator=(PreparedObstacles&&) noexcept;

  /// See apply_obstacles().
  void apply(cells::Cells& cells, const std::vector<Vec3>& previous_positions, double margin, int threads = 0) const;

  /// True if `position` lies inside a solid (closer than `margin` minus a rounding tolerance, model units).
  bool inside_solid(const Vec3& position, double margin) const;

  /// The index (in Obstacles::meshes) of a mesh with a triangle that `position` lies on, within a rounding
  /// tolerance (1e-9 of the meshes' size) of its plane; the lowest such index. None if no triangle is there.
  std::optional<std::size_t> mesh_touched(const Vec3& position) const;

  /// True if the straight move from `from` to `to` crosses (or touches) a mesh triangle.
  bool crosses_mesh(const Vec3& from, const Vec3& to) const;
  /// Every crossing (or touch) of a mesh triangle by the straight move from `from` to `to`, into `out` (cleared
  /// first): its fraction of the way, in [0, 1], and the index of its mesh (in Obstacles::meshes), one per triangle
  /// (a move through an edge crosses two), in the hierarchy's order.
  void mesh_crossings(const Vec3& from, const Vec3& to, std::vector<std::pair<double, std::size_t>>& out) const;

  /// `to`, or where the straight move from `from` first crosses a mesh triangle, `margin` (model units)
  /// back on the side of `from`: a new cell placed at `to` by a cell at `from` stays on its mother's side.
  Vec3 stop_at_mesh(const Vec3& from, const Vec3& to, double margin) const;

  const Obstacles& obstacles() const { return obstacles_; }

 private:
  struct MeshIndex;
  Obstacles obstacles_;
  std::unique_ptr<MeshIndex> index_;
};

/// Enforces the obstacles after integration. For every non-fixed cell:
/// - a move from `previous_positions[i]` that crosses a mesh triangle puts the cell back on the side it
///   came from, at the crossing point offset by `margin` along the triangle normal;
/// - a cell that enters a sphere or box during the move (even one it passes right through) is stopped
///   on the surface where it entered, keeping its motion along that surface; a cell already inside a
///   solid, or below a ground plane, is moved to the nearest point of the surface;
/// - solids count as grown by `margin`: cells end at least `margin` model units away from them;
/// - the velocity component into the obstacle is removed.
/// Corrections repeat until no constraint is violated (a few passes). A cell whose correction would cross a
/// mesh (a solid's nearest way out lying beyond a mesh wall) returns to its previous position with zero
/// velocity; so does a cell that came from outside the solids and cannot be placed (wedged between
/// obstacles), while one that was already inside (overlapping solids push it back and forth) keeps the
/// passes' progress and leaves over the next steps. Fixed cells are untouched.
/// Each cell writes only its own slot: any thread count (0 = all cores) gives identical results.
/// `margin`: model units, >= 0. Throws core::InvalidInput for a bad obstacle, a negative margin or a
/// previous_positions of the wrong size.
void apply_obstacles(cells::Cells& cells, const std::vector<Vec3>& previous_positions, const Obstacles& obstacles,
                     double margin, int threads = 0);

/// Reads a triangle mesh from STL (ASCII or binary) or OBJ, chosen by the file extension. Polygons are
/// split into triangles where they lie (core::triangulate_polygon: a concave n-gon is ear-clipped, and
/// one of over core::kMaxConcaveCorners corners is refused); non-manifold and open meshes are kept as they are. Throws
/// core::FileError for a missing or unreadable file, core::InvalidInput for an unsupported extension, a malformed file,
/// a file without triangles ("not a mesh") or non-finite coordinates; every message names the file. ASCII STL is read
/// by parse_ascii_stl (forms/mesh_io.h), so a damaged or cut-short one is refused naming the line.
TriangleMesh load_mesh(const std::filesystem::path& path);

}  // namespace cellform::forms
