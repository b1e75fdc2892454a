// `cellform run` and `cellform resume` of a space-colonisation script (Runions et al. 2005): veins in a
// leaf, a volume or on a surface, with checkpoints, SVG/PNG/PLY/OBJ and the printable solid.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "app/progress.h"
#include "app/run_internal.h"
#include "app/run_sheet.h"
#include "cells/serialize.h"
#include "cells/surface.h"
#include "core/atomic_file.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "export/vein_png.h"
#include "venation/colonisation.h"
#include "venation/domain.h"
#include "venation/vein_io.h"

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A colonisation checkpoint: the script, what resume needs to rebuild the same setup (seed, --set overrides,
/// the step limit, for surface{cells = true} the grown sheet) and the colonisation state.
std::string colonisation_checkpoint_bytes(const Start& s, std::uint64_t seed, const venation::ColonisationParams& p,
                                          const venation::Colonisation& col, const cells::Cells* sheet,
                                          std::size_t sheet_initial, std::optional<std::uint64_t> sheet_steps) {
  json meta = checkpoint_meta(s, seed, p.max_steps, col.report().steps);
  meta["mode"] = "colonisation";
  if (sheet) meta["initial_cells"] = sheet_initial;
  if (sheet && sheet_steps) meta["sheet_steps"] = *sheet_steps;
  std::map<std::string, std::string> chunks{
      {"meta", checkpoint_meta_text(meta)}, {"script", s.source}, {"colonisation", col.save()}};
  if (sheet) chunks["cells"] = cells::save(*sheet);
  return core::write_chunk_file(kCheckpointKind, kCheckpointVersion, chunks);
}

}  // namespace

/// A space-colonisation run (Runions et al. 2005) in a leaf outline, a volume or on a surface (a mesh, or the
/// sheet of cells grown first). Writes checkpoint.cfck as output{} asks, at the end and on Ctrl-C (which stops
/// it with the pattern so far written out); `cellform resume` continues it bit-identically.
int run_colonisation(const RunOptions& o, Start& s, SceneConfig& cfg, ScriptHost& host, std::uint64_t seed,
                     std::ostream& out, std::ostream& err, std::chrono::steady_clock::time_point t0) {
  const fs::path dir = s.out_dir;
  const fs::path created = first_missing(dir);  // made by this run: removed again if it stays empty
  fs::path staging;
  fs::path kept_staging;           // the frames of the folder's (a killed cell run's) checkpoint, until replaced
  std::optional<FolderLock> lock;  // held until the run has written its last file
  bool resumable = false;          // a checkpoint of this run is in the folder when the outputs are written
  json stepped;                    // run.json's steps when that checkpoint holds steps this run took, else null
  std::string checkpoint_failure;  // why the final checkpoint could not be written
  bool no_step = false;            // a resume that runs no step: the checkpoint resumed stays as it was
  std::string earlier_record;      // its run.json, put back if the outputs fail (a checkpoint marked it superseded)
  try {
    check_output_places(dir, output_names(cfg));
    staging = make_staging(dir, lock, &kept_staging);
    if (s.script_replaced) record_replaced_script(s, o, dir);
    plan_keeping_folder_checkpoint(s, o, dir);
  } catch (const std::exception&) {
    return refuse_outputs(std::current_exception(), dir, created, err);
  }
  ColonisationSpec& spec = *cfg.colonisation;
  spec.params.seed = seed;
  spec.params.threads = o.threads;
  const std::uint64_t script_steps = spec.params.max_steps;  // the script's own limit
  if (s.has_target) spec.params.max_steps = s.target_steps;  // --steps, or the checkpoint's limit
  if (cfg.resolved.contains("colonisation"))                 // run.json: the limit this run goes to
    cfg.resolved["colonisation"]["max_steps"] = spec.params.max_steps;
  apply_checkpoint_every(s.checkpoint_every, &cfg.output, cfg.resolved);
  const fs::path checkpoint = dir / kCheckpointName;
  int code = ok;
  const bool planar = spec.domain.kind == venation::DomainKind::leaf;
  FailedRun failed;
  // after a step's error: the last checkpoint this run wrote, the folder showing the run so far (a failed run.json)
  auto keep_failed_run = [&](const std::string& m) {
    err << "  (the last checkpoint is " << checkpoint.string() << failed.checkpoint_note << ")\n";
    try {
      json run = colonisation_run_record(s, seed, o.threads, spec, cfg.resolved);
      run["status"] = "failed";
      run["error"] = m;
      if (!failed.phase.empty()) run["phase"] = failed.phase;
      run["steps"] = failed.steps;
      run["timings"] = failed.timings;
      run["timings"]["total_s"] = seconds_since(t0);
      run["checkpoint"] = kCheckpointName;
      run["outputs"] = json::array({"run.json"});
      write_run_json(staging / "run.json", run);
      commit_outputs(staging, dir, {"run.json"});
    } catch (const std::exception& f) {
      err << "cellform: warning: the run.json of the failed run could not be written: " << core::error_text(f) << "\n";
    }
  };
  // a rule of the sheet's growth stuck in one library call ends the process from the watchdog's thread
  // (the message is out already); this thread is inside that call and changes none of what this reads.
  // The veins' steps call no script: their growth functions were sampled when the script was read.
  const StuckHandler on_stuck(host, [&](const std::string& error) {
    if (failed.sheet_growing) {
      err << "  (in step " << failed.sheet_stepping << " of the cell sheet)\n";
      failed.sheet_failed(failed.sheet_stepping);
      fs::path last;
      if (failed.checkpointed) {
        last = checkpoint;
        keep_failed_run(error);
      } else if (s.resume && fs::exists(o.checkpoint)) {
        err << "  (the last checkpoint is " << o.checkpoint.string() << ", the one resumed)\n";
        last = o.checkpoint;
      }
      if (!last.empty()) err << resume_hint(o, last, s.script_path) << "\n";
    }
    std::error_code ec;
    fs::remove_all(staging, ec);
    remove_empty_up_to(dir, created);
  });
  try {
    std::optional<cells::Cells> sheet;
    // cells when the sheet began to grow, for run.json (a checkpoint that does not say: the script's shapes)
    std::size_t sheet_initial = s.initial_cells > 0 ? s.initial_cells : cfg.initial_cells.size();
    std::optional<std::uint64_t> sheet_steps = s.sheet_partial ? std::nullopt : s.sheet_steps;  // as grown
    double sheet_seconds = 0;                             // growing surface{cells = true}'s sheet in this command
    auto clock_start = std::chrono::steady_clock::now();  // of the periodic checkpoints: the sheet's go on
    double checkpoint_seconds = 0;    // the periodic checkpoints (of the sheet too; the final one's is not here)
    bool sheet_checkpointed = false;  // a checkpoint written while the sheet grew is in the folder
    if (s.sheet_partial && !spec.on_cells)
      throw core::InvalidInput("checkpoint '" + o.checkpoint.string() +
                               "' was taken while a cell sheet grew, but its script grows no veins on cells");
    if (spec.on_cells) {  // resume: the sheet grown by the first run, not grown again
      if (spec.domain.initial_nodes.empty() && cfg.scene.petioles.empty())  // said now, not after the growth
        throw core::InvalidInput(kNoSheetSeeds);
      const std::uint64_t sheet_end = s.has_target ? s.target_steps : cfg.steps;
      if (spec.domain.initial_nodes.empty() && (!s.resume || s.sheet_partial) &&
          std::all_of(cfg.scene.petioles.begin(), cfg.scene.petioles.end(),
                      [&](const forms::PetioleSpec& p) { return p.step > sheet_end; })) {
        const forms::PetioleSpec& first =
            *std::min_element(cfg.scene.petioles.begin(), cfg.scene.petioles.end(),
                              [](const forms::PetioleSpec& a, const forms::PetioleSpec& b) { return a.step < b.step; });
        throw core::InvalidInput(first.origin +
                                 "surface{cells = true} starts its veins at the petiole cells, but the first petiole "
                                 "is due at step " +
                                 std::to_string(first.step) + ", after the sheet's last step (" +
                                 std::to_string(sheet_end) +
                                 "): give seeds = {{x, y, z}, ...}, or a petiole due by then");
      }
      if (s.resume && s.cells_bytes.empty())
        throw core::InvalidInput("checkpoint '" + o.checkpoint.string() +
                                 "' holds no grown cells, but the script grows veins on cells (surface{cells = true})");
      if (s.resume && !s.sheet_partial) {
        sheet = cells::load(s.cells_bytes, "checkpoint '" + o.checkpoint.string() + "'");
        // a sheet grown shorter than run.steps now asks (the first run's --steps, an edited script) is not
        // grown further: said, as a resume's --steps (the veins' limit now) might be taken for the sheet's
        if (sheet_steps && *sheet_steps < cfg.steps)
          err << "cellform: note: the sheet grew " << *sheet_steps << " steps, fewer than run.steps now asks ("
              << cfg.steps << "); a resume goes on with the veins on that sheet (--steps limits the veins), and a new "
              << "run grows the whole sheet\n";
      } else {
        const auto grow_start = std::chrono::steady_clock::now();
        Sheet grown = grow_sheet(o, s, cfg, host, seed, checkpoint, err, failed);
        sheet_seconds = seconds_since(grow_start) - grown.checkpoint_seconds;
        clock_start = grown.checkpoint_clock;
        checkpoint_seconds += grown.checkpoint_seconds;
        sheet_initial = grown.initial;
        sheet_steps = grown.step;
        sheet_checkpointed = grown.checkpointed;
        if (!grown.complete) {  // Ctrl-C: the sheet so far, and its checkpoint to finish it from
          if (!grown.checkpointed && !grown.checkpoint_error.empty() &&
              keep_other_run(dir, s.resume ? o.checkpoint : fs::path(), grown.checkpoint_error, staging, created, err))
            return failure;
          std::vector<std::string> outputs = write_outputs(staging, cfg.output, grown.cells, nullptr);
          json run = colonisation_run_record(s, seed, o.threads, spec, cfg.resolved);
          run["status"] = "interrupted";
          run["phase"] = "cells";  // the veins have not started
          run["steps"] = {{"first", 0}, {"completed", 0}, {"limit", spec.params.max_steps}};
          run["cells"] = {{"initial", grown.initial},
                          {"final", grown.cells.size()},
                          {"steps", grown.step},
                          {"target", grown.target}};
          run["timings"] = {
              {"total_s", seconds_since(t0)}, {"sheet_s", sheet_seconds}, {"checkpoints_s", checkpoint_seconds}};
          std::error_code same;  // a resumed checkpoint of this folder is there still when this one failed
          const bool resumed_here = s.resume && !grown.checkpointed && fs::equivalent(o.checkpoint, checkpoint, same);
          record_checkpoint(run, grown.checkpoint_error, grown.checkpointed || resumed_here, std::nullopt);
          outputs.push_back("run.json");
          run["outputs"] = outputs;
          write_run_json(staging / "run.json", run);
          commit_outputs(staging, dir, outputs);
          drop_earlier_checkpoint(dir, run, s.resume ? o.checkpoint : fs::path());
          err << "interrupted while the cell sheet grew (step " << grown.step << " of " << grown.target
              << "; no veins yet): the sheet so far is in " << dir.string() << "/\n";
          if (!grown.checkpoint_error.empty()) {
            err << "cellform: " << grown.checkpoint_error
                << (resumed_here
                        ? "\n  (" + o.checkpoint.string() +
                              ", the checkpoint resumed, is as it was: a resume of it grows these steps again"
                        : "\n  (this run cannot be resumed" +
                              (grown.checkpointed ? "; the last periodic checkpoint, " + checkpoint.string() + ", can"
                                                  : std::string()))
                << ")\n";
            return failure;
          }
          err << "continue with: " + continue_command(checkpoint, o.limits) + "\n";
          return interrupted;
        }
        sheet = std::move(grown.cells);
      }
    }
    const bool fresh = !s.resume || s.sheet_partial;                     // the veins start at step 0
    if (!fresh && !o.quiet && s.colonisation_bytes.size() > 20'000'000)  // its indexes take seconds to rebuild
      err << "loading the veins of checkpoint '" << o.checkpoint.string() << "' ("
          << s.colonisation_bytes.size() / 1'000'000 << " MB)...\n";
    venation::Colonisation col = [&] {
      if (fresh) return make_colonisation(spec, sheet ? &*sheet : nullptr);
      try {
        return make_colonisation(spec, sheet ? &*sheet : nullptr, &s.colonisation_bytes,
                                 "checkpoint '" + o.checkpoint.string() + "'");
      } catch (const core::FileError& e) {  // a damaged checkpoint is bad input (exit 2), as for a cell run
        throw core::InvalidInput(e.what());
      } catch (const venation::ParametersChanged&) {
        const std::string changed = changed_colonisation_values(s, cfg);
        if (changed.empty()) throw;
        // the change first, from this resume's side (the checkpoint "saved with other parameters" read backwards)
        throw core::InvalidInput(
            "checkpoint '" + o.checkpoint.string() +
            "' continues with the parameters it was saved with, and this resume changes them: " + changed + ". Only " +
            script_colonisation_message(venation::kContinueMayDiffer) + "; start a new run for other values");
      } catch (const venation::DomainChanged&) {  // told by its type (the message holds the checkpoint's path)
        const std::string domain = changed_domain_values(s, cfg);  // the script's values changed, not the files
        if (!domain.empty())
          throw core::InvalidInput("checkpoint '" + o.checkpoint.string() +
                                   "' grew its veins in another source domain: changed: " + domain +
                                   "; a resume goes on in the blade, volume or surface it started in (start a "
                                   "new run for another)");
        throw;
      }
    }();
    const std::size_t first = col.report().steps;
    auto save = [&] {
      keep_resumed_checkpoint(s, dir, err);  // resume --script: the checkpoint resumed is replaced now
      write_checkpoint(checkpoint, colonisation_checkpoint_bytes(s, seed, spec.params, col, sheet ? &*sheet : nullptr,
                                                                 sheet_initial, sheet_steps));
      if (!kept_staging.empty()) {
        std::error_code ec;
        fs::remove_all(kept_staging, ec);
        kept_staging.clear();
      }
    };
    if (!o.quiet)
      err << (fresh ? "growing" : "resuming") << " veins by space colonisation in " << s.script_path.string()
          << " (seed " << seed << (fresh ? std::string() : ", from step " + std::to_string(first)) << ")\n";
    if (fresh)
      say_large_domain(err, spec.domain,
                       !spec.on_cells && (spec.domain.kind == venation::DomainKind::volume ||
                                          spec.domain.kind == venation::DomainKind::surface));
    const auto a = std::chrono::steady_clock::now();
    const bool nonuniform = spec.params.growth == venation::GrowthMode::nonuniform;
    std::size_t last_print = 0;
    auto last_print_time = std::chrono::steady_clock::now();
    bool saved = false;          // this run wrote checkpoint.cfck (an older one may be there from another run)
    std::size_t saved_step = 0;  // the step of the last checkpoint it wrote
    CheckpointClock checkpoints(cfg.output, clock_start);
    bool checkpoint_warned = false;
    double vein_checkpoint_seconds = 0;  // the periodic checkpoints of the veins' steps
    // run.json's timings so far but total_s: the veins' steps without their periodic checkpoints, all of those,
    // and the sheet grown first in this command
    auto steps_timings = [&] {
      json t = {{"simulation_s", seconds_since(a) - vein_checkpoint_seconds},
                {"checkpoints_s", checkpoint_seconds + vein_checkpoint_seconds}};
      if (sheet_seconds > 0) t["sheet_s"] = sheet_seconds;
      return t;
    };
    try {
      while (!col.done()) {
        if (g_interrupt.load()) {
          code = interrupted;
          break;
        }
        const venation::ColonisationReport& r = col.step();
        const auto now = std::chrono::steady_clock::now();
        if (!o.quiet &&
            (r.steps - last_print >= 50 || now - last_print_time >= std::chrono::seconds(5) || col.done())) {
          last_print = r.steps;
          last_print_time = now;
          err << "step " << r.steps << ": " << r.nodes << " vein nodes, " << r.sources
              << (r.sources == 1 ? " source" : " sources");
          if (planar) err << (nonuniform ? ", growth step " : ", leaf length ") << r.scale;
          // every 50 steps or 5 s (no end is known); the line shrinks by at most 7 (sources, hours): padded
          err << ", " << duration_text(std::chrono::duration<double>(now - a).count()) << " so far"
              << (::isatty(2) ? "          \r" : "\n") << std::flush;
        }
        if (!col.done() && checkpoints.due(r.steps) &&
            periodic_checkpoint(save, err, checkpoint_warned, vein_checkpoint_seconds)) {
          saved = true;
          saved_step = r.steps;
        }
      }
    } catch (const std::exception&) {
      // a step that failed may have left the state half changed: the last checkpoint is the one to resume
      if (!o.quiet && ::isatty(2)) err << "\n";
      failed.steps = {{"first", first}, {"completed", saved_step}, {"failed", col.report().steps + 1}};
      failed.checkpointed = saved || sheet_checkpointed;
      failed.checkpoint_note = saved ? "" : ", taken while the sheet grew";
      failed.timings = steps_timings();
      throw;
    }
    failed.timings = steps_timings();  // run.json's, and a failed one's if the outputs fail
    if (!o.quiet && ::isatty(2)) err << "\n";
    // before the outputs: a failure writing them leaves the checkpoint; and a checkpoint that cannot be
    // written (a full disk) still leaves the outputs
    std::string checkpoint_error;
    const auto save_final = [&] {
      no_step = s.resume && col.report().steps == first;
      const auto own = no_step ? own_record(o.checkpoint, dir) : std::nullopt;
      if (own) earlier_record = *own;
      try {
        save();
        saved = true;
      } catch (const std::exception& e) {
        checkpoint_error = core::error_text(e);
      }
      resumable = saved;
      if (saved && col.report().steps > first) stepped = {{"first", first}, {"completed", col.report().steps}};
      checkpoint_failure = checkpoint_error;
    };
    // no step ran: the outputs are made again for another print. The checkpoint after the print, so that
    // one that fails (too fine a voxel for the memory, say) leaves the folder as it was, its earlier print too.
    const bool reprint = !fresh && col.report().steps == first && cfg.print.has_value();
    if (!reprint) save_final();
    // none of this run's: a checkpoint of another run there stays, and with it that run's outputs
    if (!reprint && !saved && !sheet_checkpointed &&
        keep_other_run(dir, s.resume ? o.checkpoint : fs::path(), checkpoint_error, staging, created, err))
      return failure;
    venation::VeinTree tree = col.tree();
    // petiole cells the grown sheet left off its surface (the veins started at the nearest point of it): a
    // stem joins each to its veins, so they stand on their supports
    const std::vector<core::Vec3> petioles = sheet ? sheet_petioles(*sheet) : std::vector<core::Vec3>{};
    if (sheet && spec.domain.initial_nodes.empty() && tree.size() > petioles.size())  // veins grew from them
      tree = venation::with_stems(tree, petioles, 1e-9);
    venation::compute_widths(tree, spec.widths);
    const venation::ColonisationReport rep = col.report();
    // stopped by max_sources before a step it would not take: the stop says why nothing grew
    const bool stopped_before_step = rep.hit_max_sources && rep.sources_wanted > 0;
    if (code == ok) say_no_veins(err, spec, rep, tree, stopped_before_step, planar);
    double leaf_length = rep.scale;  // the outline is 1 long at scale 1; nonuniform growth reports steps
    if (nonuniform) {
      const venation::Outline grown = col.outline();
      double lo = grown.points.front().y(), hi = lo;
      for (const venation::Vec2& q : grown.points) lo = std::min(lo, q.y()), hi = std::max(hi, q.y());
      leaf_length = hi - lo;
    }
    std::vector<std::string> outputs;
    if (cfg.output.ply) {
      venation::write_vein_ply(staging / "veins.ply", tree);
      outputs.push_back("veins.ply");
    }
    if (cfg.output.obj) {
      venation::write_vein_obj(staging / "veins.obj", tree);
      outputs.push_back("veins.obj");
    }
    if (cfg.output.png) {  // 3-D patterns are drawn as seen from above (+z), without an outline
      exporters::PngParams png;
      png.size = cfg.output.png_size;
      // the blank border of veins.svg (5 mm round its default 200 mm) in proportion, at least 10 pixels; small
      // images keep room to draw
      png.margin = std::min(std::max(png.margin, std::round(static_cast<double>(png.size) * 5.0 / 210.0)),
                            std::floor(static_cast<double>(png.size) / 8.0));
      exporters::write_vein_png(staging / "veins.png", tree, planar ? col.outline() : venation::Outline{}, png);
      outputs.push_back("veins.png");
    }
    if (sheet)
      for (const std::string& n : write_outputs(staging, cfg.output, *sheet, nullptr)) outputs.push_back(n);
    json printed;
    bool print_failed = false, print_cancelled = false;
    const auto discard_reprint = [&](const std::string& said, int exit_code) {  // the print was all it made
      err << (exit_code == interrupted && !o.quiet ? "\n" : "") << said << "\n  (nothing in " << dir.string()
          << "/ changed: its outputs, printable files and checkpoint are as they were)\n";
      std::error_code ec;
      fs::remove_all(staging, ec);
      remove_empty_up_to(dir, created);
      return exit_code;
    };
    std::vector<exporters::Segment> segments;  // (veins.svg is drawn at the print's scale)
    std::vector<std::array<core::Vec3, 3>> shell;
    if (cfg.print) {
      try {
        if (cfg.print->veins) segments = vein_segments(tree);  // (veins = false: the sheet alone)
        if (cfg.print->shell && sheet)
          shell = exporters::shell_triangles(*sheet, cells::Surface{cells::covering_triangles(*sheet), {}});
        if (segments.empty() && shell.empty() && stopped_before_step && code == ok) {
          err << "cellform: print: skipped: nothing grew before colonisation.max_sources stopped the run (a "
                 "resume with a higher limit prints)\n";
          printed = {{"skipped", "nothing to print: stopped at colonisation.max_sources before anything grew"}};
        } else if (cfg.print->veins && segments.empty() && code == ok && rep.hit_max_steps &&
                   spec.params.max_steps < script_steps) {
          // a quick try (--steps) cut short before a vein grew: not the sheet alone (a flat base may not fit yet)
          printed = {{"skipped", "nothing to print yet at step " + std::to_string(rep.steps) +
                                     " (no vein has grown; the run was cut short at step " +
                                     std::to_string(spec.params.max_steps) + " of the script's " +
                                     std::to_string(script_steps) + ")"}};
          err << "cellform: print: skipped: " << printed["skipped"].get<std::string>() << "\n";
        } else if (segments.empty() && shell.empty()) {
          throw NothingToPrint(
              !cfg.print->veins
                  ? "print: nothing to print: print.veins = false leaves only the cell sheet, and there is none "
                    "(print.shell = true with surface{cells = true})"
              : code == interrupted
                  ? "print: nothing to print: the run was interrupted before anything printable grew"
                  : "print: nothing to print: no vein grew (run longer, raise colonisation.darts, or lower "
                    "colonisation.birth_distance)");
        } else {
          printed = thicken_and_write(staging, *cfg.print, segments, shell, o.threads, outputs, err, o.quiet,
                                      cfg.print->shell && sheet ? shell_closing(*sheet, cfg.print->close_holes) : 0.0,
                                      sheet.has_value());
          if (!o.quiet) say_printed(err, printed);
        }
      } catch (const core::Cancelled&) {  // said once the other files are in (another Ctrl-C quits before)
        if (reprint) return discard_reprint("cellform: printing interrupted", interrupted);
        print_cancelled = true;
        printed = {{"error", "interrupted"}};
        code = interrupted;
      } catch (const std::exception& e) {
        const std::string m = output_error(e, staging, dir);
        if (reprint) return discard_reprint("cellform: " + m, failure);
        // (after a periodic checkpoint, not the final one, a resume grows the rest again: no quick retry)
        say_print_failed(err, m, "", saved && checkpoint_error.empty() && !dynamic_cast<const NothingToPrint*>(&e),
                         checkpoint, o.limits);
        printed = {{"error", m}};
        if (code != interrupted) {  // a Ctrl-C that came first stays the reason the run ended
          code = failure;
          print_failed = true;
        }
      }
    }
    if (reprint) {  // the print worked
      save_final();
      if (!saved && keep_other_run(dir, o.checkpoint, checkpoint_error, staging, created, err)) return failure;
    }
    json svg_record;
    if (planar)  // a drawing of the leaf; a 3-D pattern has no one plane to draw it in
      svg_record = draw_veins_svg(staging, cfg.output, cfg.print ? &*cfg.print : nullptr, printed, segments, shell,
                                  tree, col.outline(), outputs, err);
    json run = colonisation_run_record(s, seed, o.threads, spec, cfg.resolved);
    run["status"] = code == interrupted   ? "interrupted"
                    : print_failed        ? "print failed"
                    : rep.finished        ? "complete"
                    : rep.stalled         ? "stalled"
                    : rep.hit_max_nodes   ? "stopped at max_nodes"
                    : rep.hit_max_sources ? "stopped at max_sources"
                                          : "stopped at max_steps";
    run["steps"] = {{"first", first}, {"completed", rep.steps}, {"limit", spec.params.max_steps}};
    if (planar) run["svg"] = svg_record;
    run["veins"] = {{"nodes", rep.nodes},
                    {"loops", venation::independent_cycles(tree)},  // cycles, not the joins of two seeds' trees
                    {"anastomoses", rep.loops},
                    {"sources_left", rep.sources},
                    {"sources_born", rep.sources_born}};
    if (tree.size() > rep.nodes) run["veins"]["stems"] = tree.size() - rep.nodes;  // nodes of veins.* beyond
    run["timings"] = failed.timings;
    run["timings"]["total_s"] = seconds_since(t0);
    // a resume whose checkpoints failed in the folder of the checkpoint it resumed: that one is there still
    std::error_code same;
    const bool resumed_here =
        s.resume && !saved && !sheet_checkpointed && fs::equivalent(o.checkpoint, checkpoint, same);
    record_checkpoint(run, checkpoint_error, saved || sheet_checkpointed || resumed_here,
                      saved ? std::optional<std::uint64_t>(saved_step) : std::nullopt);
    if (cfg.print) run["print"] = printed;
    if (planar) run["veins"]["leaf_length"] = leaf_length;
    if (sheet) run["cells"] = {{"initial", sheet_initial}, {"final", sheet->size()}};
    if (sheet && sheet_steps) {  // the steps the sheet grew (--steps too), as run.steps would give them again
      run["cells"]["steps"] = *sheet_steps;
      if (run.contains("parameters") && run["parameters"].contains("run"))
        run["parameters"]["run"]["steps"] = *sheet_steps;
    }
    outputs.push_back("run.json");
    run["outputs"] = outputs;
    write_run_json(staging / "run.json", run);
    commit_outputs(staging, dir, outputs);
    drop_earlier_checkpoint(dir, run, s.resume ? o.checkpoint : fs::path());
    if (print_cancelled)
      err << (o.quiet || !::isatty(2) ? "" : "\n")  // the print's bar is drawn only on a terminal
          << "cellform: printing interrupted: no printable files (the vein files are written)\n";
    if (!checkpoint_error.empty()) {
      err << "cellform: " << checkpoint_error
          << (saved || sheet_checkpointed
                  ? "\n  (the other outputs are written; the run can be resumed from its last periodic checkpoint, " +
                        checkpoint.string() +
                        (saved ? ", of step " + std::to_string(saved_step)
                               : std::string(", taken while the sheet grew")) +
                        ")\n"
              : no_step || resumed_here
                  ? "\n  (the other outputs are written; " + o.checkpoint.string() +
                        ", the checkpoint resumed, is as it was" +
                        (no_step ? std::string(")\n") : ": a resume of it runs this run's steps again)\n")
                  : std::string("\n  (the other outputs are written, but this run cannot be resumed)\n"));
      code = failure;
    }
    std::ostream& where = code == ok ? out : err;
    if (!o.quiet || code != ok)
      where << (code == interrupted ? "interrupted"
                : print_failed      ? "veins done, but the print failed"
                : rep.finished      ? "done"
                : rep.stalled       ? "done (stalled: some sources can no longer be reached)"
                : rep.hit_max_nodes ? "stopped at colonisation.max_nodes"
                : rep.hit_max_sources && rep.sources_wanted > 0
                    ? "stopped at colonisation.max_sources (" + std::to_string(spec.params.max_sources) +
                          ") before step " + std::to_string(rep.steps + 1) +
                          ", whose darts would make more auxin sources than that wait at once; it was not taken. "
                          "Raise the limit to take it (each waiting source holds about a kilobyte), or throw fewer "
                          "darts (colonisation.darts" +
                          (planar                                              ? std::string(", or a smaller blade")
                           : spec.domain.kind == venation::DomainKind::surface ? std::string(", or a smaller surface")
                                                                               : std::string(", or a smaller volume")) +
                          (spec.params.growth != venation::GrowthMode::none ? ") or grow the leaf less" : ")")
                : rep.hit_max_sources
                    ? "stopped at colonisation.max_sources (" + std::to_string(rep.sources) +
                          " auxin sources wait for veins; the limit keeps a leaf that outgrows its veins from running "
                          "out of memory: raise it to go on, or grow the leaf less or throw fewer darts)"
                    : std::string("stopped at max_steps"))
            << ": " << rep.steps << " steps, " << tree.size() << " vein nodes, " << venation::independent_cycles(tree)
            << " loops" << extent_text(tree.positions) << "; outputs in " << dir.string() << "/\n";
    if (rep.stalled && code != interrupted) {
      const venation::Outline outline = planar ? col.outline() : venation::Outline{};
      say_sources_left(err, spec, col.sources(), planar ? &outline : nullptr);
    }
    if ((!o.quiet || code != ok) && code != interrupted && !rep.finished && !rep.stalled && checkpoint_error.empty()) {
      // both limits can be reached in one step; doubled, within what --steps and --set accept
      // (twice what was reached, where one step went past the limit: the resume must make room to step on)
      auto twice = [](std::size_t limit, std::size_t reached) {
        return std::to_string(std::min<std::size_t>(2 * std::max(limit, reached), 1'000'000'000));
      };
      where << "continue with: " << continue_command(checkpoint, o.limits);
      if (rep.hit_max_nodes) where << " --set colonisation.max_nodes=" << twice(spec.params.max_nodes, rep.nodes);
      if (rep.hit_max_sources)
        where << " --set colonisation.max_sources="
              << twice(spec.params.max_sources, std::max(rep.sources, rep.sources_wanted));
      if (rep.hit_max_steps) where << " --steps " << twice(spec.params.max_steps, rep.steps);
      where << "\n";
    }
    if (code == interrupted && checkpoint_error.empty())
      err << "continue with: " << continue_command(checkpoint, o.limits) << "\n";
    return code;
  } catch (const std::exception& e) {
    const bool input = dynamic_cast<const core::InvalidInput*>(&e) != nullptr;
    const std::string m = input ? e.what() : output_error(e, staging, dir);
    // a parameter the steps found wrong: where the script sets it
    err << "cellform: " << (input && m.rfind("colonisation.", 0) == 0 ? spec.where : std::string()) << m << "\n";
    if (input && !g_interrupt.load()) err << knob_recall(s.sets, m);  // a value a --set knob sized
    code = input ? usage : failure;
    fs::path last;
    if (failed.checkpointed) {  // a step failed after this run wrote a checkpoint
      last = checkpoint;
      keep_failed_run(m);
    } else if (s.resume && !failed.steps.is_null() && fs::exists(o.checkpoint)) {
      err << "  (the last checkpoint is " << o.checkpoint.string() << ", the one resumed)\n";
      last = o.checkpoint;
    } else if (!input) {
      // the outputs failed (a full disk): what is left to continue from
      if (!checkpoint_failure.empty())
        err << "cellform: the final checkpoint failed too: " << checkpoint_failure << "\n";
      // with steps in it, a run.json that says the run failed and why (as a cell run's; not for a resume
      // that only wrote the outputs again, whose run.json the checkpoint marked superseded)
      if (resumable && fs::exists(dir / kCheckpointName) && !stepped.is_null()) {
        failed.steps = stepped;
        keep_failed_run(m);
      } else if (resumable && fs::exists(dir / kCheckpointName)) {
        err << "  (the last checkpoint written is " << (dir / kCheckpointName).string()
            << "; cellform resume continues from it)\n";
        if (!earlier_record.empty()) try {  // the folder's run.json as it was
            core::write_file_atomically(dir / "run.json", [&](std::ostream& os) { os << earlier_record; });
          } catch (const std::exception&) {  // as full as that: the mark stays, the first error is the one said
          }
      }
    }
    // the same script would stop there again: an edited one can go on from the checkpoint
    if (!last.empty() && (input || dynamic_cast<const core::SimulationDiverged*>(&e)))
      err << resume_hint(o, last, s.script_path) << "\n";
  }
  std::error_code ec;
  fs::remove_all(staging, ec);
  remove_empty_up_to(dir, created);  // a failed run leaves no empty folder
  return code;
}

}  // namespace cellform::app
