// surface{cells = true}: the cell sheet grown before space colonisation puts veins on it, with its own
// checkpoints (mode "sheet") so that a Ctrl-C or a failure while it grows loses nothing.
#include "app/run_sheet.h"

#include "app/progress.h"
#include "cells/serialize.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "forms/scene.h"

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
  cells::Simulation& sim = scene.simulation();
  sim.set_threads(o.threads);
  if (s.resume) {
    sim.cells() = cells::load(s.cells_bytes, "checkpoint '" + o.checkpoint.string() + "'");
    sim.set_step_count(s.step);
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
  CheckpointClock checkpoints(cfg.output.checkpoint_every, cfg.output.checkpoint_seconds);
  bool& saved = out.checkpointed;
  bool warned = false;
  const std::uint64_t first = sim.step_count();
  Progress progress(err, ::isatty(2) != 0, o.quiet, sim.step_count(), out.target);
  failed.sheet_first = first;
  failed.sheet_growing = true;
  try {
    while (sim.step_count() < out.target && !g_interrupt.load()) {
      host.set_step(sim.step_count() + 1);
      failed.sheet_stepping = sim.step_count() + 1;
      scene.step();
      host.check_knobs(sim.step_count());
      progress.update(sim.step_count(), sim.cells().size());
      if (sim.step_count() < out.target && checkpoints.due(sim.step_count()) &&
          periodic_checkpoint(save, err, warned)) {
        saved = true;
        failed.sheet_checkpointed = true;
        failed.sheet_saved = sim.step_count();
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
  out.complete = sim.step_count() >= out.target;
  if (!out.complete) try {  // a Ctrl-C: the growth continues from here on resume
      save();
      saved = true;
    } catch (const std::exception& e) {  // a full disk: the sheet so far is still written out
      out.checkpoint_error = core::error_text(e);
    }
  if (sim.step_count() == 0) {  // no step ran: the links the first step would make, for the sheet's triangles
    core::PointGrid grid;
    cells::update_links(sim.cells(), sim.params(), grid, sim.threads());
  }
  out.step = sim.step_count();
  out.cells = std::move(sim.cells());
  return out;
}

}  // namespace cellform::app
