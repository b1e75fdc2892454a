// The run and resume commands.
#include "app/run.h"
#include "app/run_internal.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <set>

#include "app/progress.h"
#include "cells/serialize.h"
#include "cells/surface.h"
#include "core/atomic_file.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "export/cell_files.h"
#include "export/mesh_files.h"
#include "export/printable.h"
#include "export/vein_files.h"
#include "venation/canalisation.h"

#ifndef CELLFORM_VERSION
#define CELLFORM_VERSION "0.0.0"
#endif

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

std::string version() { return CELLFORM_VERSION; }

namespace {

std::string checkpoint_bytes(const Start& s, std::uint64_t seed, std::uint64_t target, const forms::Scene& scene,
                             const json& veins) {
  json meta = checkpoint_meta(s, seed, target, scene.simulation().step_count());
  meta["initial_cells"] = s.initial_cells;
  meta["physics"] = s.physics;
  if (veins.is_object()) meta["veins"] = veins;  // run.json's of a resume that runs no step
  return core::write_chunk_file(
      kCheckpointKind, kCheckpointVersion,
      {{"meta", checkpoint_meta_text(meta)}, {"script", s.source}, {"cells", cells::save(scene.simulation().cells())}});
}

/// The start of a cell run's run.json: what ran, with which seed and threads, and how it ended.
json run_head(const Start& s, std::uint64_t seed, int threads, const std::string& status) {
  return {{"program", "cellform"},
          {"version", version()},
          {"command", s.resume ? "resume" : "run"},
          {"script", script_record(s)},
          {"seed", seed},
          {"threads", threads},  // as asked (0 = all cores); threads_used: what that came to here
          {"threads_used", core::effective_threads(threads)},
          {"status", status}};
}

/// Writes `run` as run.json, listing `outputs` (files in `staging`) and, for a resumed run, its frames from
/// before the checkpoint already in `dir`; then moves them all into `dir` (commit_outputs, drop_earlier_checkpoint).
void commit_run(json run, std::vector<std::string> outputs, const Start& s, std::uint64_t first, std::uint64_t seed,
                const fs::path& staging, const fs::path& dir, const fs::path& resumed) {
  outputs.push_back("run.json");
  // a resumed run's frames from before its checkpoint are in the folder already: still this run's outputs
  const std::vector<std::string> kept =
      s.resume ? earlier_frames(dir, first, s.checkpoint_script_hash, seed, s.checkpoint_sets)
               : std::vector<std::string>{};
  json listed = outputs;
  for (const std::string& n : kept)
    if (std::find(outputs.begin(), outputs.end(), n) == outputs.end()) listed.push_back(n);
  run["outputs"] = listed;
  write_run_json(staging / "run.json", run);
  commit_outputs(staging, dir, outputs, kept);
  drop_earlier_checkpoint(dir, run, resumed);
}

}  // namespace

int run_command(const RunOptions& o, std::ostream& out, std::ostream& err) {
  const auto t0 = std::chrono::steady_clock::now();
  Start s;
  SceneConfig cfg;
  ScriptHost host(o.limits);
  Progress* bar = nullptr;  // the steps' progress bar, while it is drawn: a script's line goes below it
  const auto show_line = [&err, &bar](const char* who, const std::string& line) {
    if (bar) bar->break_line();
    err << std::string(who).append(line).append("\n");  // one write: a line stays whole in a shared log
  };
  const auto show_print = [&show_line](const std::string& line) { show_line("script: ", line); };
  host.set_print(show_print);
  std::unique_ptr<forms::Scene> scene;
  std::uint64_t seed = 0, target = 0;
  fs::path staging;
  fs::path killed_staging;  // the staging folder holding the frames of the checkpoint in the folder (a killed run's)
  std::string folder_mark;  // checkpoint_mark of the checkpoint in the folder when this run took it
  std::optional<FolderLock> lock;  // held until the run has written its last file
  std::string print_error;         // the print failed: why, said once the other outputs are in (or failed)
  bool print_retry = false;        // and a resume with other print.* values can print again
  try {
    s = start_from(o);
    host.accept_digit_booleans(s.digit_booleans);
    const bool colonisation_checkpoint = !s.colonisation_bytes.empty() || s.sheet_partial;
    try {  // resume --script: the run's own --sets that the edited script has no parameter for are dropped
      std::set<std::string> may_go_unused;
      if (s.script_replaced)
        for (const auto& [k, v] : s.checkpoint_sets)
          if (!o.sets.count(k)) may_go_unused.insert(k);
      // a colonisation checkpoint of a run that set cells.* or division.* (now refused, once ignored): unused
      if (colonisation_checkpoint)
        for (const auto& [k, v] : s.checkpoint_sets)
          if ((k.rfind("cells.", 0) == 0 || k.rfind("division.", 0) == 0) && !o.sets.count(k)) may_go_unused.insert(k);
      cfg = host.load(s.source, s.script_path, s.sets, may_go_unused);
      for (const std::string& n : cfg.notes) err << "cellform: note: " << n << "\n";
      for (const std::string& k : host.unused_overrides()) {
        err << "cellform: note: the run's --set " << k << "=" << s.sets[k] << " is dropped: " << s.script_path.string()
            << " has no parameter for it\n";
        s.sets.erase(k);
      }
      if (s.script_unchanged)
        err << "cellform: note: " << o.replace_script->string()
            << " is the script the checkpoint keeps, unchanged: this is a plain resume\n";
      if (s.script_replaced && cfg.colonisation.has_value() == colonisation_checkpoint)  // else refused below
        adopt_edited_script(s, o, cfg, err);
      // a resumed cell run (or sheet) steps with the values it was saved with, whatever the defaults are now: the
      // script is read again with those that changed set (not with --script: its edited values are the point)
      if (s.resume && !s.script_replaced && s.physics.is_object() && (!cfg.colonisation || s.sheet_partial)) {
        const json now = physics_of(cfg.resolved);
        json changed = json::object();
        std::string listed;
        for (const auto& [section, values] : s.physics.items())
          for (const auto& [k, v] : values.items())
            if (now.contains(section) && now[section].contains(k) && now[section][k] != v) {  // known both ways
              changed[section][k] = v;
              listed += (listed.empty() ? "" : ", ") + section + "." + k + " = " + v.dump() + " (now " +
                        now[section][k].dump() + ")";
            }
        if (!changed.empty()) {
          host.set_print([](const std::string&) {});  // its print() lines were shown by the first reading
          try {
            cfg = host.load(s.source, s.script_path, with_physics(s.sets, changed));
          } catch (const core::InvalidInput& e) {  // a value the script now refuses (one a rule replaces)
            if (g_interrupt.load()) throw;
            cfg = host.load(s.source, s.script_path, s.sets);
            err << "cellform: warning: the run was saved with " << listed << ", which this script no longer accepts ("
                << e.what() << "); it continues with today's\n";
          }
          host.set_print(show_print);
        }
      }
    } catch (const core::InvalidInput& e) {
      if (!s.resume || g_interrupt.load()) throw;  // a resumed script is the checkpoint's copy, with its --sets
      if (s.script_replaced)
        throw core::InvalidInput(std::string(e.what()) + " (resuming checkpoint '" + o.checkpoint.string() +
                                 "' with --script, and the --set overrides of its run)");
      throw core::InvalidInput(std::string(e.what()) + " (resuming checkpoint '" + o.checkpoint.string() +
                               "', which keeps the script and the --set overrides of its run; to go on with a "
                               "corrected copy: " +
                               resume_command(o, o.checkpoint, {}) + ")");
    }
    if (s.resume && cfg.colonisation.has_value() != colonisation_checkpoint)
      throw core::InvalidInput("checkpoint '" + o.checkpoint.string() + "' is of a " +
                               (colonisation_checkpoint ? "space-colonisation" : "cell") +
                               (s.script_replaced ? " run, but --script " + s.script_path.string() + " describes a "
                                                  : std::string(" run, but its script with these --set overrides now "
                                                                "describes a ")) +
                               (cfg.colonisation ? "space-colonisation" : "cell") + " run");
    adopt_mesh_files(s, o, cfg, err);
    refuse_two_step_limits(s, o, cfg);
    seed = s.seed ? *s.seed : cfg.seed;
    host.set_seed(seed);  // math.random in rules: from the seed and the step
    if (cfg.resolved.contains("run")) cfg.resolved["run"]["seed"] = seed;  // run.json: the seed used (--seed too)
    target = s.has_target ? s.target_steps : cfg.steps;
    g_print_planned = cfg.print.has_value();                        // what a Ctrl-C from now on says
    if (s.script_replaced && !cfg.colonisation && target < s.step)  // as --steps below it would be
      throw InputError((cfg.steps_given_at.empty() ? s.script_path.string() + ": " : cfg.steps_given_at) +
                       "run.steps = " + std::to_string(target) + " is below the checkpoint's step " +
                       std::to_string(s.step) + "; raise it, or give --steps " + std::to_string(s.step) + " or more");
    // run.json: the steps this cell run goes to (--steps, or its checkpoint's, too)
    if (!cfg.colonisation && cfg.resolved.contains("run")) cfg.resolved["run"]["steps"] = target;
    if (cfg.colonisation) {
      adopt_max_steps(s, o, cfg);
      return run_colonisation(o, s, cfg, host, seed, out, err, t0);
    }
    // the one default changed since checkpoints record their values: say so where it applies
    const json division = cfg.resolved.value("division", json::object());
    if (s.resume && !s.physics.is_object() && division.value("trigger", "") == "neighbours" &&
        division.value("radius", 0.0) == cells::kDivisionRadius * cfg.scene.cells.rest_length &&
        !division.value("rule", json()).is_string() && !s.sets.count("division.radius"))
      err << "cellform: note: checkpoint '" << o.checkpoint.string()
          << "' does not record its run's parameter values (an older cellform): if the script leaves "
             "division.radius to its default, the run continues with "
          << core::number_text(cfg.scene.cells.division.radius) << " (the default was 1.5 model units)\n";
    s.physics = physics_of(cfg.resolved);
    apply_checkpoint_every(s.checkpoint_every, &cfg.output, cfg.resolved);
    scene = std::make_unique<forms::Scene>(cfg.scene, seed);
    scene->set_note([&show_line](const std::string& n) { show_line("cellform: note: ", n); });
    cells::Simulation& sim = scene->simulation();
    sim.set_threads(o.threads);
    if (s.resume) {
      sim.cells() = cells::load(s.cells_bytes, "checkpoint '" + o.checkpoint.string() + "'");
      sim.set_step_count(s.step);
      check_resumed_cells(s, cfg, *scene, o.threads);
      cells::Params veins = sim.params();  // vein cells of the checkpoint bound the step with no venation{} now
      veins.vein_trees = std::count(sim.cells().type.begin(), sim.cells().type.end(), cells::CellType::vein) > 0;
      if (veins.vein_trees && !sim.params().vein_trees) cells::validate(veins);
    } else {
      if (cfg.initial_cells.empty() && cfg.scene.petioles.empty())
        throw core::InvalidInput(s.script_path.string() +
                                 ": the script places no cells; start with a shape such as disc{radius = 3}");
      for (const InitialCell& c : cfg.initial_cells)
        cells::add_cell(sim.cells(), c.position, cells::CellType::general, c.fixed);
      scene->start();
    }
    const cells::Rules rules = host.rules();
    if (rules.divides) sim.rules().divides = rules.divides;
    if (rules.split_direction) sim.rules().split_direction = rules.split_direction;
    scene->set_source_rule(host.source_rule());
  } catch (const InputError& e) {
    err << "cellform: " << e.what() << "\n";
    return usage;
  } catch (const core::InvalidInput& e) {
    err << "cellform: " << e.what() << "\n";
    if (!g_interrupt.load()) err << knob_recall(s.sets, e.what());
    return g_interrupt.load() ? interrupted : usage;  // a Ctrl-C while the script was read stops it there
  } catch (const core::FileError& e) {
    err << "cellform: " << e.what() << "\n";
    return usage;
  } catch (const std::exception& e) {
    err << "cellform: " << core::error_text(e) << "\n";
    return failure;
  }

  cells::Simulation& sim = scene->simulation();
  const fs::path dir = s.out_dir;
  const fs::path created = first_missing(dir);  // made by this run: removed again if it stays empty
  try {
    if (cfg.output.every > 0) check_frames_folder(dir);  // before anything is made there
    check_output_places(dir, output_names(cfg));
    staging = make_staging(dir, lock, &killed_staging, &folder_mark);
    // a resume of this folder's checkpoint read it before taking the lock: another run may have replaced it
    std::error_code same;
    if (s.resume && fs::equivalent(o.checkpoint, dir / kCheckpointName, same) && folder_mark != s.checkpoint_mark) {
      lock.reset();
      fs::remove_all(staging, same);
      throw core::FileError("checkpoint '" + o.checkpoint.string() +
                            "' was replaced by another run while this one started; resume it again");
    }
    if (s.script_replaced) record_replaced_script(s, o, dir);
    plan_keeping_folder_checkpoint(s, o, dir);
  } catch (const std::exception&) {
    return refuse_outputs(std::current_exception(), dir, created, err);
  }

  const std::uint64_t first = sim.step_count();
  const std::size_t initial_cells = sim.cells().size();       // of this command
  if (s.initial_cells == 0) s.initial_cells = initial_cells;  // a fresh run (or a checkpoint that did not say)
  if (!o.quiet)
    err << (s.resume ? "resuming " : "running ") << s.script_path.string() << " from step " << first << " to " << target
        << " (" << initial_cells << " cells, seed " << seed << ")\n";
  if (s.resume && first >= target && !o.steps)  // notes are said with --quiet too: it stills the progress alone
    err << "cellform: note: the checkpoint is at its run's last step (" << target << "): no step runs, the outputs"
        << (cfg.print ? " (and the print, if anything grew)" : "")
        << " are made again; give --steps N to continue to step N\n";
  say_late_starts(err, cfg.scene, first, target);
  Progress progress(err, ::isatty(2) != 0, o.quiet, first, target, cfg.print ? "the print" : "",
                    sim.params().division.max_cells);
  bar = &progress;
  CheckpointClock checkpoints(cfg.output);
  std::vector<std::string> outputs;
  const fs::path checkpoint = dir / kCheckpointName;
  std::string status = "complete";
  double sim_seconds = 0;
  double checkpoint_seconds = 0;  // the periodic checkpoints' (the final one's is in output_s)
  int code = ok;
  bool saved = false;            // this run wrote checkpoint.cfck (an older one may be there from another run)
  std::string checkpoint_error;  // why the final checkpoint could not be written
  std::string earlier_record;    // a resume that runs no step: the folder's run.json, put back if the outputs fail
  bool checkpoint_warned = false;
  std::uint64_t saved_step = 0;            // the step of the last checkpoint this run wrote
  std::size_t saved_cells = 0;             // and its cells
  std::uint64_t stepping = 0;              // the step being computed, while one is (steps count from 1)
  std::vector<std::uint64_t> frame_steps;  // the step of every frame written (outputs holds their names)
  // the frames a killed run wrote up to the checkpoint this one resumes are this run's too (a checkpoint of
  // another folder, or a new run, takes none; the folder stays until this run replaces that checkpoint)
  std::string held_mark;  // the checkpoint whose frames (up to its step) this run's staging folder holds
  if (s.resume && !killed_staging.empty() && folder_mark == s.checkpoint_mark) {
    for (const auto& [step, name] : salvage_frames(killed_staging, staging, sim.step_count())) {
      outputs.push_back(name);
      frame_steps.push_back(step);
    }
    held_mark = s.checkpoint_mark;
  }
  auto vein_record = [&]() -> json {
    return cfg.scene.venation ? vein_summary(sim.cells(), scene->venation_report(), s.vein_summary) : json();
  };
  auto checkpoint_now = [&] {
    keep_resumed_checkpoint(s, dir, err);  // resume --script: the checkpoint resumed is replaced now
    const std::string bytes = checkpoint_bytes(s, seed, target, *scene, vein_record());
    const std::string mark = checkpoint_mark(bytes);
    // marked before and after the checkpoint is replaced: a kill at any moment leaves the folder's checkpoint
    // with a staging folder that holds its frames (this one, or the one kept)
    const bool marked = mark_staging(staging, {mark, held_mark});
    write_checkpoint(checkpoint, bytes);
    saved_step = sim.step_count();
    saved_cells = sim.cells().size();
    if (marked && mark_staging(staging, {mark})) {
      held_mark = mark;
      if (!killed_staging.empty()) {  // no checkpoint needs its frames any more
        std::error_code ec;
        fs::remove_all(killed_staging, ec);
        killed_staging.clear();
      }
    }
  };
  // a run an error stops after a checkpoint: the folder shows it so far, frames too, with a failed run.json
  auto keep_failed_run = [&](const std::string& error) {
    try {
      std::vector<std::string> names;
      for (std::size_t k = 0; k < frame_steps.size(); ++k)
        if (frame_steps[k] <= saved_step) names.push_back(outputs[k]);
      json run = run_head(s, seed, o.threads, "failed");
      run.update(
          {{"error", error},
           {"steps",
            {{"first", first},
             {"completed", saved_step},
             {"target", target},
             {"failed", stepping > 0 ? json(stepping) : json(nullptr)}}},
           {"cells", {{"initial", s.initial_cells}, {"final", saved_cells}}},
           {"overrides", s.sets},
           {"parameters", cfg.resolved},
           {"timings",
            {{"total_s", seconds_since(t0)}, {"simulation_s", sim_seconds}, {"checkpoints_s", checkpoint_seconds}}},
           {"checkpoint", kCheckpointName}});
      commit_run(run, names, s, first, seed, staging, dir, {});
    } catch (const std::exception& f) {
      err << "cellform: warning: the frames and run.json of the failed run could not be written: "
          << core::error_text(f) << "\n";
    }
  };
  // after a script error: what is left to go on from, and how (the message itself is out already)
  auto explain_failure = [&](const std::string& error) {
    // only a checkpoint of this run (or the one resumed) is worth naming: a step that failed may have
    // left the state half changed, and a file from an earlier run in the folder is not this run's
    fs::path last;
    if (saved) {
      // (of which step: output.checkpoint_seconds may have skipped the ones checkpoint_every asked for since)
      err << "  (the last checkpoint is " << checkpoint.string() << ", of step " << saved_step << ")\n";
      last = checkpoint;
      keep_failed_run(error);
    } else if (s.resume && fs::exists(o.checkpoint)) {
      err << "  (the last checkpoint is " << o.checkpoint.string() << ", the one resumed)\n";
      last = o.checkpoint;
    } else if (stepping > 0) {
      err << "  (no checkpoint of this run was written before step " << stepping
          << ", so there is nothing to go on from; output.checkpoint_every and output.checkpoint_minutes, or "
             "--checkpoint-every N, set how often one is"
          << (fs::exists(dir / "run.json") ? "; the files in " + dir.string() + "/ are an earlier run's" : "") << ")\n";
    }
    // the same script would stop there again: an edited one can go on from the checkpoint
    if (!last.empty()) err << resume_hint(o, last, s.script_path) << "\n";
  };
  // a script stuck in one library call ends the process from the watchdog's thread; this thread is
  // inside that call, in a rule of the step being computed, and touches none of what this reads
  const StuckHandler on_stuck(host, [&](const std::string& error) {
    if (stepping > 0 && error.find(" at step ") == std::string::npos) err << "  (in step " << stepping << ")\n";
    explain_failure(error);
    std::error_code ec;
    fs::remove_all(staging, ec);
    remove_empty_up_to(dir, created);
  });
  const auto write_frame = [&](std::uint64_t step) {
    const std::string name = "frames/" + exporters::frame_name("cells", step, "ply");
    core::ensure_directory(staging / "frames");
    // linked as they lie now; with the attributes of the later frames, none flowing before canalisation's
    // first pass (on a copy: rules must not see them before it): one layout for a sequence
    sim.relink();
    const bool bare = cfg.scene.venation && !venation::has_attributes(sim.cells());
    cells::Cells copy = bare ? sim.cells() : cells::Cells{};
    if (bare) venation::add_attributes(copy);
    const cells::Cells& c = bare ? copy : sim.cells();
    exporters::write_cells_ply(staging / name, c, cells::triangulate(c));
    outputs.push_back(name);
    frame_steps.push_back(step);
  };
  try {
    if (cfg.output.every > 0 && sim.step_count() == 0)  // the cells as placed (also when no step runs: --steps 0)
      write_frame(0);
    // the step at which the cells reached division.max_cells, in this command (a full start is no news)
    std::uint64_t full_at = sim.cells().size() >= sim.params().division.max_cells ? target + 1 : 0;
    while (sim.step_count() < target) {
      if (g_interrupt.load()) {
        status = "interrupted";
        code = interrupted;
        break;
      }
      host.set_step(sim.step_count() + 1);
      const auto a = std::chrono::steady_clock::now();
      stepping = sim.step_count() + 1;
      try {
        scene->step();
        host.check_knobs(sim.step_count());
      } catch (const core::SimulationDiverged& e) {
        progress.break_line();                    // a bar drawn on a terminal
        err << "cellform: " << e.what() << "\n";  // says "diverged" and what to try
        try {
          checkpoint_now();  // the cells are those of the last good step
          saved = true;
          err << "  (the state of step " << sim.step_count() << " is saved in " << checkpoint.string() << ")\n";
        } catch (const std::exception& f) {
          err << "cellform: the checkpoint of step " << sim.step_count()
              << ", the last good one, could not be written: " << core::error_text(f) << "\n";
          if (saved) err << "  (the last checkpoint is " << checkpoint.string() << ", of step " << saved_step << ")\n";
        }
        if (saved) {
          keep_failed_run(e.what());
          err << resume_hint(o, checkpoint, s.script_path) << "\n";
          err << sets_carry_over(s.sets);
        }
        std::error_code ec;
        fs::remove_all(staging, ec);
        return failure;
      }
      stepping = 0;
      sim_seconds += seconds_since(a);
      const std::uint64_t step = sim.step_count();
      if (full_at == 0 && sim.cells().size() >= sim.params().division.max_cells) full_at = step;
      progress.update(step, sim.cells().size());
      if (cfg.output.every > 0 && step % cfg.output.every == 0)  // asked for, whatever output.ply says of the end
        write_frame(step);
      if (step < target && checkpoints.due(step))
        saved = periodic_checkpoint(checkpoint_now, err, checkpoint_warned, checkpoint_seconds) || saved;
    }
    progress.finish();
    if (full_at > 0 && full_at <= target)  // divisions, and the rules that decide them, stopped there
      err << "cellform: note: the cells reached division.max_cells = " << sim.params().division.max_cells << " at step "
          << full_at << "; no cell divided after it" << (sim.rules().divides ? ", nor was division.rule called" : "")
          << " (raise division.max_cells, or the params{} knob the script sets it from, to grow on)\n";
    if (cfg.scene.venation && sim.step_count() > first)  // the notes wait for a finished run (not yet: not news)
      say_vein_findings(err, sim.cells(), scene->venation_report(), *cfg.scene.venation, !g_interrupt.load());
    // the links of the cells as they lie now, for the surface, the print and the checkpoint (the notes above
    // speak of those canalisation saw)
    sim.relink();
    if (!g_interrupt.load()) say_loose_supports(err, sim.cells());
    const auto b = std::chrono::steady_clock::now();
    json printed;
    bool print_cancelled = false, printed_first = false;  // (a Ctrl-C of the early print ends the run)
    std::vector<std::string> print_names;
    // a run cut short (--steps below the script's run.steps, a quick try) before any vein grew skips a print of
    // veins, rather than fail it or print the sheet alone (a print without veins is made, or fails, as in a full run)
    const bool skip_print = cfg.print && cfg.print->veins && cfg.scene.venation && target < cfg.steps &&
                            !g_interrupt.load() && venation::vein_graph(sim.cells()).edges.empty();
    if (skip_print) {
      printed = {{"skipped", "nothing to print yet at step " + std::to_string(sim.step_count()) +
                                 " (no vein has grown; the run was cut short at step " + std::to_string(target) +
                                 " of the script's " + std::to_string(cfg.steps) + ")"}};
      err << "cellform: print: skipped: " << printed["skipped"].get<std::string>() << "\n";
    }
    if (cfg.print && !skip_print && s.resume && first >= target) {
      // no step ran: the outputs are made again for another print. The print first, so that one that
      // fails (too fine a voxel for the memory, say) leaves the folder as it was, its earlier print too.
      try {
        printed = write_printable(staging, *cfg.print, sim.cells(), cfg.scene.venation.has_value(), o.threads,
                                  print_names, err, o.quiet);
        if (!o.quiet) say_printed(err, printed);
      } catch (const std::exception& e) {  // a Ctrl-C (core::Cancelled) too: the print was all this run made
        const bool cancelled = dynamic_cast<const core::Cancelled*>(&e) != nullptr;
        err << (cancelled ? std::string(o.quiet || !::isatty(2) ? "" : "\n") + "cellform: printing interrupted"
                          : "cellform: " + output_error(e, staging, dir))
            << "\n  (nothing in " << dir.string()
            << "/ changed: its outputs, printable files and checkpoint are as they were)\n";
        std::error_code ec;
        fs::remove_all(staging, ec);
        remove_empty_up_to(dir, created);
        return cancelled ? interrupted : failure;
      }
      printed_first = true;
    }
    const bool no_step = s.resume && first >= target;  // the checkpoint resumed stays as it was
    const auto own = no_step ? own_record(o.checkpoint, dir) : std::nullopt;
    if (own) earlier_record = *own;
    // the checkpoint first: outputs failing after it leave it to resume from; one that fails leaves the outputs
    try {
      checkpoint_now();
      saved = true;
    } catch (const std::exception& e) {
      checkpoint_error = core::error_text(e);
    }
    // none of this run's: another run's checkpoint there stays, with its outputs (the commit keeps one resumed)
    if (!saved && keep_other_run(dir, s.resume ? o.checkpoint : fs::path(), checkpoint_error, staging, created, err))
      return failure;
    for (const std::string& n :
         write_outputs(staging, cfg.output, sim.cells(), cfg.scene.venation ? &*cfg.scene.venation : nullptr))
      outputs.push_back(n);
    outputs.insert(outputs.end(), print_names.begin(), print_names.end());
    if (cfg.print && !skip_print && !printed_first) {
      try {
        printed = write_printable(staging, *cfg.print, sim.cells(), cfg.scene.venation.has_value(), o.threads, outputs,
                                  err, o.quiet);
        if (!o.quiet) say_printed(err, printed);
      } catch (const core::Cancelled&) {  // said once the other files are in (another Ctrl-C quits before)
        print_cancelled = true;
        printed = {{"error", "interrupted"}};
        status = "interrupted";
        code = interrupted;
      } catch (const std::exception& e) {
        print_error = output_error(e, staging, dir);  // said once the other files are in (their writing may fail)
        print_retry = saved && checkpoint_error.empty() && !dynamic_cast<const NothingToPrint*>(&e);
        printed = {{"error", print_error}};
        if (code != interrupted) {  // a Ctrl-C that came first stays the reason the run ended
          code = failure;
          status = "print failed";  // the cells are complete; run.json's print.error says why
        }
      }
    }
    const double output_seconds = seconds_since(b);
    const double total = seconds_since(t0);
    const std::uint64_t done = sim.step_count() - first;
    json run = run_head(s, seed, o.threads, status);
    run.update({{"steps", {{"first", first}, {"completed", sim.step_count()}, {"target", target}}},
                {"cells", {{"initial", s.initial_cells}, {"final", sim.cells().size()}}},
                {"veins", vein_record()},
                {"overrides", s.sets},
                {"parameters", cfg.resolved},
                {"timings",
                 {{"total_s", total},
                  {"simulation_s", sim_seconds},
                  {"output_s", output_seconds},
                  {"checkpoints_s", checkpoint_seconds},
                  {"steps_per_s", sim_seconds > 0 ? static_cast<double>(done) / sim_seconds : 0.0}}}});
    // a resume whose checkpoints failed in the folder of the checkpoint it resumed: that one is there still
    std::error_code same;
    const bool resumed_here = s.resume && !saved && fs::equivalent(o.checkpoint, checkpoint, same);
    record_checkpoint(run, checkpoint_error, saved || resumed_here, saved ? saved_step : first);
    if (cfg.print) run["print"] = printed;
    commit_run(run, outputs, s, first, seed, staging, dir, s.resume ? o.checkpoint : fs::path());
    if (!print_error.empty())
      say_print_failed(err, print_error,
                       checkpoint_error.empty() ? "the other outputs and the checkpoint are written"
                                                : "the other outputs are written",
                       print_retry, checkpoint, o.limits);
    if (print_cancelled)
      err << (o.quiet || !::isatty(2) ? "" : "\n")
          << "cellform: printing interrupted: no printable files (the other outputs"
          << (checkpoint_error.empty() ? " and the checkpoint are written)\n" : " are written)\n");
    if (!checkpoint_error.empty()) {
      err << "cellform: " << checkpoint_error
          << (saved ? "\n  (the other outputs are written; the run can be resumed from its last periodic checkpoint, " +
                          checkpoint.string() + ", of step " + std::to_string(saved_step) + ")\n"
              : no_step || resumed_here
                  ? "\n  (the other outputs are written; " + o.checkpoint.string() + ", the checkpoint resumed (step " +
                        std::to_string(first) + "), is as it was" +
                        (no_step ? std::string(")\n") : ": a resume of it runs this run's steps again)\n")
                  : std::string("\n  (the other outputs are written, but this run cannot be resumed)\n"));
      code = failure;
    }
    if (!o.quiet || code != ok) {
      std::ostream& where = code == ok ? out : err;
      where << (code == interrupted ? "interrupted at step "
                : code == ok        ? "done: step "
                                    : "stopped with an error at step ")
            << sim.step_count() << ", " << sim.cells().size() << " cells" << extent_text(sim.cells().position)
            << "; outputs in " << dir.string() << "/\n";
      if (code == interrupted && saved) err << "continue with: " << continue_command(checkpoint, o.limits) << "\n";
    }
    return code;
  } catch (const core::InvalidInput& e) {
    progress.finish();
    err << "cellform: " << e.what() << "\n";
    explain_failure(e.what());
    code = usage;
  } catch (const std::exception& e) {
    progress.finish();
    if (!print_error.empty()) err << "cellform: " << print_error << "\n";
    err << "cellform: " << output_error(e, staging, dir) << "\n";
    // the outputs failed (a full disk): what is left to continue from; a run.json that says so (a few kB,
    // which a full disk usually still has) and the frames up to it stay, as after a script error. (With no
    // checkpoint of steps this run took, as when no step ran, the folder stays as it was: a resume that only
    // writes the outputs again must not replace a finished run's outputs by a record of its failure.)
    if (!checkpoint_error.empty()) err << "cellform: the final checkpoint failed too: " << checkpoint_error << "\n";
    if (saved && fs::exists(checkpoint)) {
      err << "  (the last checkpoint written is " << checkpoint.string() << "; cellform resume continues from it)\n";
      if (saved_step > first) keep_failed_run(output_error(e, staging, dir));
    }
    if (saved && saved_step == first && !earlier_record.empty()) try {
        core::write_file_atomically(dir / "run.json", [&](std::ostream& os) { os << earlier_record; });
      } catch (const std::exception&) {  // as full as that: the mark stays, the first error is the one said
      }
    code = failure;
  }
  std::error_code ec;
  fs::remove_all(staging, ec);
  remove_empty_up_to(dir, created);  // a failed run leaves no empty folder
  return code;
}

}  // namespace cellform::app
