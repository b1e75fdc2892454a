// Printable structural meshes: vein segments thickened into tapered capsules and sheets into shells, as one watertight
// mesh in mm.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cells/cells.h"
#include "cells/surface.h"
#include "core/types.h"
#include "export/mesh.h"
#include "venation/canalisation.h"

namespace cellform::exporters {

using core::Vec3;

/// A tapered capsule (round cone): the convex hull of a sphere of radius `ra` at `a` and one of radius
/// `rb` at `b`. Model units. a == b gives a sphere of radius max(ra, rb).
struct Segment {
  Vec3 a, b;              ///< end points, model units
  double ra = 0, rb = 0;  ///< radii at a and b, model units (raised to ThickenParams::min_radius after scaling)
};

struct ThickenReport;

/// Settings of thicken(). Lengths are in millimetres of the printed part unless stated otherwise.
struct ThickenParams {
  double scale = 0;  ///< mm per model unit; 0 = auto: the printed form's largest extent (radii raised to min_radius,
                     ///< shell thickness included) becomes `auto_extent`
  double auto_extent = 120;  ///< mm: size of the largest side of the bounding box when scale = 0
  /// mm; 0 = auto: min_radius / 2 (a minimum-radius vein is 4 voxels across), at most half the shell thickness
  /// with shell triangles (two voxels across the wall), or coarser, up to the thinnest member printed (a vein's
  /// radius, at least min_radius; half the shell's wall), where that would need more than max_memory_bytes
  /// (ThickenReport::voxel_raised_from says so). A given one is at most min_radius with segments and at most half
  /// the shell thickness with shell triangles (voxelise refuses more)
  double voxel_size = 0;
  double min_radius = 0.4;       ///< mm: thinner veins are raised to this printable minimum
  double shell_thickness = 0.6;  ///< mm: total wall thickness of the shell around shell triangles (half on each side)
  double adaptivity = 0.2;       ///< 0..1: OpenVDB volumeToMesh adaptivity; 0 = uniform quads, higher = fewer triangles
  double max_memory_bytes = 2e9;  ///< refuse (core::InvalidInput) when the estimated peak memory exceeds this
  /// bytes the process can still get, which the caller measures (an address-space limit, a container's limit, the
  /// machine's free memory): refused (core::InvalidInput naming `available_name`) when the estimated peak exceeds
  /// it. Unlike max_memory_bytes it never coarsens the automatic voxel, so the same parameters give the same print
  /// on any machine, or none. (The mesher cannot fail cleanly: OpenVDB's volumeToMesh aborts the process when an
  /// allocation fails in it.)
  double available_bytes = std::numeric_limits<double>::infinity();
  std::string available_name = "the memory available";
  int threads = 0;             ///< worker threads; 0 = all cores. Output is bitwise identical for any value
  bool fill_cavities = false;  ///< fill closed pockets inside the solid (drop their inner walls)
  /// mm: cut this much off the bottom of the solid (its lowest z, after scaling) so that it stands on a
  /// flat face instead of the round end of a vein; 0 = no cut. Must be less than the solid's height.
  double flat_base = 0;
  /// raise each vein end by its radius as printed (mm), so that a flat form's veins, thick and thin, all rest on
  /// its lowest plane instead of being centred on it (the shell is not moved)
  bool lay_flat = false;
  /// model units: close the shell (dilate by this radius r, then erode by it), so that gaps in the triangle
  /// soup narrower than 2 sqrt(h^2 + 2 h r) (h = half the shell's thickness, in mm after scaling) are
  /// filled, thinner at their middle; 0 = the shell as given. Veins are not affected.
  double close_holes = 0;
  /// mm: the closing's radius is at most this (0 = no cap). A sheet's cells can be far apart at a large print
  /// scale, and a closing of half their spacing would also fill the space between folds of the sheet that
  /// lie closer than twice its radius: walls many times shell_thickness.
  double close_holes_max = 0;
  /// Called on the calling thread between blocks of work with the fraction of the stage done (0..1,
  /// non-decreasing within voxelise() and within mesh_level_set()); return false to stop, which throws
  /// core::Cancelled (OpenVDB's interrupter idea). Empty = never stops. Does not change the output.
  std::function<bool(double)> progress;
  /// Called on the calling thread, before it starts, with a word on a stage that will take long: a shell's closing
  /// of many voxels' radius (minutes where the default takes seconds). Empty = not said. Does not change the output.
  std::function<void(const std::string&)> note;
  /// Called on the calling thread with the plan (the report's scale, voxel size and voxel_raised_from,
  /// segments, shell triangles, raised radii, base and height, estimate) once it is made, before any voxel:
  /// notes on it come before the stages, which may take minutes. Empty = none. Does not change the output.
  /// It may throw to stop there, before any voxel (the exception passes through voxelise() unchanged): a
  /// caller that needs only the plan (app/print.cpp, the voxel size a memory limit gives) asks it this way.
  std::function<void(const ThickenReport&)> planned;
};

/// What thicken() did.
struct ThickenReport {
  double scale = 0;                 ///< mm per model unit actually used
  double voxel_size = 0;            ///< mm actually used
  double voxel_raised_from = 0;     ///< mm: the automatic voxel size raised to fit max_memory_bytes, else 0
  std::size_t segments = 0;         ///< capsules voxelised
  std::size_t shell_triangles = 0;  ///< shell triangles voxelised
  std::size_t raised_radii = 0;     ///< segment end radii raised to min_radius
  double base_z = 0;                ///< mm: height of the flat base's plane (flat_base > 0), else the lowest z
  double height = 0;                ///< mm: height of the form before any cut (lowest to highest z)
  std::size_t active_voxels = 0;    ///< narrow-band voxels of the level set
  double estimated_bytes = 0;       ///< memory estimate the refusal check used
  std::size_t triangles = 0;        ///< triangles of the output mesh
  std::size_t vertices = 0;         ///< vertices of the output mesh
  std::size_t parts = 0;            ///< connected components of the output mesh
  std::size_t pieces = 0;           ///< parts of positive volume: separate solid pieces
  std::size_t cavities = 0;         ///< parts of negative volume: walls of closed pockets inside a piece
  std::size_t filled_cavities = 0;  ///< cavities filled (fill_cavities) by removing their walls
  std::size_t dust_parts = 0;       ///< parts of less than a voxel's volume, removed
  double volume = 0;                ///< mm^3, enclosed by the output mesh (positive)
  double area = 0;                  ///< mm^2, surface area of the output mesh
  /// triangles of intersecting pairs whose neighbourhood was meshed again without adaptivity (each once a pass,
  /// summed over the passes)
  std::size_t remeshed_triangles = 0;
  std::size_t self_intersections = 0;  ///< intersecting triangle pairs left in the output (0 unless the repair gave up)
  double voxelise_seconds = 0;         ///< wall time of voxelisation
  double mesh_seconds = 0;             ///< wall time of meshing
};

/// A narrow-band signed distance grid (OpenVDB FloatGrid, mm, background = 3 voxels) kept behind an
/// opaque handle so that only printable.cpp and printable_mesh.cpp include OpenVDB.
class LevelSet {
 public:
  struct Impl;
  LevelSet();
  explicit LevelSet(std::shared_ptr<const Impl> impl);
  /// Throws core::InvalidInput on an empty handle (default-constructed: no voxelise() made it).
  const Impl& impl() const;
  double voxel_size() const;  ///< mm
  double scale() const;       ///< mm per model unit
  std::size_t active_voxels() const;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// Removes every connected part (through shared vertices) of negative signed volume, i.e. the inner
/// walls of closed cavities, with every piece lying inside one of them (which would be a surface inside
/// solid), and the vertices only they used, so the cavities become solid. Returns how many parts were removed.
/// `threads`: 0 = all cores; the result is the same for any value.
std::size_t fill_cavities(PrintableMesh& mesh, int threads = 0);

/// mm: the automatic voxel size (ThickenParams::voxel_size 0) before any raise for memory: four voxels across a
/// vein of `min_radius` mm, and with shell triangles (`shell`) at least two across a wall of `shell_thickness`
/// mm (a coarser voxel broke a 0.3 mm lamp shade into pieces).
double automatic_voxel_size(double min_radius, double shell_thickness, bool shell);

/// mm per model unit the print of `segments` and `shell_triangles` uses: params.scale, or the automatic
/// scale at which the printed form (radii raised to min_radius, the shell's half thickness around its
/// triangles) is params.auto_extent mm along its largest side (1 for a form of no extent). Known before any
/// voxel: veins.svg is drawn at it even when the print fails. Throws core::InvalidInput on a non-finite
/// coordinate or radius, or a negative radius.
double print_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell_triangles,
                   const ThickenParams& params);

/// Voxelises the union of the tapered capsules and of a shell of `shell_thickness` around the triangles
/// (any soup: non-manifold and open input is fine) into a level set in mm. Each leaf of the grid takes
/// the minimum of the exact signed distances of the primitives overlapping it (gather, not scatter), so
/// the grid is bitwise identical for any thread count.
/// Throws core::InvalidInput: no segments and no shell triangles; a non-finite coordinate or radius
/// (naming the segment or triangle); a negative radius; bad parameters; an estimated memory need above
/// max_memory_bytes (the message gives the need and a voxel size that fits); a form reaching more than about
/// 8.4 million voxels from the origin, however small (recentre it first, as `cellform` does).
LevelSet voxelise(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell_triangles,
                  const ThickenParams& params, ThickenReport* report = nullptr);

/// Meshes the zero level set (OpenVDB volumeToMesh with params.adaptivity), splits quads along their
/// shorter diagonal, orients the result outward (positive signed volume). Vertices in mm.
/// Adaptive merging can fold triangles into each other at creases; every intersecting pair is found
/// (self_intersecting_pairs) and the voxels around it are meshed again without merging, for up to three
/// passes, then once without merging anywhere; each pass checks the whole mesh again.
/// report->self_intersections says what is left (0 in every case tested).
PrintableMesh mesh_level_set(const LevelSet& level_set, const ThickenParams& params, ThickenReport* report = nullptr);

/// voxelise() then mesh_level_set(). Throws as voxelise().
PrintableMesh thicken(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell_triangles,
                      const ThickenParams& params, ThickenReport* report = nullptr);

/// Writes the level set as an OpenVDB .vdb file (one FloatGrid named "surface", class level set, mm).
/// Atomic; core::FileError on failure; core::InvalidInput for an empty level set.
void write_vdb(const std::filesystem::path& path, const LevelSet& level_set);

/// One segment per vein edge (child node to parent node) with the nodes' radii, but for a side branch (a
/// child of another order than its parent's), which has its own radius at both ends. A node without an edge
/// (a petiole no vein has reached yet) is left out: printed, it was a ball apart from the form. Model units.
std::vector<Segment> vein_segments(const venation::VeinGraph& graph);

/// The surface triangles of the cell sheet as positions (model units), for the shell.
std::vector<std::array<Vec3, 3>> shell_triangles(const cells::Cells& cells, const cells::Surface& surface);

}  // namespace cellform::exporters
