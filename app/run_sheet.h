// Internal to app/: the cell sheet that surface{cells = true} grows before space colonisation puts veins on
// it (run_sheet.cpp), the colonisation made on it or in any domain, and what a colonisation run that failed has
// left (run_colonisation.cpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/run_internal.h"
#include "cells/cells.h"
#include "venation/colonisation.h"

namespace cellform::app {

/// The cells of surface{cells = true}, and whether they grew for all their steps.
struct Sheet {
  cells::Cells cells;
  std::uint64_t step = 0, target = 0;
  std::size_t initial = 0;  // cells when the growth began (of the run, not of this resume)
  bool complete = false;
  bool checkpointed = false;      // a sheet checkpoint of this run is in the folder
  double checkpoint_seconds = 0;  // spent on its periodic checkpoints
  // when its last periodic checkpoint was written, or its growth began: the veins' clock goes on from there
  std::chrono::steady_clock::time_point checkpoint_clock;
  std::string checkpoint_error;  // why the checkpoint on Ctrl-C could not be written
};

/// What a colonisation run that a step's error stopped has left: for its run.json and its message.
struct FailedRun {
  bool checkpointed = false;    // this run wrote the checkpoint in its folder
  std::string checkpoint_note;  // said of that checkpoint (", taken while the sheet grew")
  std::string phase;            // "cells" while the sheet grew
  nlohmann::json steps;         // run.json's steps; null unless a step failed
  // while the sheet grows, for a script stuck in one library call (ScriptHost::set_on_stuck), whose
  // handler cannot wait for an exception: the step being computed and the checkpoints so far
  bool sheet_growing = false;
  std::uint64_t sheet_first = 0, sheet_saved = 0, sheet_stepping = 0;
  bool sheet_checkpointed = false;
  std::chrono::steady_clock::time_point sheet_start;  // when the sheet's steps began
  double sheet_checkpoint_s = 0;                      // spent on its periodic checkpoints so far
  /// run.json's timings but total_s: the steps and checkpoints so far (seconds)
  nlohmann::json timings = nlohmann::json::object();
  /// The state of the sheet's growth as run_colonisation's catch records it, with `failing` the step.
  void sheet_failed(std::uint64_t failing) {
    phase = "cells";
    steps = {{"sheet_first", sheet_first}, {"sheet_completed", sheet_saved}, {"sheet_failed", failing}};
    const double grown = seconds_since(sheet_start);
    timings = {{"sheet_s", grown - sheet_checkpoint_s}, {"checkpoints_s", sheet_checkpoint_s}};
    checkpointed = sheet_checkpointed;
    checkpoint_note = ", taken while the sheet grew at step " + std::to_string(sheet_saved);
  }
};

/// surface{cells = true}: grows the script's cells (cells{}, division{}, run{}, shapes) for --steps or
/// run.steps steps (from a sheet checkpoint's step when `s` resumes one). Writes a sheet checkpoint to
/// `checkpoint` as output.checkpoint_every asks and when a Ctrl-C ends the growth early.
Sheet grow_sheet(const RunOptions& o, Start& s, const SceneConfig& cfg, ScriptHost& host, std::uint64_t seed,
                 const std::filesystem::path& checkpoint, std::ostream& err, FailedRun& failed);

/// Said when surface{cells = true} has no seed: none given and no petiole cell in the grown sheet.
inline constexpr const char* kNoSheetSeeds =
    "surface{cells = true} needs seeds = {{x, y, z}, ...} or a petiole{...} cell where the veins start";

/// The petiole cells of a grown sheet, in order: the default seeds of surface{cells = true}.
std::vector<core::Vec3> sheet_petioles(const cells::Cells& sheet);

/// The colonisation of the spec's domain; for surface{cells = true} the sheet of `sheet`, with the seeds
/// (default: the petiole cells) moved onto it. With `state` (resume), from that Colonisation::save() state.
venation::Colonisation make_colonisation(const ColonisationSpec& spec, const cells::Cells* sheet,
                                         const std::string* state = nullptr, const std::string& what = "");

/// Notes a 3-D domain over 1,000 vein segments (model units) across: a mesh in mm without {scale} grows for hours.
void say_large_domain(std::ostream& err, const venation::Domain& d, bool mesh_file);

/// The parts of a colonisation run's run.json that do not depend on how it ended; its "parameters" are the
/// script's resolved values, without the cells' and the division's when no cell grows.
nlohmann::json colonisation_run_record(const Start& s, std::uint64_t seed, int threads, const ColonisationSpec& spec,
                                       const nlohmann::json& parameters);

}  // namespace cellform::app
