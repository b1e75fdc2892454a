// Thickening into a level set (voxelise); meshing it is in printable_mesh.cpp, the helpers both use in
// printable_common.cpp. This file and printable_mesh.cpp are the only ones that include OpenVDB (printable_vdb.h).
#include "export/printable.h"

#include "export/printable_internal.h"
#include "export/printable_vdb.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include "core/errors.h"
#include "core/parallel.h"

namespace cellform::exporters {

using detail::auto_scale;
using detail::bytes_text;
using detail::check_available;
using detail::check_params;
using detail::closing_overlap;
using detail::closing_radius;
using detail::fmt;
using detail::init_openvdb;
using detail::note_long_closing;
using detail::report_progress;
using detail::seconds_since;

LevelSet::LevelSet() = default;
LevelSet::LevelSet(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
const LevelSet::Impl& LevelSet::impl() const {
  if (!impl_) throw core::InvalidInput("an empty level set (no voxelise() made it) has no grid to mesh or write");
  return *impl_;
}
double LevelSet::voxel_size() const { return impl_ ? impl_->voxel_size : 0.0; }
double LevelSet::scale() const { return impl_ ? impl_->scale : 0.0; }
std::size_t LevelSet::active_voxels() const { return impl_ ? impl_->active_voxels : 0; }

namespace {

constexpr int kHalfWidth = 3;  // narrow band half width in voxels (OpenVDB's LEVEL_SET_HALF_WIDTH)
constexpr int kLeafLog2 = 3;   // 8^3 voxels per leaf
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
static_assert(FloatLeaf::DIM == (1 << kLeafLog2));

// Bytes per narrow-band voxel (leaf values, masks, partly filled leaves) and per surface quad before
// adaptivity (volumeToMesh scratch and output, our triangles); measured on the export benchmarks and rounded up.
constexpr double kBytesPerActiveVoxel = 14;
constexpr double kBytesPerQuad = 160;

// Exact signed distance to a round cone, after Inigo Quilez's sdRoundCone (one square root per voxel);
// falls back to a sphere when one end sphere contains the other.
struct Capsule {
  Vec3 a, ba;
  double r1 = 0, r2 = 0, l2 = 0, rr = 0, a2 = 0, il2 = 0;
  bool sphere = false;
  Vec3 lo, hi;  // bounding box of the solid, mm

  Capsule(const Vec3& pa, const Vec3& pb, double ra, double rb) {
    lo = pa.cwiseMin(pb) - Vec3::Constant(std::max(ra, rb));
    hi = pa.cwiseMax(pb) + Vec3::Constant(std::max(ra, rb));
    const double len = (pb - pa).norm();
    if (len <= std::abs(ra - rb) * (1 + 1e-9) + 1e-12) {  // one sphere swallows the other
      sphere = true;
      a = ra >= rb ? pa : pb;
      r1 = std::max(ra, rb);
      return;
    }
    a = pa;
    ba = pb - pa;
    r1 = ra;
    r2 = rb;
    l2 = ba.squaredNorm();
    rr = r1 - r2;
    a2 = l2 - rr * rr;
    il2 = 1.0 / l2;
  }

  double distance(const Vec3& p) const {
    const Vec3 pa = p - a;
    if (sphere) return pa.norm() - r1;
    const double y = pa.dot(ba);
    const double z = y - l2;
    const double x2 = (pa * l2 - ba * y).squaredNorm();
    const double y2 = y * y * l2;
    const double z2 = z * z * l2;
    const double k = (rr > 0 ? 1.0 : rr < 0 ? -1.0 : 0.0) * rr * rr * x2;
    const double sz = z > 0 ? 1.0 : z < 0 ? -1.0 : 0.0;
    const double sy = y > 0 ? 1.0 : y < 0 ? -1.0 : 0.0;
    if (sz * a2 * z2 > k) return std::sqrt(x2 + z2) * il2 - r2;
    if (sy * a2 * y2 < k) return std::sqrt(x2 + y2) * il2 - r1;
    return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - r1;
  }
};

// A slab of half thickness h around a triangle: unsigned distance to the triangle minus h.
struct Slab {
  Vec3 p0, p1, p2;
  double h = 0;
  Vec3 lo, hi;

  Slab(const Vec3& a, const Vec3& b, const Vec3& c, double half_width) : p0(a), p1(b), p2(c), h(half_width) {
    lo = a.cwiseMin(b).cwiseMin(c) - Vec3::Constant(h);
    hi = a.cwiseMax(b).cwiseMax(c) + Vec3::Constant(h);
  }

  // Closest point on a triangle, Ericson, Real-Time Collision Detection 5.1.5 (degenerate triangles too).
  double distance(const Vec3& p) const {
    const Vec3 ab = p1 - p0, ac = p2 - p0, ap = p - p0;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return ap.norm() - h;
    const Vec3 bp = p - p1;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return bp.norm() - h;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      const double v = d1 / (d1 - d3);
      return (ap - v * ab).norm() - h;
    }
    const Vec3 cp = p - p2;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return cp.norm() - h;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      const double w = d2 / (d2 - d6);
      return (ap - w * ac).norm() - h;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
      const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      return (bp - w * (p2 - p1)).norm() - h;
    }
    const double denom = va + vb + vc;
    if (!(std::abs(denom) > 0)) return ap.norm() - h;  // all three points coincide
    const double v = vb / denom, w = vc / denom;
    return (ap - ab * v - ac * w).norm() - h;
  }
};

struct Box {
  openvdb::Coord lo, hi;  // inclusive voxel index range
};

// A (leaf, primitive) pair; primitives are numbered capsules first, then slabs.
struct LeafRef {
  std::uint64_t leaf;
  std::uint32_t prim;
  bool operator<(const LeafRef& o) const { return leaf != o.leaf ? leaf < o.leaf : prim < o.prim; }
};

constexpr int kKeyBits = 21;
constexpr std::int64_t kKeyOffset = std::int64_t{1} << (kKeyBits - 1);

std::uint64_t leaf_key(int x, int y, int z) {
  return (static_cast<std::uint64_t>(x + kKeyOffset) << (2 * kKeyBits)) |
         (static_cast<std::uint64_t>(y + kKeyOffset) << kKeyBits) | static_cast<std::uint64_t>(z + kKeyOffset);
}

openvdb::Coord leaf_origin(std::uint64_t key) {
  const std::uint64_t mask = (std::uint64_t{1} << kKeyBits) - 1;
  const auto c = [&](int shift) {
    return static_cast<int>(static_cast<std::int64_t>((key >> shift) & mask) - kKeyOffset) * (1 << kLeafLog2);
  };
  return {c(2 * kKeyBits), c(kKeyBits), c(0)};
}

bool finite(const Vec3& v) { return v.allFinite(); }

}  // namespace

double automatic_voxel_size(double min_radius, double shell_thickness, bool shell) {
  return (shell ? std::min(min_radius, shell_thickness) : min_radius) / 2;
}

double print_scale(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                   const ThickenParams& params) {
  // Validate and find the model's bounding box (radii included) for the automatic scale.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& s = segments[i];
    if (!finite(s.a) || !finite(s.b) || !std::isfinite(s.ra) || !std::isfinite(s.rb))
      throw core::InvalidInput("thicken: vein segment " + std::to_string(i) + " has a non-finite end point or radius");
    if (s.ra < 0 || s.rb < 0)
      throw core::InvalidInput("thicken: vein segment " + std::to_string(i) + " has a negative radius");
    lo = lo.cwiseMin(s.a - Vec3::Constant(s.ra)).cwiseMin(s.b - Vec3::Constant(s.rb));
    hi = hi.cwiseMax(s.a + Vec3::Constant(s.ra)).cwiseMax(s.b + Vec3::Constant(s.rb));
  }
  for (std::size_t i = 0; i < shell.size(); ++i)
    for (const Vec3& p : shell[i]) {
      if (!finite(p))
        throw core::InvalidInput("thicken: shell triangle " + std::to_string(i) + " has a non-finite corner");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if (params.scale > 0) return params.scale;
  const double extent = segments.empty() && shell.empty() ? 0.0 : (hi - lo).maxCoeff();
  return extent > 0 ? auto_scale(segments, shell, params.min_radius, params.shell_thickness / 2, params.auto_extent,
                                 params.auto_extent / extent)
                    : 1.0;
}

LevelSet voxelise(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell,
                  const ThickenParams& params, ThickenReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  check_params(params);
  if (segments.empty() && shell.empty())
    throw core::InvalidInput("thicken: nothing to thicken: the form has no vein segments and no shell triangles");
  const double half_shell = params.shell_thickness / 2;
  if (!segments.empty() && params.voxel_size > params.min_radius)
    throw core::InvalidInput("thicken: voxel_size " + fmt("%g", params.voxel_size) + " mm exceeds min_radius " +
                             fmt("%g", params.min_radius) +
                             " mm: the thinnest veins would vanish; use a voxel size of at most min_radius");
  if (!shell.empty() && params.voxel_size > half_shell)
    throw core::InvalidInput("thicken: voxel_size " + fmt("%g", params.voxel_size) +
                             " mm exceeds half the shell_thickness " + fmt("%g", params.shell_thickness) +
                             " mm: with fewer than two voxels across, the wall would break into pieces; use a voxel "
                             "size of at most shell_thickness / 2");
  const double scale = print_scale(segments, shell, params);
  // (the automatic one may be raised below, up to the thinnest member printed)
  double voxel = params.voxel_size > 0
                     ? params.voxel_size
                     : automatic_voxel_size(params.min_radius, params.shell_thickness, !shell.empty());
  detail::check_given_scale(segments, shell, params, scale);

  // Primitives in mm, with radii raised to the printable minimum.
  std::vector<Capsule> caps;
  caps.reserve(segments.size());
  std::size_t raised = 0;
  // mm^2, the surface of the union: lateral areas, plus a hemisphere at each free end (an end shared with
  // another segment is inside the union). Overlaps are still counted twice, so this errs high.
  double area = 0;
  // segment ends, sorted: an end found once is free (a sorted array, not a map: millions of segments)
  std::vector<std::array<double, 3>> ends;
  ends.reserve(2 * segments.size());
  for (const Segment& s : segments) {
    ends.push_back({s.a.x(), s.a.y(), s.a.z()});
    ends.push_back({s.b.x(), s.b.y(), s.b.z()});
  }
  std::sort(ends.begin(), ends.end());
  auto free_end = [&](const Vec3& p) {
    const std::array<double, 3> k{p.x(), p.y(), p.z()};
    const auto [first, last] = std::equal_range(ends.begin(), ends.end(), k);
    return last - first == 1;
  };
  // the lowest point of the solid, mm: of a round cone, the lower of its end spheres' lowest points;
  // of a slab, its lowest corner less half the thickness
  double bottom = std::numeric_limits<double>::infinity(), top = -bottom;
  // mm: the thinnest member printed, a vein's radius (raised to min_radius) or the shell's half wall
  double thinnest = shell.empty() ? std::numeric_limits<double>::infinity() : half_shell;
  for (const Segment& s : segments) {
    const double ra = std::max(s.ra * scale, params.min_radius), rb = std::max(s.rb * scale, params.min_radius);
    thinnest = std::min({thinnest, ra, rb});
    const Vec3 a = s.a * scale + Vec3(0, 0, params.lay_flat ? ra : 0),
               b = s.b * scale + Vec3(0, 0, params.lay_flat ? rb : 0);
    bottom = std::min({bottom, a.z() - ra, b.z() - rb});
    top = std::max({top, a.z() + ra, b.z() + rb});
    raised += (s.ra * scale < params.min_radius) + (s.rb * scale < params.min_radius);
    caps.emplace_back(a, b, ra, rb);
    const double len = (s.b - s.a).norm() * scale;
    area += M_PI * (ra + rb) * std::hypot(len, ra - rb);
    if (free_end(s.a)) area += 2 * M_PI * ra * ra;
    if (free_end(s.b)) area += 2 * M_PI * rb * rb;
  }
  std::vector<Slab> slabs;
  slabs.reserve(shell.size());
  for (const auto& t : shell) {
    slabs.emplace_back(t[0] * scale, t[1] * scale, t[2] * scale, half_shell);
    const Vec3 a = t[0] * scale, b = t[1] * scale, c = t[2] * scale;
    bottom = std::min(bottom, std::min({a.z(), b.z(), c.z()}) - half_shell);
    top = std::max(top, std::max({a.z(), b.z(), c.z()}) + half_shell);
    area += (b - a).cross(c - a).norm();  // both faces; rims are mostly shared with neighbours
  }

  if (params.flat_base > 0 && !(params.flat_base < top - bottom))
    throw core::InvalidInput("thicken: flat_base (" + fmt("%g", params.flat_base) +
                             " mm) must be less than the height of the printed form (" + fmt("%.4g", top - bottom) +
                             " mm), or nothing is left to print");
  const double base_z = params.flat_base > 0 ? bottom + params.flat_base : bottom;  // mm: the cut plane
  const bool cut = params.flat_base > 0;

  // Memory: narrow-band voxels (both sides of the surface) and surface quads both scale as voxel^-2. A shell's
  // closing holds its dilation's grid and exact distances through the whole dilated thickness at once: the
  // volume within h + r + two bands of the sheet, counted once where a folded sheet's dilations overlap
  // (closing_overlap); 1.6 grids alive at once, measured: peak 0.81 GB on a flat 89-cell disc at 120 mm.
  double shell_area = 0;
  for (const Slab& w : slabs) shell_area += (w.p1 - w.p0).cross(w.p2 - w.p0).norm() / 2;
  const auto dilation = [&](double v) { return half_shell + closing_radius(params, scale) + 2 * kHalfWidth * v; };
  if (!std::isfinite(thinnest)) thinnest = params.min_radius;  // (no vein, no shell)
  double overlap = 1;  // counted only where the sum of the dilations is over the limit (it costs a pass)
  const auto estimate_at = [&](double v) {
    const double active_estimate = area * 2 * kHalfWidth / (v * v);  // the band is kHalfWidth voxels
    const double quads_estimate = area / (v * v);
    const double closing_voxels =
        params.close_holes > 0 && !slabs.empty() ? 1.6 * overlap * shell_area * 2 * dilation(v) / (v * v * v) : 0.0;
    return (active_estimate + closing_voxels) * kBytesPerActiveVoxel + quads_estimate * kBytesPerQuad +
           static_cast<double>(caps.size() + slabs.size()) * 200;
  };
  double estimate = estimate_at(voxel);
  if (estimate > params.max_memory_bytes && params.close_holes > 0 && !slabs.empty()) {
    const double coarsest = params.voxel_size > 0 ? voxel : thinnest;  // the voxel may be raised up to it
    overlap = closing_overlap(shell, scale, shell_area, dilation(voxel), dilation(std::max(voxel, coarsest)));
    estimate = estimate_at(voxel);
  }
  double voxel_raised_from = 0;
  if (estimate > params.max_memory_bytes) {
    // a coarser voxel helps only up to the thinnest member (thinner ones would vanish): beyond, only size or
    // memory; from a voxel whose estimate is finite (1e-300 mm overflows it)
    double fit = std::max(voxel, 1e-6 * params.min_radius);
    // ~ voxel^-2 to ^-3: each step at least halves the error (of alternating sign under ^-3)
    for (int k = 0; k < 64; ++k) fit *= std::sqrt(estimate_at(fit) / params.max_memory_bytes);
    const double needed = fit * 1.05;
    // the automatic voxel gives way to the memory limit, up to the thinnest member (a vein of that radius, or
    // the shell's wall, stays two voxels across; above min_radius where the veins print thicker): rounded up to two
    // significant digits, a value a user can read and pass on, or the largest that is allowed; checked, as the
    // iteration converges slowly where the per-primitive part of the estimate dominates
    double chosen = 0;
    if (params.voxel_size == 0) {
      const double unit = std::pow(10.0, std::floor(std::log10(needed)) - 1);
      for (const double v : {std::ceil(needed / unit) * unit, needed, thinnest})
        if (chosen == 0 && v > voxel && v <= thinnest && estimate_at(v) <= params.max_memory_bytes) chosen = v;
    }
    if (chosen > 0) {
      voxel_raised_from = voxel;
      voxel = chosen;
      estimate = estimate_at(voxel);
    } else {
      const double primitives = static_cast<double>(caps.size() + slabs.size()) * 200;  // alone: no voxel fits
      const std::string advice =
          primitives >= params.max_memory_bytes
              ? "its " + std::to_string(caps.size() + slabs.size()) +
                    " vein segments and sheet triangles alone need about " + bytes_text(primitives) +
                    ", so no voxel size fits: raise the memory limit"
          : needed <= std::min(params.min_radius, thinnest)
              ? "use a voxel size of at least " + fmt("%.3g", needed) + " mm (at most " +
                    (thinnest < params.min_radius ? "half the shell thickness, " : "min_radius, ") +
                    fmt("%.3g", std::min(params.min_radius, thinnest)) +
                    " mm), a smaller scale, or raise the memory limit"
          : needed <= thinnest && params.voxel_size > 0  // (the automatic voxel would have been raised so far)
              ? "use the automatic voxel size (0), which may be as coarse as the thinnest member, " +
                    fmt("%.3g", thinnest) + " mm, a smaller scale, or raise the memory limit"
              : "use a smaller scale or size, or raise the memory limit (a voxel coarse enough would be " +
                    fmt("%.3g", needed) + " mm, above " +
                    (thinnest == half_shell && !slabs.empty() ? "half the shell thickness "
                     : thinnest > params.min_radius           ? "the thinnest vein's radius "
                                                              : "min_radius ") +
                    fmt("%.3g", thinnest) + " mm, so the thinnest " + (slabs.empty() ? "veins" : "members") +
                    " would vanish" +
                    (thinnest == params.min_radius ? "; a larger min_radius allows a coarser voxel" : "") + ")";
      throw core::InvalidInput("thicken: at a voxel size of " + fmt("%.3g", voxel) + " mm the form needs " +
                               (std::isfinite(estimate) && estimate < 1e18
                                    ? "about " + bytes_text(estimate) + " of memory, more than the limit of "
                                    : std::string("more memory than the limit of ")) +
                               bytes_text(params.max_memory_bytes) + "; " + advice);
    }
  }
  check_available(estimate, voxel, params, estimate_at(thinnest));
  ThickenReport plan_only, &plan = report ? *report : plan_only;
  plan.scale = scale, plan.voxel_size = voxel;
  plan.voxel_raised_from = voxel_raised_from;
  plan.segments = caps.size();
  plan.shell_triangles = slabs.size();
  plan.raised_radii = raised;
  plan.base_z = base_z;
  plan.height = top - bottom;
  plan.estimated_bytes = estimate;
  if (params.planned) params.planned(plan);
  const double band = kHalfWidth * voxel;  // mm, also the grid's background value

  // One narrow-band grid of the union of capsules `cs` and slabs `ss`, cut below z = cut_z when `cut`;
  // progress goes from p0 to p1 of the stage.
  const float bg = static_cast<float>(band);
  auto rasterise = [&](const std::vector<Capsule>& cs, const std::vector<Slab>& ss, bool cut_below, double cut_z,
                       double p0, double p1) {
    // Index boxes of the primitives widened by the band; voxel (i, j, k) sits at (i, j, k) * voxel mm.
    const std::size_t nprim = cs.size() + ss.size();
    std::vector<Box> boxes(nprim);
    double overlaps = 0;  // (leaf, primitive) pairs the gather will list
    const double max_index = static_cast<double>(kKeyOffset - 2) * (1 << kLeafLog2);
    for (std::size_t i = 0; i < nprim; ++i) {
      const Vec3& plo = i < cs.size() ? cs[i].lo : ss[i - cs.size()].lo;
      const Vec3& phi = i < cs.size() ? cs[i].hi : ss[i - cs.size()].hi;
      const Vec3 ilo = ((plo.array() - band) / voxel).ceil(), ihi = ((phi.array() + band) / voxel).floor();
      if (ilo.cwiseAbs().maxCoeff() > max_index || ihi.cwiseAbs().maxCoeff() > max_index)
        throw core::InvalidInput("thicken: the form reaches more than " + fmt("%.0f", max_index) +
                                 " voxels from the origin; move it nearer the origin (the voxels are counted "
                                 "from there), or use a larger voxel size or a smaller scale");
      boxes[i].lo = openvdb::Coord(static_cast<int>(ilo.x()), static_cast<int>(ilo.y()), static_cast<int>(ilo.z()));
      boxes[i].hi = openvdb::Coord(static_cast<int>(ihi.x()), static_cast<int>(ihi.y()), static_cast<int>(ihi.z()));
      const openvdb::Coord a = boxes[i].lo >> kLeafLog2, b = boxes[i].hi >> kLeafLog2;  // as the gather
      overlaps += double(b.x() - a.x() + 1) * double(b.y() - a.y() + 1) * double(b.z() - a.z() + 1);
    }
    // the gather below lists every (leaf, primitive) overlap at once; the estimate above counts surface voxels
    // only, and a shell or vein many voxels thick (1000 mm at 0.2 mm) overlaps far more leaves. The list is
    // short-lived (a few hundred MB for the full-size poplar's 4.45 M segments, whose grids the estimate puts at
    // 4.5 GB), so it is held against the limit alone.
    if (overlaps * sizeof(LeafRef) > params.max_memory_bytes)
      throw core::InvalidInput("thicken: at a voxel size of " + fmt("%.3g", voxel) + " mm the form's " +
                               std::to_string(nprim) + " pieces overlap about " + fmt("%.3g", overlaps) +
                               " blocks of 8 x 8 x 8 voxels, which need " + bytes_text(overlaps * sizeof(LeafRef)) +
                               " of memory to list, more than the limit of " + bytes_text(params.max_memory_bytes) +
                               "; a shell or veins this thick need a larger voxel size, or raise the memory limit");

    auto grid = openvdb::FloatGrid::create(bg);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("surface");  // the name Houdini and Blender give a level set

    core::with_threads(params.threads, [&] {
      // Gather: list every (leaf, primitive) overlap, sort by leaf, then each leaf takes the minimum
      // over its primitives. Every leaf is computed by one task from sorted input: no races, no order effects.
      std::vector<std::size_t> offset(nprim + 1, 0);
      for (std::size_t i = 0; i < nprim; ++i) {
        const openvdb::Coord a = boxes[i].lo >> kLeafLog2, b = boxes[i].hi >> kLeafLog2;
        offset[i + 1] = offset[i] + static_cast<std::size_t>(b.x() - a.x() + 1) *
                                        static_cast<std::size_t>(b.y() - a.y() + 1) *
                                        static_cast<std::size_t>(b.z() - a.z() + 1);
      }
      std::vector<LeafRef> refs(offset[nprim]);
      core::parallel_for(
          nprim, params.threads,
          [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
              const openvdb::Coord a = boxes[i].lo >> kLeafLog2, b = boxes[i].hi >> kLeafLog2;
              std::size_t k = offset[i];
              for (int x = a.x(); x <= b.x(); ++x)
                for (int y = a.y(); y <= b.y(); ++y)
                  for (int z = a.z(); z <= b.z(); ++z) refs[k++] = {leaf_key(x, y, z), static_cast<std::uint32_t>(i)};
            }
          },
          256);
      tbb::parallel_sort(refs.begin(), refs.end());  // unique elements: the sorted order is unique too
      std::vector<std::size_t> runs;
      for (std::size_t k = 0; k < refs.size(); ++k)
        if (k == 0 || refs[k].leaf != refs[k - 1].leaf) runs.push_back(k);
      runs.push_back(refs.size());

      const std::size_t nleaves = runs.size() - 1;
      std::vector<std::unique_ptr<FloatLeaf>> leaves(nleaves);
      const double nudge = 1e-3 * voxel;  // mm: moves the surface by at most this much
      // Leaves in blocks, so the progress callback runs on this thread between them; the blocks split
      // the work the same way for any thread count, and each leaf is computed alone anyway.
      const std::size_t block = std::max<std::size_t>(256, nleaves / 64 + 1);
      for (std::size_t first = 0; first < nleaves; first += block) {
        report_progress(params, p0 + (p1 - p0) * static_cast<double>(first) / static_cast<double>(nleaves));
        core::parallel_for(
            std::min(nleaves, first + block) - first, params.threads,
            [&](std::size_t begin, std::size_t end) {
              std::array<double, FloatLeaf::SIZE> d;
              for (std::size_t l = first + begin; l < first + end; ++l) {
                const openvdb::Coord origin = leaf_origin(refs[runs[l]].leaf);
                const openvdb::Coord last = origin.offsetBy(FloatLeaf::DIM - 1);
                d.fill(band);
                for (std::size_t k = runs[l]; k < runs[l + 1]; ++k) {
                  const std::uint32_t i = refs[k].prim;
                  const openvdb::Coord a = openvdb::Coord::maxComponent(boxes[i].lo, origin);
                  const openvdb::Coord b = openvdb::Coord::minComponent(boxes[i].hi, last);
                  for (int x = a.x(); x <= b.x(); ++x)
                    for (int y = a.y(); y <= b.y(); ++y)
                      for (int z = a.z(); z <= b.z(); ++z) {
                        double& slot = d[FloatLeaf::coordToOffset(openvdb::Coord(x, y, z))];
                        // already deeper than the band: stored as -band whatever else overlaps it (below), so
                        // its distance to this primitive is not needed (in a thick or closed shell, most are)
                        if (slot <= -band) continue;
                        const Vec3 p(x * voxel, y * voxel, z * voxel);
                        const double dist = i < cs.size() ? cs[i].distance(p) : ss[i - cs.size()].distance(p);
                        slot = std::min(slot, dist);
                      }
                }
                if (cut_below)  // intersect with the half space above the base plane
                  for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n)
                    d[n] = std::max(d[n], cut_z - (origin.z() + FloatLeaf::offsetToLocalCoord(n).z()) * voxel);
                bool any = false;
                for (double v : d) any = any || std::abs(v) < band;
                if (!any) continue;  // entirely inside or outside: the flood fill below supplies the sign
                auto leaf = std::make_unique<FloatLeaf>(origin, bg, false);
                for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
                  const double v = d[n];
                  // A value at or next to 0 puts the crossings of several voxel edges on the same point and
                  // volumeToMesh then emits distinct vertices at one position (zero-area triangles); push
                  // it off.
                  if (std::abs(v) < nudge)
                    leaf->setValueOn(n, static_cast<float>(v < 0 ? -nudge : nudge));
                  else if (std::abs(v) < band)
                    leaf->setValueOn(n, static_cast<float>(v));
                  else
                    leaf->setValueOff(n, v < 0 ? -bg : bg);
                }
                leaves[l] = std::move(leaf);
              }
            },
            16);
      }
      report_progress(params, p1);
      auto& tree = grid->tree();
      for (auto& leaf : leaves)
        if (leaf) tree.addLeaf(leaf.release());
      openvdb::tools::signedFloodFill(tree);
    });
    return grid;
  };

  init_openvdb();
  openvdb::FloatGrid::Ptr grid;
  const double close = closing_radius(params, scale);  // mm: radius of the shell's closing
  if (!slabs.empty()) note_long_closing(params, close, voxel);
  if (close > 0 && !slabs.empty()) {
    // The shell closed (dilated by `close`, then eroded by it). The dilated slabs' grid is made exact by
    // fast sweeping from its surface, on a band widened inward past `close`; its level set at -close is
    // the eroded surface. A gap of width w in a sheet of half thickness h stays closed while the dilated
    // sheet covers its middle deeper than `close`: w < 2 sqrt(h^2 + 2 h close). A cut is made `close`
    // lower, so the erosion brings it up to base_z.
    std::vector<Slab> wide;
    wide.reserve(slabs.size());
    for (const Slab& w : slabs) wide.emplace_back(w.p0, w.p1, w.p2, w.h + close);
    const openvdb::FloatGrid::Ptr dilated = rasterise({}, wide, cut, base_z - close, 0.0, 0.5);
    const int inner = static_cast<int>(std::ceil(close / voxel)) + kHalfWidth + 1;  // voxels past the band
    openvdb::FloatGrid::Ptr closed;
    core::with_threads(params.threads, [&] {
      // OpenVDB's sweeps take no interrupter: a cancel is seen between them (each a few seconds to tens of
      // seconds on a large shell) and every few thousand leaves of the erosion
      const openvdb::FloatGrid::Ptr exact = openvdb::tools::sdfToSdf(*dilated);
      report_progress(params, 0.55);
      closed = openvdb::tools::dilateSdf(*exact, inner, openvdb::tools::NN_FACE_EDGE, 1,
                                         openvdb::tools::FastSweepingDomain::SWEEP_LESS_THAN_ISOVALUE);
      report_progress(params, 0.65);
      const double leaves = static_cast<double>(closed->tree().leafCount());
      std::size_t done = 0;
      // The erosion, over every voxel of every leaf, so that none is left unwritten with a sign a flood fill
      // would have to guess. Inactive voxels lie past the widened band (outside, or deeper inside than
      // `close` plus the band): their sign alone decides.
      for (auto leaf = closed->tree().beginLeaf(); leaf; ++leaf, ++done) {
        if (done % 4096 == 0) report_progress(params, 0.65 + 0.1 * static_cast<double>(done) / std::max(leaves, 1.0));
        for (openvdb::Index n = 0; n < FloatLeaf::SIZE; ++n) {
          const float v = leaf->getValue(n);
          if (!leaf->isValueOn(n)) {
            leaf->setValueOff(n, v < 0 ? -bg : bg);
            continue;
          }
          const double d = static_cast<double>(v) + close;
          if (std::abs(d) < band)
            leaf->setValueOn(n, static_cast<float>(d));
          else
            leaf->setValueOff(n, d < 0 ? -bg : bg);
        }
      }
      openvdb::tools::changeLevelSetBackground(closed->tree(), bg);  // tiles: +-bg by their sign
      openvdb::tools::pruneLevelSet(closed->tree());
    });
    closed->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    closed->setGridClass(openvdb::GRID_LEVEL_SET);
    report_progress(params, 0.75);
    grid = caps.empty() ? closed : rasterise(caps, {}, cut, base_z, 0.75, 1.0);
    if (!caps.empty()) core::with_threads(params.threads, [&] { openvdb::tools::csgUnion(*grid, *closed); });
    report_progress(params, 1.0);
    // as for the gathered leaves: no value at (or next to) 0, where volumeToMesh would make zero-area triangles
    const float nudge = static_cast<float>(1e-3 * voxel);
    for (auto v = grid->tree().beginValueOn(); v; ++v)
      if (std::abs(*v) < nudge) v.setValue(*v < 0 ? -nudge : nudge);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("surface");  // the name Houdini and Blender give a level set
  } else {
    grid = rasterise(caps, slabs, cut, base_z, 0.0, 1.0);
  }

  auto impl = std::make_shared<LevelSet::Impl>();
  impl->grid = grid;
  impl->voxel_size = voxel;
  impl->scale = scale;
  if (cut) impl->base_z = base_z;
  impl->active_voxels = static_cast<std::size_t>(grid->activeVoxelCount());
  if (report) {
    report->active_voxels = impl->active_voxels;
    report->voxelise_seconds = seconds_since(t0);
  }
  return LevelSet(std::move(impl));
}

PrintableMesh thicken(const std::vector<Segment>& segments, const std::vector<std::array<Vec3, 3>>& shell_triangles,
                      const ThickenParams& params, ThickenReport* report) {
  return mesh_level_set(voxelise(segments, shell_triangles, params, report), params, report);
}

}  // namespace cellform::exporters
