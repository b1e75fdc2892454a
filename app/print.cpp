// print{...}: thickening the veins and the cell sheet into a printable solid, and writing its files.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app/memory.h"
#include "app/run.h"
#include "app/run_internal.h"
#include "cells/surface.h"
#include "core/errors.h"
#include "export/mesh_check.h"
#include "export/mesh_files.h"
#include "export/printable.h"
#include "export/stand.h"

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::chrono::seconds kQuietStage{10};  // a print stage not on a terminal says its quarters after this

double shell_closing(const cells::Cells& c, double close_holes) { return 0.5 * close_holes * median_link_length(c); }

double median_link_length(const cells::Cells& c) {
  std::vector<double> lengths;
  const std::size_t stride = static_cast<std::size_t>(std::max(c.link_stride, 0));
  for (std::size_t i = 0; i < c.size(); ++i)
    for (std::size_t k = 0; k < stride && i * stride + k < c.links.size(); ++k) {
      const core::Index j = c.links[i * stride + k];
      if (j != core::kNoIndex && j < c.size() && j != i) lengths.push_back((c.position[j] - c.position[i]).norm());
    }
  if (lengths.empty()) return 0;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  return lengths[lengths.size() / 2];
}

namespace {

/// Model units: the centre of the bounding box of what is printed when the print would reach more than 2^17
/// voxels from the origin (a form at site coordinates, say), else zero. There a 32-bit coordinate (the mesher's,
/// STL's) is coarser than 1/128 of a voxel: a form 196 m out in mm at 0.2 mm voxels (a 32-bit step of 1/13
/// voxel) got ten times the triangles, crossing and zero-area ones. The scale is the print's (`print_scale`,
/// which does not depend on where the form lies), the voxel size the one the print takes: an automatic voxel
/// raised to fit print.max_memory reaches farther (the plan, made before any voxel, is asked for it). Zero when
/// the input is not finite (voxelise then says which part).
core::Vec3 far_centre(const std::vector<exporters::Segment>& segments,
                      const std::vector<std::array<core::Vec3, 3>>& shell, const PrintSpec& spec,
                      const exporters::ThickenParams& tp) {
  core::Vec3 lo = core::Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const exporters::Segment& s : segments) {
    lo = lo.cwiseMin(s.a).cwiseMin(s.b);
    hi = hi.cwiseMax(s.a).cwiseMax(s.b);
  }
  for (const auto& t : shell)
    for (const core::Vec3& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  if (!lo.allFinite() || !hi.allFinite()) return core::Vec3::Zero();
  const double reach = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
  double scale = 0;  // mm per model unit
  try {
    scale = exporters::print_scale(segments, shell, tp);
  } catch (const core::InvalidInput&) {
    return core::Vec3::Zero();  // a non-finite radius, say: voxelise says which segment
  }
  double voxel = spec.voxel_size > 0  // mm
                     ? spec.voxel_size
                     : exporters::automatic_voxel_size(spec.min_radius, spec.shell_thickness, !shell.empty());
  if (spec.voxel_size == 0 && reach * scale > 0x1p17 * voxel) {
    struct Planned {
      double voxel;  // mm
    };
    exporters::ThickenParams probe = tp;
    probe.progress = nullptr;
    probe.note = nullptr;
    probe.planned = [](const exporters::ThickenReport& plan) { throw Planned{plan.voxel_size}; };
    try {
      (void)exporters::voxelise(segments, shell, probe, nullptr);
    } catch (const Planned& plan) {
      voxel = plan.voxel;
    } catch (const std::exception&) {  // (the print itself says what is wrong)
    }
  }
  return reach * scale > 0x1p17 * voxel ? core::Vec3(0.5 * (lo + hi)) : core::Vec3::Zero();
}

}  // namespace

/// Thickens vein segments (model units, Murray radii) and shell triangles into a printable solid and
/// writes the requested formats into `dir`. Appends the file names to `names`; returns what run.json
/// records. Throws on failure.
namespace {

exporters::ThickenParams thicken_params(const PrintSpec& spec, int threads, double close_holes) {
  exporters::ThickenParams tp;
  tp.scale = spec.scale;
  tp.auto_extent = spec.size;
  tp.voxel_size = spec.voxel_size;
  tp.min_radius = spec.min_radius;
  tp.shell_thickness = spec.shell_thickness;
  tp.adaptivity = spec.adaptivity;
  tp.max_memory_bytes = spec.max_memory_mb * 1e6;
  tp.threads = threads;
  tp.fill_cavities = spec.fill_cavities;
  tp.flat_base = spec.flat_base;
  tp.lay_flat = spec.lay_flat;
  tp.close_holes = close_holes;
  tp.close_holes_max = spec.close_holes_max;
  return tp;
}

}  // namespace

double planned_print_scale(const PrintSpec& spec, const std::vector<exporters::Segment>& segments,
                           const std::vector<std::array<core::Vec3, 3>>& shell) {
  return exporters::print_scale(segments, shell, thicken_params(spec, 1, 0));
}

namespace {

/// How the printed solid stands on the plane of its lowest point (run.json's print.stand; null for a form of
/// several parts, each of which stands or not), and a word when it falls over, from where it lies or at a small
/// tilt (exporters::falls): with the print.flat_base that would give it a foot.
json say_stand(std::ostream& err, const exporters::PrintableMesh& mesh, double flat_base, std::size_t pieces,
               int threads) {
  if (pieces != 1) return nullptr;
  const exporters::Stand st = exporters::stand_on_bed(mesh);
  if (!st.measured) return nullptr;
  const core::Vec3& g = st.centre_of_mass;
  json j = {{"footprint_mm2", st.footprint_area},
            {"tip_angle_deg", st.tip_angle},
            {"centre_of_mass_mm", {g.x(), g.y(), g.z()}},
            {"settle_angle_deg", st.settle_angle},
            {"flat_base_to_stand_mm", nullptr}};
  if (!exporters::falls(st)) return j;  // stands, or rocks a few degrees onto more of its underside
  const double cut = exporters::base_cut_to_stand(mesh, exporters::kFootTip, 0.5, 50, threads);
  const double base = std::ceil((flat_base + cut) * 10 - 1e-9) / 10;  // mm, as the user would write it
  if (cut > 0) j["flat_base_to_stand_mm"] = base;
  const std::string footprint = "the " + core::number_text(std::round(st.footprint_area * 10) / 10) +
                                " square mm that touch the bed (the convex hull of its lowest " +
                                core::number_text(exporters::kFirstLayer) + " mm)";
  const std::string cure =
      cut > 0 ? "print.flat_base = " + core::number_text(base) + " gives it a flat foot that tips only past " +
                    core::number_text(exporters::kFootTip) + " degrees"
      : st.margin <= 0
          ? "no cut off its lower half, in one piece, gives it a foot that tips only past " +
                core::number_text(exporters::kFootTip) + " degrees: print it with supports, turned, or on a base"
          : "no cut off its lower half, in one piece, gives it a foot that tips only past " +
                core::number_text(exporters::kFootTip) + " degrees (a brim, or a base, steadies it)";
  auto tenths = [](double mm) {  // (a walkthrough's print lay "0 mm beyond" its footprint)
    const double r = std::round(mm * 10) / 10;
    return r == 0 && mm > 0 ? std::string("under 0.1") : core::number_text(r);
  };
  if (st.margin <= 0)
    err << "cellform: warning: the printable solid does not stand by itself: its centre of mass lies "
        << tenths(-st.margin) << " mm beyond " << footprint
        << ": only bed adhesion (or supports) holds it while it prints, and off the bed it rolls "
        << core::number_text(std::round(st.settle_angle)) << " degrees before it rests; " << cure << "\n";
  else
    err << "cellform: note: print: the printable solid stands, but tips over when tilted "
        << core::number_text(std::round(st.tip_angle * 10) / 10) << " degrees, and then rolls "
        << core::number_text(std::round(st.settle_angle)) << " degrees: its centre of mass lies " << tenths(st.margin)
        << " mm inside the edge of " << footprint << "; " << cure << "\n";
  return j;
}

/// ": the largest W x D x H mm about {x, y, z}; the others ..., places in model units" for a printed solid of several
/// pieces (surfaces of positive volume; cavities are not pieces), the smaller ones where a script places them:
/// the mesh is in mm, (model - centre) * scale.
std::string pieces_text(const exporters::PrintableMesh& mesh, double scale, const core::Vec3& centre) {
  const std::vector<std::uint32_t> part = exporters::part_labels(mesh);
  struct Piece {
    double volume = 0;
    core::Vec3 lo = core::Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  };
  std::vector<Piece> piece(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    Piece& q = piece[part[t[0]]];
    const core::Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    q.volume += a.dot(b.cross(c)) / 6;
    for (const core::Vec3* v : {&a, &b, &c}) q.lo = q.lo.cwiseMin(*v), q.hi = q.hi.cwiseMax(*v);
  }
  std::vector<Piece> solid;
  for (const Piece& q : piece)
    if (q.volume > 0) solid.push_back(q);
  if (solid.size() < 2) return {};
  std::stable_sort(solid.begin(), solid.end(), [](const Piece& a, const Piece& b) { return a.volume > b.volume; });
  auto size = [](const Piece& q) {
    const core::Vec3 d = q.hi - q.lo;
    return core::number_text(std::round(d.x() * 10) / 10) + " x " + core::number_text(std::round(d.y() * 10) / 10) +
           " x " + core::number_text(std::round(d.z() * 10) / 10) + " mm";
  };
  auto place = [&](const Piece& q) {
    const core::Vec3 at = (q.lo + q.hi) / 2 / scale + centre;
    return " about " +
           core::point_text(std::round(at.x() * 10) / 10, std::round(at.y() * 10) / 10, std::round(at.z() * 10) / 10);
  };
  std::string text = ": the largest " + size(solid[0]) + place(solid[0]) + "; ";
  for (std::size_t k = 1; k < solid.size() && k <= 3; ++k)
    text += (k > 1 ? ", " : solid.size() == 2 ? "the other " : "the others ") + size(solid[k]) + place(solid[k]);
  if (solid.size() > 4) text += " and " + std::to_string(solid.size() - 4) + " more";
  return text + ", places in model units";
}

}  // namespace

json thicken_and_write(const fs::path& dir, const PrintSpec& spec, const std::vector<exporters::Segment>& segments,
                       const std::vector<std::array<core::Vec3, 3>>& shell, int threads,
                       std::vector<std::string>& names, std::ostream& err, bool quiet, double close_holes, bool sheet) {
  exporters::ThickenParams tp = thicken_params(spec, threads, close_holes);
  // checked before the first voxel: the mesher cannot fail cleanly where the machine has less than the estimate
  const MemoryHeadroom room = memory_headroom();
  tp.available_bytes = room.bytes;
  tp.available_name = room.name;
  // Ctrl-C stops the thickening at the next block; on a terminal the stage shows its percentage. A Ctrl-C
  // that stopped the steps before printing began asked for the outputs, the solid included: it is not one.
  const bool tty = !quiet && ::isatty(2) != 0;
  tp.note = [&err, tty](const std::string& n) { err << (tty ? "\n" : "") << "cellform: note: print: " << n << "\n"; };
  const bool stopped_before = g_interrupt.load();
  g_print_cancel = false;
  g_print_after_interrupt = stopped_before;
  g_printing = !stopped_before;
  struct PrintDone {
    ~PrintDone() { g_print_after_interrupt = g_printing = false; }
  } print_done;
  // not on a terminal (a log), a stage still running after 10 s says each quarter it passes on a line of its own
  auto stage_progress = [&err, tty, quiet, stopped_before](const char* stage) {
    return [&err, tty, quiet, stopped_before, stage, shown = -1,
            began = std::chrono::steady_clock::now()](double f) mutable {
      const int pct = static_cast<int>(f * 100);
      if (tty && pct != shown) {
        shown = pct;
        err << "\r" << stage << " " << pct << "%" << std::flush;
        if (pct == 100) err << "\n";
      } else if (!tty && !quiet && pct / 25 > shown / 25 && std::chrono::steady_clock::now() - began > kQuietStage) {
        shown = pct;
        err << stage << " " << pct / 25 * 25 << "%\n";
      }
      return stopped_before ? !g_print_cancel.load() : !g_interrupt.load();
    };
  };
  if (segments.empty() && shell.empty())
    throw NothingToPrint(
        g_interrupt.load() ? "print: nothing to print: the run was interrupted before anything printable grew"
        : !spec.shell ? "print: nothing to print yet (no vein has grown; run longer, lower venation.threshold, or use "
                        "shell = true)"
        : spec.veins  ? "print: nothing to print yet (no vein has grown, and the cells form no sheet of triangles to "
                        "thicken; grow a sheet, for example from a disc{...})"
                      : "print: the cells form no sheet of triangles to thicken yet (a line or a single cell has no "
                        "surface; grow a sheet, for example from a disc{...})");
  if (!quiet)
    err << "thickening "
        << (segments.empty() && spec.shell
                ? std::string("the cell sheet")
                : std::to_string(segments.size()) + " vein segments" + (spec.shell ? " and the cell sheet" : ""))
        << "...\n";
  exporters::ThickenReport rep;
  tp.progress = stage_progress("voxelising");
  exporters::LevelSet level_set;
  // a form far from the origin is printed about its own centre (run.json's print.origin_mm places it back)
  const core::Vec3 centre = far_centre(segments, shell, spec, tp);
  std::vector<exporters::Segment> moved_segments;
  std::vector<std::array<core::Vec3, 3>> moved_shell;
  if (centre != core::Vec3::Zero()) {
    moved_segments = segments;
    for (exporters::Segment& s : moved_segments) {
      s.a -= centre;
      s.b -= centre;
    }
    moved_shell = shell;
    for (auto& t : moved_shell)
      for (core::Vec3& p : t) p -= centre;
  }
  const bool moved = centre != core::Vec3::Zero();
  // said before the stages, which may take minutes (they came after the voxels, 20 to 30 s into a large print)
  tp.planned = [&](const exporters::ThickenReport& plan) {
    // nearly every vein raised to the printable minimum, which is more than a segment long at this scale: dense
    // veins (a colonisation preset printed small) fuse into a plate, which a note says before the slicer does
    if (!segments.empty() && plan.raised_radii * 10 >= segments.size() * 2 * 9 && plan.scale > 0) {
      std::vector<double> lengths;
      lengths.reserve(segments.size());
      for (const exporters::Segment& g : segments) lengths.push_back((g.b - g.a).norm());
      const auto mid = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
      std::nth_element(lengths.begin(), mid, lengths.end());
      const double segments_per_radius = *mid > 0 ? spec.min_radius / plan.scale / *mid : 0.0;
      // (99%, not a rounded 100%, while any radius is not raised; one segment, not "1 segments")
      const double ends = static_cast<double>(2 * segments.size()), shown = std::round(segments_per_radius * 10) / 10;
      const double percent = std::round(100.0 * static_cast<double>(plan.raised_radii) / ends);
      if (segments_per_radius > 1)
        err << "cellform: note: print: "
            << core::number_text(static_cast<double>(plan.raised_radii) < ends ? std::min(percent, 99.0) : 100.0)
            << "% of the vein radii are raised to print.min_radius (" << core::number_text(spec.min_radius)
            << " mm), which is " << core::number_text(shown) << (shown == 1 ? " vein segment" : " vein segments")
            << " at this scale: veins closer than twice that fuse, and closely spaced veins print as a "
               "plate (give a larger "
            << (spec.scale > 0 ? "print.scale" : "print.size")
            << ", or a smaller print.min_radius if the printer allows)\n";
    }
    if (spec.flat_base > 0 && spec.flat_base > 0.5 * plan.height)  // (a cut above the whole form is refused)
      err << "cellform: note: print: print.flat_base (" << core::number_text(spec.flat_base)
          << " mm) cuts away the lower " << core::number_text(std::round(100 * spec.flat_base / plan.height))
          << "% of the form's " << core::number_text(std::round(plan.height * 10) / 10)
          << " mm height, and what is left may be thinner than print.min_radius promises (a flat form prints "
             "lying flat: flat_base = 0, or a cut of a millimetre or so, and print.lay_flat = true rests all its veins "
             "on the bed)\n";
    if (plan.voxel_raised_from > 0)  // said even when quiet: the print is coarser than the default promises
      err << "cellform: note: print: the automatic voxel size " << plan.voxel_raised_from
          << (plan.voxel_raised_from < spec.min_radius / 2 ? " mm (half print.shell_thickness) "
                                                           : " mm (print.min_radius / 2) ")
          << "would need more memory than print.max_memory (" << spec.max_memory_mb << " MB); using " << plan.voxel_size
          << " mm (set print.voxel_size, or raise print.max_memory, for a finer surface)\n";
  };
  try {
    level_set = exporters::voxelise(moved ? moved_segments : segments, moved ? moved_shell : shell, tp, &rep);
  } catch (const core::InvalidInput& e) {  // the library's names for what the script calls print.*
    std::string m = e.what();
    for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
             {"thicken: ", "print: "},
             {"flat_base", "print.flat_base"},
             {"use a voxel size of", "use a print.voxel_size of"},
             {"a larger voxel size", "a larger print.voxel_size"},
             {"(at most min_radius,", "(at most print.min_radius,"},
             {"above min_radius", "above print.min_radius"},
             {"a smaller scale or size", "a smaller print.size (or print.scale)"},
             {"a smaller scale", "a smaller print.size (or print.scale)"},
             {"use a larger scale", "use a larger print.scale"},
             {"2 min_radius", "2 print.min_radius"},
             {"raise the memory limit", "raise print.max_memory"},
             {"lower the memory limit", "lower print.max_memory"},
             {"a coarser voxel size", "a coarser print.voxel_size"}})
      for (std::size_t at = m.find(from); at != std::string::npos; at = m.find(from, at + to.size()))
        m.replace(at, from.size(), to);
    throw core::InvalidInput(m);
  }
  tp.progress = stage_progress("meshing");
  const exporters::PrintableMesh mesh = exporters::mesh_level_set(level_set, tp, &rep);
  if (mesh.triangles.empty()) {  // a file of no facets is no print: said, not written
    std::ostringstream m;
    m << std::setprecision(4) << "print: the printable solid is empty";
    if (spec.flat_base > 0)
      m << ": print.flat_base (" << spec.flat_base << " mm) leaves " << std::max(rep.height - spec.flat_base, 0.0)
        << " mm of the form's " << rep.height << " mm height, too thin for the print's " << rep.voxel_size
        << " mm voxels; lower print.flat_base";
    else
      m << " (the form is thinner than the print's " << rep.voxel_size
        << " mm voxels); use a smaller print.voxel_size or a larger print.min_radius";
    throw core::InvalidInput(m.str());
  }
  // separate vein trees (several petioles, seeds) join through the sheet they grew in
  const bool join_by_shell = sheet && !spec.shell;
  if (rep.pieces > 1 && spec.pieces == "one")
    throw core::InvalidInput(
        "print{pieces = \"one\"}: the form falls apart into " + std::to_string(rep.pieces) + " parts" +
        pieces_text(mesh, rep.scale, moved ? centre : core::Vec3::Zero()) + " (" +
        (join_by_shell ? "print.shell = true adds the cell sheet, which joins the trees it connects; " : "") +
        (spec.flat_base > 0 ? "lower print.flat_base, " : "") +
        "raise print.min_radius, grow longer, or set pieces = \"warn\")");
  if (rep.pieces > 1 && spec.pieces == "warn")
    err << "cellform: warning: the printable form has " << rep.pieces << " separate parts"
        << pieces_text(mesh, rep.scale, moved ? centre : core::Vec3::Zero())
        << (join_by_shell ? " (print.shell = true adds the cell sheet, which joins the trees it connects)" : "")
        << "\n";
  if (rep.cavities > 0 && !spec.fill_cavities)  // said even when quiet, as the parts: a print problem
    err << "cellform: warning: the printable solid has " << rep.cavities
        << (rep.cavities == 1 ? " closed cavity (a sealed pocket inside it, which traps"
                              : " closed cavities (sealed pockets inside it, which trap")
        << " resin or powder in resin and powder printing); print.fill_cavities = true fills "
        << (rep.cavities == 1 ? "it" : "them") << "\n";
  if (rep.self_intersections > 0)  // none left in any case tested: said if it happens
    err << "cellform: warning: printable solid: " << rep.self_intersections
        << " pairs of triangles still cross after meshing without merging around them (cellform check FILE "
           "counts them; a finer print.voxel_size may avoid them)\n";
  const json stand = say_stand(err, mesh, spec.flat_base, rep.pieces, threads);
  for (const std::string& f : spec.formats) {
    const std::string name = "printable." + f;
    if (f == "vdb")
      exporters::write_vdb(dir / name, level_set);
    else
      exporters::write_mesh(dir / name, mesh);
    names.push_back(name);
  }
  json printed = {{"scale_mm_per_unit", rep.scale},
                  {"voxel_size_mm", rep.voxel_size},
                  {"voxel_raised_from_mm", rep.voxel_raised_from > 0 ? json(rep.voxel_raised_from) : json(nullptr)},
                  {"segments", rep.segments},
                  {"shell_triangles", rep.shell_triangles},
                  {"raised_radii", rep.raised_radii},
                  {"triangles", rep.triangles},
                  {"parts", rep.pieces},
                  {"cavities", rep.cavities},
                  {"filled_cavities", rep.filled_cavities},
                  // adaptivity 0 skips the search (uniform meshing makes no crossings in any test): not counted
                  {"self_intersections", spec.adaptivity > 0 ? json(rep.self_intersections) : json(nullptr)},
                  {"volume_mm3", rep.volume},
                  {"area_mm2", rep.area},
                  {"seconds", rep.voxelise_seconds + rep.mesh_seconds}};
  printed["stand"] = stand;
  if (spec.flat_base > 0) printed["base_z_mm"] = rep.base_z;
  if (moved) {
    const core::Vec3 origin = centre * rep.scale;
    printed["origin_mm"] = {origin.x(), origin.y(), origin.z()};
    err << "cellform: note: print: the form lies " << core::number_text(origin.norm() / 1000)
        << " m from the origin in the print's millimetres, where 32-bit coordinates (the mesher's, STL's) are "
           "coarser than 1/128 of its "
        << core::number_text(rep.voxel_size) << " mm voxels; printable.* are written about the form's centre, "
        << core::point_text(origin.x(), origin.y(), origin.z())
        << " mm (run.json's print.origin_mm: add it to lay them over cells.obj and veins.obj times the scale)\n";
  }
  return printed;
}

json write_printable(const fs::path& dir, const PrintSpec& spec, const cells::Cells& c, bool has_veins, int threads,
                     std::vector<std::string>& names, std::ostream& err, bool quiet) {
  std::vector<exporters::Segment> segments;
  if (spec.veins && has_veins) {
    const venation::VeinGraph g = venation::vein_graph(c);
    if (!g.edges.empty()) segments = exporters::vein_segments(g);  // petioles alone are no structure to print
  }
  std::vector<std::array<core::Vec3, 3>> shell;
  if (spec.shell) shell = exporters::shell_triangles(c, cells::Surface{cells::covering_triangles(c), {}});
  return thicken_and_write(dir, spec, segments, shell, threads, names, err, quiet,
                           spec.shell ? shell_closing(c, spec.close_holes) : 0.0, true);
}

void say_printed(std::ostream& err, const nlohmann::json& printed) {
  err << "printable solid: " << printed["triangles"] << " triangles, " << printed["parts"] << " part(s), "
      << printed["cavities"]
      << (printed["filled_cavities"] > 0 ? " closed cavities (filled), scale " : " closed cavities, scale ")
      << core::number_text(printed["scale_mm_per_unit"].get<double>()) << " mm per model unit\n";
}

void say_print_failed(std::ostream& err, const std::string& message, const std::string& after, bool retry,
                      const std::filesystem::path& checkpoint, const ScriptLimits& limits) {
  err << "cellform: " << message << (after.empty() ? "" : "\n  (" + after + ")") << "\n";
  if (retry)  // a retry need not grow the cells or veins again
    err << "  to print again with other print.* values: " << continue_command(checkpoint, limits)
        << " --set print.NAME=VALUE\n";
}

}  // namespace cellform::app
