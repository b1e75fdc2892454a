// Shared by the printing stages (printable.cpp voxelises, printable_mesh.cpp meshes): parameter checks,
// progress and cancelling, thread counts, the automatic scale and the shell's memory estimate (no OpenVDB).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "core/errors.h"
#include "core/triangle_intersection.h"
#include "export/printable.h"
#include "export/printable_internal.h"

namespace cellform::exporters {

namespace detail {

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

std::string bytes_text(double b) { return b >= 1e9 ? fmt("%.1f GB", b / 1e9) : fmt("%.0f MB", std::ceil(b / 1e6)); }

void check_available(double estimate, double voxel, const ThickenParams& params, double coarsest) {
  if (!(estimate > params.available_bytes)) return;
  // within max_memory_bytes, which sets the automatic voxel; a limit at most the available memory makes it fit,
  // where the coarsest voxel it may take fits
  const double fits = std::floor(params.available_bytes / 1e6);  // MB
  std::string advice = "use a coarser voxel size, or a smaller scale or size";
  if (params.voxel_size == 0)
    advice = coarsest <= fits * 1e6 ? "lower the memory limit to " + fmt("%.0f", fits) +
                                          " MB or less (the automatic voxel size then coarsens to fit), or use a "
                                          "smaller scale or size"
                                    : "use a smaller scale or size (no voxel coarse enough fits: the thinnest "
                                      "members would vanish), or free some memory";
  throw core::InvalidInput("thicken: at a voxel size of " + fmt("%.3g", voxel) + " mm the form needs about " +
                           bytes_text(estimate) + " of memory, more than " + params.available_name + " (" +
                           bytes_text(params.available_bytes) + "); " + advice);
}

void check_params(const ThickenParams& p) {
  const auto bad = [](const std::string& what) { throw core::InvalidInput("thicken: " + what); };
  if (!(std::isfinite(p.scale) && p.scale >= 0))
    bad("scale must be >= 0 mm per model unit (0 = auto), got " + fmt("%g", p.scale));
  if (!(std::isfinite(p.auto_extent) && p.auto_extent > 0))
    bad("auto_extent must be > 0 mm, got " + fmt("%g", p.auto_extent));
  if (!(std::isfinite(p.min_radius) && p.min_radius > 0))
    bad("min_radius must be > 0 mm, got " + fmt("%g", p.min_radius));
  if (!(std::isfinite(p.voxel_size) && p.voxel_size >= 0))
    bad("voxel_size must be >= 0 mm (0 = auto), got " + fmt("%g", p.voxel_size));
  if (!(std::isfinite(p.shell_thickness) && p.shell_thickness > 0))
    bad("shell_thickness must be > 0 mm, got " + fmt("%g", p.shell_thickness));
  if (!(p.adaptivity >= 0 && p.adaptivity <= 1)) bad("adaptivity must be in [0, 1], got " + fmt("%g", p.adaptivity));
  if (!(p.max_memory_bytes > 0)) bad("max_memory_bytes must be > 0");
  if (p.threads < 0) bad("threads must be >= 0 (0 = all cores)");
  if (!(std::isfinite(p.close_holes) && p.close_holes >= 0))
    bad("close_holes must be >= 0 model units (0 = none), got " + fmt("%g", p.close_holes));
  if (!(std::isfinite(p.close_holes_max) && p.close_holes_max >= 0))
    bad("close_holes_max must be >= 0 mm (0 = no cap), got " + fmt("%g", p.close_holes_max));
  if (!(std::isfinite(p.flat_base) && p.flat_base >= 0))
    bad("flat_base must be >= 0 mm (0 = no cut), got " + fmt("%g", p.flat_base));
}

/// A scale given (not found from auto_extent, which is checked against min_radius before a run): as for a
/// size, veins at least 2 min_radius thick must be thinner than the form they make, when they are printed
/// alone (with a sheet printed too, the sheet is the form).
void check_given_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                       const ThickenParams& params, double scale) {
  if (params.scale > 0 && !segments.empty() && shell.empty()) {  // (a sheet printed too is the form)
    Vec3 c_lo = Vec3::Constant(std::numeric_limits<double>::infinity()), c_hi = -c_lo;
    for (const Segment& s : segments) {
      c_lo = c_lo.cwiseMin(s.a).cwiseMin(s.b);
      c_hi = c_hi.cwiseMax(s.a).cwiseMax(s.b);
    }
    const double across = (c_hi - c_lo).maxCoeff() * scale;
    if (across > 0 && !(across > 2 * params.min_radius))  // (a form of one point is a ball, whatever the scale)
      throw core::InvalidInput(
          "thicken: at a scale of " + fmt("%.3g", scale) + " mm per model unit the veins span " + fmt("%.3g", across) +
          " mm, not more than the thinnest vein (2 min_radius = " + fmt("%.3g", 2 * params.min_radius) +
          " mm): the veins would be larger than the form; use a larger scale");
  }
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Calls params.progress (if any); throws core::Cancelled when it asks to stop.
void report_progress(const ThickenParams& params, double fraction) {
  if (params.progress && !params.progress(fraction)) throw core::Cancelled();
}

double closing_radius(const ThickenParams& p, double scale) {
  const double r = p.close_holes * scale;
  return p.close_holes_max > 0 ? std::min(r, p.close_holes_max) : r;
}

double auto_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                  double min_radius, double half_shell, double target, double upper) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 hi_r = Vec3::Constant(-inf), hi_c = hi_r, hi_s = hi_r, lo_r = Vec3::Constant(inf), lo_c = lo_r, lo_s = lo_r;
  for (const Segment& g : segments)
    for (const auto& [p, r] : {std::pair{g.a, g.ra}, std::pair{g.b, g.rb}}) {
      hi_r = hi_r.cwiseMax(p + Vec3::Constant(r));
      lo_r = lo_r.cwiseMin(p - Vec3::Constant(r));
      hi_c = hi_c.cwiseMax(p);
      lo_c = lo_c.cwiseMin(p);
    }
  for (const auto& t : shell)
    for (const Vec3& p : t) {
      hi_s = hi_s.cwiseMax(p);
      lo_s = lo_s.cwiseMin(p);
    }
  auto printed_extent = [&](double s) {  // s > 0
    double e = 0;
    for (int k = 0; k < 3; ++k) {
      const double top = std::max({s * hi_r[k], s * hi_c[k] + min_radius, s * hi_s[k] + half_shell});
      const double bottom = std::min({s * lo_r[k], s * lo_c[k] - min_radius, s * lo_s[k] - half_shell});
      e = std::max(e, top - bottom);
    }
    return e;
  };
  double lo = 0, hi = upper;
  // the model's radii alone reach the target at `upper`; a target below the thickness of one vein or of
  // the shell (reached at any scale) keeps `upper`, as when the thickness did not count
  if (!(printed_extent(hi) >= target) || printed_extent(upper * 1e-9) >= target) return upper;
  for (int i = 0; i < 200 && lo < hi; ++i) {
    const double mid = lo + (hi - lo) / 2;
    if (mid <= lo || mid >= hi) break;
    (printed_extent(mid) < target ? lo : hi) = mid;
  }
  return hi;  // the least scale found that reaches the target; 0 < hi <= upper
}

double dilated_volume(const std::vector<std::array<Vec3, 3>>& shell, double scale, double radius, bool* coarsened,
                      double max_cells) {
  if (coarsened) *coarsened = false;
  if (shell.empty() || !(radius > 0)) return 0;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : shell)
    for (const Vec3& p : t) lo = lo.cwiseMin(p * scale), hi = hi.cwiseMax(p * scale);
  lo.array() -= radius;
  hi.array() += radius;
  const Vec3 extent = hi - lo;
  double cell = radius / 2;
  const double cells = (extent / cell).array().ceil().prod();
  if (cells > max_cells) {
    cell *= std::cbrt(cells / max_cells) * 1.01;
    if (coarsened) *coarsened = true;
  }
  // and at most as many distance tests: triangles much larger than the radius (a large print of a coarse
  // sheet) each test a box of (edge / cell)^3 cells
  double tests = 0;
  for (const auto& t : shell) {
    const Vec3 box = (t[0].cwiseMax(t[1]).cwiseMax(t[2]) - t[0].cwiseMin(t[1]).cwiseMin(t[2])) * scale;
    tests += ((box.array() + 2 * radius) / cell + 1).prod();
  }
  if (tests > max_cells) {
    cell *= std::cbrt(tests / max_cells) * 1.01;
    if (coarsened) *coarsened = true;
  }
  const auto size = [&](int k) { return static_cast<std::int64_t>(std::ceil(extent[k] / cell)) + 1; };
  const std::int64_t nx = size(0), ny = size(1), nz = size(2);
  std::vector<std::uint64_t> bits(static_cast<std::size_t>((nx * ny * nz + 63) / 64), 0);
  const double r2 = radius * radius;
  for (const auto& tri : shell) {
    const Vec3 a = tri[0] * scale, b = tri[1] * scale, c = tri[2] * scale;
    const Vec3 box_lo = (a.cwiseMin(b).cwiseMin(c) - lo).array() - radius;
    const Vec3 box_hi = (a.cwiseMax(b).cwiseMax(c) - lo).array() + radius;
    // cells whose centre (i + 0.5) * cell lies in the box
    const auto first = [&](int k) {
      return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(box_lo[k] / cell - 0.5)));
    };
    const auto last = [&](int k, std::int64_t n) {
      return std::min<std::int64_t>(n - 1, static_cast<std::int64_t>(std::floor(box_hi[k] / cell - 0.5)));
    };
    for (std::int64_t i = first(0); i <= last(0, nx); ++i)
      for (std::int64_t j = first(1); j <= last(1, ny); ++j)
        for (std::int64_t k = first(2); k <= last(2, nz); ++k) {
          const std::int64_t at = (i * ny + j) * nz + k;
          std::uint64_t& word = bits[static_cast<std::size_t>(at / 64)];
          const std::uint64_t bit = std::uint64_t{1} << (at % 64);
          if (word & bit) continue;  // counted already (from a neighbouring triangle)
          const Vec3 q =
              lo +
              cell *
                  (Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)).array() + 0.5).matrix();
          if ((core::closest_point_on_triangle(q, a, b, c) - q).squaredNorm() <= r2) word |= bit;
        }
  }
  std::uint64_t count = 0;
  for (const std::uint64_t w : bits) count += static_cast<std::uint64_t>(__builtin_popcountll(w));
  return static_cast<double>(count) * cell * cell * cell;
}

double closing_overlap(const std::vector<std::array<Vec3, 3>>& shell, double scale, double area, double d0, double d1) {
  if (shell.empty() || !(area > 0)) return 1;
  double share = 0;
  for (const double d : {d0, d1})
    if (d == d0 || d != d1) {
      bool coarsened = false;
      const double v = dilated_volume(shell, scale, d, &coarsened);
      if (coarsened) return 1;  // cells wider than half the dilation miss thin parts: no estimate to trust
      share = std::max(share, v / (2 * area * d));
    }
  return std::min(1.0, share);
}

void note_long_closing(const ThickenParams& params, double close, double voxel) {
  if (!(close > 25 * voxel) || !params.note) return;
  params.note("the shell's closing radius is " + core::number_text(close) + " mm, " +
              core::number_text(std::round(close / voxel)) + " voxels of " + core::number_text(voxel) +
              " mm: the closing fills all the space within that of the sheet, which may take many minutes (" +
              (params.close_holes_max > 0 ? "close_holes_max caps the radius, in mm"
                                          : "close_holes_max = 0 leaves the radius uncapped") +
              "; close_holes sets it in cell spacings)");
}

}  // namespace detail

}  // namespace cellform::exporters
