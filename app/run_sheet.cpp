// surface{cells = true}: the cell sheet grown before space colonisation puts veins on it, with its own
// checkpoints (mode "sheet") so that a Ctrl-C or a failure while it grows loses nothing.
#include "app/run_sheet.h"

#include "app/progress.h"
#include "app/run.h"
#include "cells/serialize.h"
#include "cells/surface.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "forms/scene.h"
#include "venation/domain.h"

#include <cmath>
#include <functional>

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A checkpoint taken while surface{cells = true}'s sheet grows: the cells and their step, with what
/// resume needs to finish the growth bit-identically and then grow the veins.
std::string sheet_checkpoint_bytes(const Start& s, std::uint64_t seed, std::uint64_t target,
                                   const cells::Simulation& sim, std::size_t initial_cells, const json& physics) {
  json meta = checkpoint_meta(s, seed, target, sim.step_count());
  meta["mode"] = "sheet";
  meta["steps_given"] = s.has_target;
  meta["initial_cells"] = initial_cells;
  meta["physics"] = physics;  // a resume grows the rest with these values, whatever the defaults then
  return core::write_chunk_file(
      kCheckpointKind, kCheckpointVersion,
      {{"meta", checkpoint_meta_text(meta)}, {"script", s.source}, {"cells", cells::save(sim.cells())}});
}

}  // namespace

/// surface{cells = true}: grows the script's cells (cells{}, division{}, run{}, shapes) for --steps or
/// run.steps steps (from a sheet checkpoint's step when `s` resumes one). Writes a sheet checkpoint to
/// `checkpoint` as output.checkpoint_every asks and when a Ctrl-C ends the growth early.
Sheet grow_sheet(const RunOptions& o, Start& s, const SceneConfig& cfg, ScriptHost& host, std::uint64_t seed,
                 const fs::path& checkpoint, std::ostream& err, FailedRun& failed) {
  forms::Scene scene(cfg.scene, seed);
  Progress* bar = nullptr;
  scene.set_note([&bar, &err](const std::string& n) {
    if (bar) bar->break_line();
    err << "cellform: note: " << n << "\n";
  });
  cells::Simulation& sim = scene.simulation();
  sim.set_threads(o.threads);
  if (s.resume) {
    sim.cells() = cells::load(s.cells_bytes, "checkpoint '" + o.checkpoint.string() + "'");
    sim.set_step_count(s.step);
    check_resumed_cells(s, cfg, scene, o.threads);
  } else {
    for (const InitialCell& c : cfg.initial_cells)
      cells::add_cell(sim.cells(), c.position, cells::CellType::general, c.fixed);
    scene.start();
  }
  const cells::Rules rules = host.rules();
  if (rules.divides) sim.rules().divides = rules.divides;
  if (rules.split_direction) sim.rules().split_direction = rules.split_direction;
  Sheet out;
  out.target = s.has_target ? s.target_steps : cfg.steps;
  out.initial = s.resume && s.initial_cells > 0 ? s.initial_cells : sim.cells().size();
  if (!o.quiet)
    err << (s.resume ? "resuming the cell sheet from step " + std::to_string(s.step) + " to step "
                     : std::string("growing the cell sheet for "))
        << out.target << (s.resume ? "" : " steps") << " (" << sim.cells().size() << " cells)\n";
  const json physics = physics_of(cfg.resolved);
  auto save = [&] {
    keep_resumed_checkpoint(s, checkpoint.parent_path(), err);  // resume --script: replaced now
    write_checkpoint(checkpoint, sheet_checkpoint_bytes(s, seed, out.target, sim, out.initial, physics));
  };
  CheckpointClock checkpoints(cfg.output);
  bool& saved = out.checkpointed;
  bool warned = false;
  const std::uint64_t first = sim.step_count();
  Progress progress(err, ::isatty(2) != 0, o.quiet, sim.step_count(), out.target, "the veins",
                    sim.params().division.max_cells);
  bar = &progress;
  // a script's print() while the bar is drawn goes on a line of its own (as in cell runs)
  const std::function<void(const std::string&)> outer_print = host.print_function();
  host.set_print([&progress, &outer_print](const std::string& line) {
    progress.break_line();
    if (outer_print) outer_print(line);
  });
  struct RestorePrint {
    ScriptHost& host;
    const std::function<void(const std::string&)>& print;
    ~RestorePrint() { host.set_print(print); }
  } restore_print{host, outer_print};
  failed.sheet_first = first;
  failed.sheet_start = std::chrono::steady_clock::now();
  failed.sheet_growing = true;
  try {
    while (sim.step_count() < out.target && !g_interrupt.load()) {
      host.set_step(sim.step_count() + 1);
      failed.sheet_stepping = sim.step_count() + 1;
      scene.step();
      host.check_knobs(sim.step_count());
      progress.update(sim.step_count(), sim.cells().size());
      if (sim.step_count() < out.target && checkpoints.due(sim.step_count())) {
        if (periodic_checkpoint(save, err, warned, out.checkpoint_seconds)) {
          saved = true;
          failed.sheet_checkpointed = true;
          failed.sheet_saved = sim.step_count();
        }
        failed.sheet_checkpoint_s = out.checkpoint_seconds;
      }
    }
    failed.sheet_growing = false;
  } catch (const std::exception& e) {
    failed.sheet_growing = false;
    if (!o.quiet && ::isatty(2)) err << "\n";
    // the step being made (a knob check after a step has counted it already)
    const std::uint64_t failing = failed.sheet_stepping > sim.step_count() ? failed.sheet_stepping : sim.step_count();
    // cells that diverged keep the last good step: that one is worth a checkpoint
    if (dynamic_cast<const core::SimulationDiverged*>(&e)) try {
        save();
        saved = true;
        failed.sheet_checkpointed = true;
        failed.sheet_saved = sim.step_count();
      } catch (const std::exception&) {
        // the last periodic checkpoint, if any, stays the one to go on from
      }
    failed.sheet_failed(failing);
    throw;
  }
  progress.finish();
  out.checkpoint_clock = checkpoints.last();
  out.complete = sim.step_count() >= out.target;
  if (!out.complete) try {  // a Ctrl-C: the growth continues from here on resume
      save();
      saved = true;
    } catch (const std::exception& e) {  // a full disk: the sheet so far is still written out
      out.checkpoint_error = core::error_text(e);
    }
  sim.relink();  // for the sheet's triangles (when no step ran, no links are made)
  out.step = sim.step_count();
  out.cells = std::move(sim.cells());
  return out;
}

std::vector<core::Vec3> sheet_petioles(const cells::Cells& sheet) {
  std::vector<core::Vec3> out;
  for (std::size_t i = 0; i < sheet.size(); ++i)
    if (sheet.type[i] == cells::CellType::petiole) out.push_back(sheet.position[i]);
  return out;
}

venation::Colonisation make_colonisation(const ColonisationSpec& spec, const cells::Cells* sheet,
                                         const std::string* state, const std::string& what) {
  auto make = [&](const auto& domain) {
    try {
      return state ? venation::Colonisation::load(domain, spec.params, *state, what)
                   : venation::Colonisation(domain, spec.params);
    } catch (const venation::ParametersChanged& e) {  // in the script's terms, still telling what it is
      throw venation::ParametersChanged(script_colonisation_message(e.what()));
    } catch (const venation::DomainChanged& e) {
      throw venation::DomainChanged(script_colonisation_message(e.what()));
    } catch (const core::InvalidInput& e) {
      throw core::InvalidInput(script_colonisation_message(e.what()));
    }
  };
  if (spec.domain.kind == venation::DomainKind::leaf) return make(spec.leaf);
  if (!sheet) return make(spec.domain);
  venation::Domain d = spec.domain;
  d.mesh.vertices = sheet->position;
  d.mesh.triangles = cells::triangulate(*sheet, false).triangles;  // as before one-layer files: no gaps
  if (d.mesh.triangles.empty())
    throw core::InvalidInput(
        "surface{cells = true}: the grown cells form no triangles to grow veins on (place a "
        "sheet such as disc{...} and grow it longer)");
  std::vector<core::Vec3> seeds = d.initial_nodes.empty() ? sheet_petioles(*sheet) : d.initial_nodes;
  if (seeds.empty()) throw core::InvalidInput(kNoSheetSeeds);
  d.initial_nodes = {d.mesh.vertices[d.mesh.triangles[0][0]]};
  const venation::PreparedDomain sheet_surface(d);
  const std::vector<core::Vec3> asked = seeds;
  auto point_text = [](const core::Vec3& q) { return core::point_text(q.x(), q.y(), q.z()); };
  for (core::Vec3& p : seeds) p = sheet_surface.closest_point(p);
  // a seed given far off the sheet is a slip (a unit, a sign): farther than half the sheet's size (a seed at
  // the foot of a vault lies below its crown) and 3 cell spacings, refused (not on resume: the run took it)
  core::Vec3 lo = sheet->position.empty() ? core::Vec3::Zero() : sheet->position[0], hi = lo;
  for (const core::Vec3& p : sheet->position) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double reach = std::max(3 * median_link_length(*sheet), 0.5 * (hi - lo).norm());
  if (!spec.domain.initial_nodes.empty() && !state)
    for (std::size_t k = 0; k < seeds.size(); ++k)
      if (const double off = (seeds[k] - asked[k]).norm(); off > reach)
        throw core::InvalidInput(spec.domain_where + "surface.seeds[" + std::to_string(k + 1) + "] " +
                                 point_text(asked[k]) + " is " + core::number_text(off) +
                                 " model units from the grown sheet (its nearest point is " + point_text(seeds[k]) +
                                 "); a seed moves onto the sheet from at most half the sheet's size or 3 cell "
                                 "spacings away (" +
                                 core::number_text(reach) + " here)");
  if (const auto r = venation::first_repeat(seeds);
      r && spec.domain.initial_nodes.empty() && spec.params.type == venation::VenationType::closed)
    throw core::InvalidInput("surface{cells = true}: the petioles at " + point_text(asked[r->first]) + " and " +
                             point_text(asked[r->second]) + " rest on the same point of the grown sheet, " +
                             point_text(seeds[r->first]) +
                             ", where a closed pattern's veins would start twice and never grow apart; place them "
                             "apart, or give surface.seeds");
  d.initial_nodes = seeds;
  return make(d);
}

void say_large_domain(std::ostream& err, const venation::Domain& d, bool mesh_file) {
  const Eigen::AlignedBox3d box = venation::bounding_box(d);
  if (box.isEmpty()) return;
  const double across = box.sizes().maxCoeff();
  if (!(across > 1000)) return;
  const std::string kind = d.kind == venation::DomainKind::surface ? "surface" : "volume";
  err << "cellform: note: the " << kind << " spans " << core::number_text(std::round(across))
      << " vein segments (model units) at its longest: veins that fill so large a domain take long"
      << (mesh_file ? ". A mesh drawn in millimetres wants " + kind + "{scale = ...}, which scales its coordinates\n"
                    : std::string("\n"));
}

static const char* domain_name(venation::DomainKind k) {
  switch (k) {
    case venation::DomainKind::leaf:
      return "leaf";
    case venation::DomainKind::box:
      return "box";
    case venation::DomainKind::ball:
      return "ball";
    case venation::DomainKind::volume:
      return "volume";
    case venation::DomainKind::surface:
      return "surface";
  }
  return "?";
}

json colonisation_run_record(const Start& s, std::uint64_t seed, int threads, const ColonisationSpec& spec,
                             const json& parameters) {
  json p = parameters;
  if (!spec.on_cells)  // no cell grows: their parameters played no part (and --set refuses them)
    for (const char* section : {"cells", "division"}) p.erase(section);
  return {{"program", "cellform"},
          {"version", version()},
          {"command", s.resume ? "resume" : "run"},
          {"mode", "colonisation"},
          {"domain", domain_name(spec.domain.kind)},
          {"script", script_record(s)},
          {"seed", seed},
          {"threads", threads},  // as asked (0 = all cores); threads_used: what that came to here
          {"threads_used", core::effective_threads(threads)},
          {"overrides", s.sets},
          {"parameters", p}};
}

}  // namespace cellform::app
