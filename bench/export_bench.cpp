// Benchmarks of printable meshes: thickening a 50k-segment vein tree (time, peak memory) and checking the result.
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>

#include "bench/bench.h"
#include "core/random.h"
#include "export/mesh_check.h"
#include "export/printable.h"

namespace cellform::bench {

namespace {

using core::Vec3;
using exporters::Segment;

/// A synthetic vein tree standing in for a grown 50,000-cell form: a 3-D binary tree of 15 levels,
/// branches split at +-35 degrees about a random axis and shrink by 0.8 per level, every branch cut
/// into unit-length segments (a cell spacing), radii by Murray's law (0.1 * leaves^(1/3) model units).
/// 44,288 segments; scaled to 120 mm (0.81 mm per unit) they are ~0.8 mm long, mostly at the 0.4 mm minimum
/// radius, and fuse into a dense tangle (genus ~3200, 4.8M triangles): harsher than a leaf-like sheet.
const std::vector<Segment>& tree50k() {
  static const std::vector<Segment> segments = [] {
    std::vector<Segment> s;
    core::Rng rng(2024);
    const int levels = 15;
    struct Branch {
      Vec3 start, dir;
      int level;
    };
    std::vector<Branch> stack{{Vec3::Zero(), Vec3::UnitZ(), 0}};
    while (!stack.empty()) {
      const Branch b = stack.back();
      stack.pop_back();
      const double length = 26 * std::pow(0.8, b.level);
      const int pieces = std::max(1, static_cast<int>(std::lround(length)));
      const double r = 0.1 * std::cbrt(std::pow(2.0, levels - 1 - b.level));
      Vec3 p = b.start;
      for (int i = 0; i < pieces; ++i) {
        const Vec3 q = p + b.dir * (length / pieces);
        s.push_back({p, q, r, r});
        p = q;
      }
      if (b.level + 1 >= levels) continue;
      Vec3 axis = b.dir.cross(rng.unit_vector());
      axis.normalize();
      for (double angle : {0.61, -0.61})
        stack.push_back({p, Eigen::AngleAxisd(angle, axis) * b.dir, b.level + 1});
    }
    return s;
  }();
  return segments;
}

void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }

exporters::ThickenReport thicken_once(double voxel, exporters::PrintableMesh* out = nullptr) {
  exporters::ThickenParams p;
  p.voxel_size = voxel;
  exporters::ThickenReport report;
  auto mesh = exporters::thicken(tree50k(), {}, p, &report);
  if (out) *out = std::move(mesh);
  return report;
}

double seconds(const std::function<void()>& f) {
  const auto a = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

const Register r1{{"export.thicken.50k", "s",
                   "thicken a synthetic 50k-segment vein tree to a printable mesh at default settings (120 mm, "
                   "voxel 0.2 mm, adaptivity 0.2, intersection repair included)",
                   3, [] { return seconds([] { thicken_once(0); }); }}};
const Register r2{{"export.thicken.50k.peak_mb", "MB",
                   "peak resident memory while thickening the 50k-segment tree at default settings", 1, [] {
                     tree50k();
                     reset_peak_rss();
                     thicken_once(0);
                     return peak_rss_bytes() / 1e6;
                   }}};
const Register r3{{"export.thicken.50k.fine", "s", "thicken the 50k-segment tree with 0.16 mm voxels (the finest the 2 GB estimate allows)", 1,
                   [] { return seconds([] { thicken_once(0.16); }); }}};
const Register r4{{"export.thicken.50k.fine.peak_mb", "MB", "peak resident memory thickening with 0.16 mm voxels", 1,
                   [] {
                     tree50k();
                     reset_peak_rss();
                     thicken_once(0.16);
                     return peak_rss_bytes() / 1e6;
                   }}};
const Register r5{{"export.check.50k", "s", "check_mesh of the 50k-segment tree's printable mesh (default settings)", 3,
                   [] {
                     static exporters::PrintableMesh mesh;
                     if (mesh.triangles.empty()) thicken_once(0, &mesh);
                     return seconds([] { exporters::check_mesh(mesh); });
                   }}};

}  // namespace

}  // namespace cellform::bench
