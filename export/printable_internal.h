// Private to export/: what printable.cpp (voxelising), printable_mesh.cpp (meshing) and printable_common.cpp
// share, without OpenVDB (the level set's grid is in printable_vdb.h); not for other folders.
#pragma once

#include <array>
#include <chrono>
#include <string>
#include <vector>

#include "export/printable.h"

namespace cellform::exporters {

namespace detail {

/// printf-formats one number (messages).
std::string fmt(const char* f, double x);
/// `b` bytes, in GB from 1 GB on, else in MB (rounded up).
std::string bytes_text(double b);
/// Throws core::InvalidInput when the print's `estimate` (bytes, at `voxel` mm) exceeds params.available_bytes;
/// `coarsest` is the estimate at the coarsest voxel the automatic one may take (the thinnest member), which
/// says whether a lower max_memory_bytes would help.
void check_available(double estimate, double voxel, const ThickenParams& params, double coarsest);
/// Throws core::InvalidInput naming the first ThickenParams field out of range.
void check_params(const ThickenParams& p);
/// InvalidInput for a given scale (mm per model unit) at which veins printed alone span no more than
/// 2 min_radius.
void check_given_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                       const ThickenParams& params, double scale);
double seconds_since(std::chrono::steady_clock::time_point t);
/// Calls params.progress (if any); throws core::Cancelled when it asks to stop.
void report_progress(const ThickenParams& params, double fraction);
/// mm per model unit at which the printed form, as it is thickened (vein radii raised to `min_radius` mm,
/// the shell `half_shell` mm to each side), is `target` mm along its largest side. Along an axis the printed
/// form reaches max(s max(a + r), s max(a) + min_radius, s max(p) + half_shell) over vein ends a (radius r)
/// and shell corners p, and as far the other way: an extent that grows with s, solved by bisection below
/// `upper` (where the model's own radii alone give `target`).
double auto_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                  double min_radius, double half_shell, double target, double upper);
/// mm: the radius of the shell's closing, close_holes at the scale, capped by close_holes_max.
double closing_radius(const ThickenParams& p, double scale);
/// mm^3: the volume within `radius` mm of the triangles `shell` (model units, scaled by `scale` mm per unit),
/// counted as the cells of a grid radius / 2 mm wide whose centres lie that close (coarser past `max_cells`
/// cells, 2^28 or 32 MB of bits, or as many distance tests: then `coarsened` is set, and a thin part may be
/// missed). Where a folded sheet
/// lies within 2 radius of itself the dilations overlap and count once.
double dilated_volume(const std::vector<std::array<Vec3, 3>>& shell, double scale, double radius,
                      bool* coarsened = nullptr, double max_cells = 0x1p28);
/// The share of the sum of the triangles' dilations (2 area d, `area` mm^2 of `shell` at `scale`) that their
/// union takes, the larger at the dilations `d0` and `d1` mm (the finest and the coarsest voxel's), at most 1
/// (rims and corners add to a small sheet's union); 1 for no triangles, and where the grid had to be coarsened.
double closing_overlap(const std::vector<std::array<Vec3, 3>>& shell, double scale, double area, double d0, double d1);
/// Tells params.note of a closing of more than 25 voxels' radius (`close` mm, `voxel` mm), which may take minutes
/// (the default caps it at 10).
void note_long_closing(const ThickenParams& params, double close, double voxel);

}  // namespace detail

}  // namespace cellform::exporters
