// Wall thickness of a printable mesh: where is the form too thin to print?
#pragma once

#include <cstddef>
#include <vector>

#include "core/types.h"
#include "export/mesh.h"

namespace cellform::exporters {

/// Local wall thickness by the ray method of print-preparation tools: from the centroid of each
/// triangle a ray goes along the inward normal to the first triangle it meets that shares no vertex
/// with it (neighbours mostly meet it at folds of a crease or of a fine mesh, not across the wall), or,
/// if it meets none such, to the first other triangle (a coarse solid whose faces all share corners, a
/// tetrahedron or a pyramid); if that triangle faces away from the ray (the ray leaves the solid there)
/// the distance is the wall thickness at that triangle. A triangle at least twice as long as that
/// thickness, and every triangle of a mesh of at most 1,024, gets more rays, from the centroids of its
/// regular subdivision (see wall_thickness), so the large faces of a coarse mesh show where their wall thins. For a
/// tapered capsule this is its local diameter, for a shell its wall. Lengths are in the mesh's units (mm for cellform
/// output). The mesh must be wound outward (positive volume).
struct ThicknessReport {
  std::size_t samples = 0;   ///< triangles whose ray left the solid through another triangle
  std::size_t missed = 0;    ///< rays that met nothing or entered the solid (open, inverted or creased spots)
  std::size_t given_up = 0;  ///< centroid rays given up among too many overlapping boxes (where very many
                             ///< triangles meet; an extra ray given up leaves its area to its centroid's value)
  double min = 0;  ///< thinnest sample of a triangle not under kSliverArea times the median triangle area (0 if
                   ///< none; of all, if only slivers); where the rays that met only neighbours of their
                   ///< triangle are under 1% of the measured area (a fine mesh's folds), of the others only.
                   ///< Single rays in the crotch of a junction can cut a corner, so p01 is the robust figure
  core::Vec3 min_at = core::Vec3::Zero();  ///< where the ray of the thinnest sample starts
  double p01 = 0;                          ///< 1st percentile of the samples, by area: 1% of the surface is thinner
  double median = 0;                       ///< median of the samples, by area
};

/// ThicknessReport::min leaves out triangles under this fraction of the median triangle area: a mesher's
/// slivers, whose normal is noise (their samples still count, by their area, in p01 and median).
inline constexpr double kSliverArea = 0.01;

/// Casts one ray per non-degenerate triangle through a bounding-volume hierarchy (median splits), and
/// up to 64 for a triangle at least twice as long as its wall is thick, and about 4096 / T for each of a
/// mesh of T <= 1024 triangles (from the centroids of its subdivision, each ray weighing its part of the
/// area; at most max(2^20, 4 per triangle) such rays in all), O(T log T). Deterministic for any `threads` (0 = all
/// cores).
ThicknessReport wall_thickness(const PrintableMesh& mesh, int threads = 0);

/// triangle_thickness's value for a ray given up: it entered more bounding boxes than a check can afford
/// (thousands, where very many triangles meet at one spot), so that a check stays about linear in triangles.
inline constexpr double kGivenUp = -2;

/// Per-triangle thickness of the centroids' rays (negative where the ray missed; kGivenUp), for colouring or
/// tests.
std::vector<double> triangle_thickness(const PrintableMesh& mesh, int threads = 0);

}  // namespace cellform::exporters
