// Benchmarks of printable meshes: thickening a 50k-segment vein tree (time, peak memory) and checking the result.
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>

#include "bench/bench.h"
#include "cells/simulation.h"
#include "cells/surface.h"
#include "core/random.h"
#include "export/mesh_check.h"
#include "export/printable.h"
#include "export/thickness.h"
#include "forms/shapes.h"
#include "venation/canalisation.h"

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
      for (double angle : {0.61, -0.61}) stack.push_back({p, Eigen::AngleAxisd(angle, axis) * b.dir, b.level + 1});
    }
    return s;
  }();
  return segments;
}

void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }

// The process's peak (VmHWM) counts the forms earlier benchmarks of a sweep keep cached (a 1,000,000-cell
// simulation of cells.step.1m adds about 160 MB): the figure is the benchmark's own when it runs alone.
/// The note of a peak_mb benchmark `name`: what its figure holds in a sweep.
std::string alone(const std::string& name) {
  return " (the process's peak, which counts what earlier benchmarks keep: run it alone, cellform-bench '" + name +
         "$')";
}

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

const Register r1{
    {"export.thicken.tree44k", "s",
     "stress: thicken a synthetic 44k-segment 3-D vein tree to a printable mesh at default settings (120 mm, "
     "voxel 0.2 mm, adaptivity 0.2, intersection repair included)",
     3, [] { return seconds([] { thicken_once(0); }); }}};
const Register r2{{"export.thicken.tree44k.peak_mb", "MB",
                   "peak resident memory while thickening the 44k-segment synthetic tree at default settings" +
                       alone("export.thicken.tree44k.peak_mb"),
                   1, [] {
                     tree50k();
                     reset_peak_rss();
                     thicken_once(0);
                     return peak_rss_bytes() / 1e6;
                   }}};
const Register r3{{"export.thicken.tree44k.fine", "s",
                   "thicken the 44k-segment synthetic tree with 0.16 mm voxels (the finest the 2 GB estimate allows)",
                   1, [] { return seconds([] { thicken_once(0.16); }); }}};
const Register r4{{"export.thicken.tree44k.fine.peak_mb", "MB",
                   "peak resident memory thickening with 0.16 mm voxels" + alone("export.thicken.tree44k.fine.peak_mb"),
                   1, [] {
                     tree50k();
                     reset_peak_rss();
                     thicken_once(0.16);
                     return peak_rss_bytes() / 1e6;
                   }}};
const Register r5{{"export.check.tree44k", "s",
                   "check_mesh of the 44k-segment synthetic tree's printable mesh (default settings)", 3, [] {
                     static exporters::PrintableMesh mesh;
                     if (mesh.triangles.empty()) thicken_once(0, &mesh);
                     return seconds([] { exporters::check_mesh(mesh); });
                   }}};

/// A cone of 20,000 slivers round its tip and 20,000 round its base's centre, as CAD programs write a
/// finely divided cone or a cylinder's caps: every sliver's box holds the axis.
const exporters::PrintableMesh& cone40k() {
  static const exporters::PrintableMesh cone = [] {
    constexpr std::uint32_t n = 20000;
    exporters::PrintableMesh m;
    m.vertices.emplace_back(0, 0, 10);
    for (std::uint32_t i = 0; i < n; ++i)
      m.vertices.emplace_back(5 * std::cos(2 * M_PI * i / n), 5 * std::sin(2 * M_PI * i / n), 0);
    m.vertices.emplace_back(0, 0, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      m.triangles.push_back({0, i + 1, (i + 1) % n + 1});
      m.triangles.push_back({n + 1, (i + 1) % n + 1, i + 1});
    }
    return m;
  }();
  return cone;
}
const Register r5b{{"export.check.cone40k", "s",
                    "what cellform check does (check_mesh and wall_thickness) to a cone of 2 x 20,000 slivers", 3, [] {
                      const auto& m = cone40k();
                      return seconds([&] {
                        exporters::check_mesh(m);
                        exporters::wall_thickness(m);
                      });
                    }}};

/// A grown form: a disc of cells divided by age up to 50,000 cells with auxin canalisation every step
/// (threshold 30), as a script would grow it. Returns its veins as segments (Murray radii) and its sheet.
struct GrownForm {
  std::vector<Segment> veins;
  std::vector<std::array<Vec3, 3>> sheet;
  std::size_t cells = 0;
};
const GrownForm& leaf50k() {
  static const GrownForm form = [] {
    cells::Params p;
    p.weights[0].separation = 0.05;
    p.drag = Vec3(0.85, 0.85, 0.3);
    p.time_step = 0.2;
    p.division.trigger = cells::DivisionTrigger::age;
    p.division.division_age = 10;
    p.division.probability = 0.5;
    p.division.max_cells = 50000;
    cells::Simulation sim(p, 11);
    sim.set_threads(2);
    for (const Vec3& q : forms::hex_disc(Vec3::Zero(), Vec3::UnitZ(), 7, 1.0)) cells::add_cell(sim.cells(), q);
    sim.cells().type[0] = cells::CellType::petiole;
    sim.cells().fixed[0] = 1;
    venation::Params vp;
    vp.threshold = 30;
    venation::Workspace ws;
    while (sim.cells().size() < 50000) {
      sim.step();
      venation::canalise(sim.cells(), vp, {}, ws);
    }
    GrownForm f;
    f.cells = sim.cells().size();
    f.veins = exporters::vein_segments(venation::vein_graph(sim.cells()));
    f.sheet = exporters::shell_triangles(sim.cells(), cells::triangulate(sim.cells(), false));
    return f;
  }();
  return form;
}

double thicken_leaf(double voxel, bool sheet, double close_holes = 0) {
  exporters::ThickenParams p;
  p.voxel_size = voxel;
  p.close_holes = close_holes;
  const GrownForm& f = leaf50k();
  return seconds([&] { exporters::thicken(f.veins, sheet ? f.sheet : std::vector<std::array<Vec3, 3>>{}, p); });
}

const Register r6{{"export.thicken.leaf50k", "s",
                   "thicken the veins of a grown 50,000-cell form (cells + canalisation) at default settings", 3,
                   [] { return thicken_leaf(0, false); }}};
const Register r7{{"export.thicken.leaf50k.peak_mb", "MB",
                   "peak resident memory of export.thicken.leaf50k" + alone("export.thicken.leaf50k.peak_mb"), 1, [] {
                     leaf50k();
                     reset_peak_rss();
                     thicken_leaf(0, false);
                     return peak_rss_bytes() / 1e6;
                   }}};
const Register r8{{"export.thicken.leaf50k.fine", "s", "the same with 0.1 mm voxels (half the default)", 1,
                   [] { return thicken_leaf(0.1, false); }}};
const Register r9{{"export.thicken.leaf50k.shell", "s", "veins and the cell sheet as a 0.6 mm shell, default settings",
                   1, [] { return thicken_leaf(0, true); }}};
// a wide closing: close_holes 0.5 model units (half the median link, as print.close_holes = 1 asks), 2.8 mm on
// this 120 mm form, left uncapped (cellform run caps it at print.close_holes_max, 2 mm by default)
const Register r9b{{"export.thicken.leaf50k.shell.closed", "s",
                    "the same shell with its gaps closed over half a cell spacing (0.5 model units: 2.8 mm, uncapped)",
                    1, [] { return thicken_leaf(0, true, 0.5); }}};
const Register r9c{{"export.thicken.leaf50k.shell.closed.peak_mb", "MB",
                    "peak resident memory of export.thicken.leaf50k.shell.closed" +
                        alone("export.thicken.leaf50k.shell.closed.peak_mb"),
                    1, [] {
                      leaf50k();
                      reset_peak_rss();
                      thicken_leaf(0, true, 0.5);
                      return peak_rss_bytes() / 1e6;
                    }}};
const Register r10{{"export.thicken.leaf50k.segments", "segments", "vein segments of the grown 50,000-cell form", 1,
                    [] { return static_cast<double>(leaf50k().veins.size()); }}};

}  // namespace

}  // namespace cellform::bench
