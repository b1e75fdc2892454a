// The embedded, sandboxed Lua 5.4 host that turns a growth script into a scene configuration.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cells/simulation.h"
#include "forms/scene.h"
#include "venation/colonisation.h"
#include "venation/domain.h"
#include "venation/leaf_shape.h"

struct lua_State;

namespace cellform::app {

/// Limits that stop a runaway script with a clear error.
struct ScriptLimits {
  std::uint64_t instructions = 500'000'000;      ///< Lua VM instructions for running the script itself
  std::uint64_t rule_instructions = 10'000'000;  ///< per call of a rule function
  std::size_t memory_bytes = 512u << 20;         ///< Lua heap, bytes
  /// Seconds one call into Lua's C libraries may run (the instruction budget does not see inside one: a
  /// string pattern that backtracks can run for hours) before the process stops with a message (exit 2);
  /// after a Ctrl-C, such a call gets 2 s (exit 130).
  double library_seconds = 60;
};

/// A cell the script places before the first step.
struct InitialCell {
  core::Vec3 position;
  bool fixed = false;
};

/// What the script asked for.
struct OutputSpec {
  bool ply = true;
  bool obj = true;
  std::uint64_t every = 0;                ///< frame interval in steps (0 = no frames)
  std::uint64_t checkpoint_every = 1000;  ///< checkpoint interval in steps (0 = only at the end)
  double checkpoint_seconds = 60;  ///< s: a periodic checkpoint this soon after the last one is skipped (0: never)
  double checkpoint_minutes =
      10;                       ///< min: also one this long after the last one (or the start), at any step (0: never)
  bool png = false;             ///< space colonisation: also write veins.png
  int png_size = 1024;          ///< pixels: longer side of veins.png
  double svg_size = 0;          ///< mm: longer side of the leaf drawn in veins.svg (0: the print's scale, or 200)
  std::string svg_size_at;      ///< where svg_size was given ("file:line: " or "--set ...: "), or empty
  bool svg_join_veins = false;  ///< veins.svg: a path per vein (svg_paths = "veins")
  std::string svg_paths_at;     ///< where svg_paths was given, or empty
};

/// Space colonisation requested by colonisation{...} in a leaf{...}, volume{...} or surface{...}.
struct ColonisationSpec {
  venation::Leaf leaf;
  venation::ColonisationParams params;
  venation::WidthParams widths;
  venation::Domain domain;    ///< kind leaf: grows in `leaf`; else in this volume or surface
  bool on_cells = false;      ///< surface{cells = true}: grow the cells first, the domain is their sheet
  bool growth_given = false;  ///< colonisation.growth was set (a 3-D domain then needs "none")
  std::string length_given;   ///< a leaf-size field set (initial_length, ...): none of a 3-D domain's
  std::string where;          ///< "file:line: " of colonisation{...}, for its errors found while it runs
  std::string domain_where;   ///< "file:line: " of volume{...} or surface{...}, likewise
};

/// A printable solid requested by print{...}.
struct PrintSpec {
  bool veins = true;
  bool shell = false;
  double size = 120;             ///< mm, largest extent when scale = 0
  double scale = 0;              ///< mm per model unit (0 = auto)
  double min_radius = 0.4;       ///< mm
  double shell_thickness = 0.6;  ///< mm
  double voxel_size = 0;         ///< mm (0 = auto)
  double adaptivity = 0.2;
  double max_memory_mb = 2000;
  std::vector<std::string> formats{"stl"};  ///< stl, obj, ply, scad, vdb
  std::string pieces = "warn";              ///< any, warn, one
  bool fill_cavities = false;               ///< fill closed pockets inside the solid
  double flat_base = 0;                     ///< mm cut off the bottom for a flat base (0 = none)
  bool lay_flat = false;                    ///< each vein raised by its radius: a flat form's veins rest on its plane
  double close_holes = 1;                   ///< cell spacings: holes in the shell up to this size are filled
  double close_holes_max = 2;               ///< mm: the closing's radius at most (0 = no cap)
};

/// Everything a script describes, resolved (script values, then --set overrides, then defaults).
struct SceneConfig {
  forms::SceneDescription scene;
  std::vector<InitialCell> initial_cells;
  std::uint64_t steps = 200;
  std::string steps_given_at;  ///< where run.steps was given ("file:line: " or "--set run.steps=N: "), or empty
  std::uint64_t seed = 1;
  double max_memory_mb = 0;  ///< run.max_memory: MB the cells may take at the peak; 0 = three quarters of the machine's
  OutputSpec output;
  std::optional<PrintSpec> print;
  std::optional<ColonisationSpec> colonisation;        ///< set: the run grows veins by space colonisation, not cells
  nlohmann::json resolved = nlohmann::json::object();  ///< every resolved parameter, by section
  /// what the script sets that has no effect in this run, said before it starts ("file:line: print.x ...")
  std::vector<std::string> notes;
  /// each mesh{} obstacle's file, in script order: its path as read, and "fnv1a64:<hex>" of its bytes
  std::vector<std::pair<std::filesystem::path, std::string>> mesh_files;
};

/// --set overrides: "name" for params{} knobs, "section.name" for script functions' parameters.
using Overrides = std::map<std::string, std::string>;

/// Runs growth scripts in a sandbox: only the cellform API and the safe parts of the base, string,
/// table, math, utf8 and coroutine libraries; no files, processes, OS, module loading or binary chunks.
/// Errors are core::InvalidInput with "file:line:" first.
class ScriptHost {
 public:
  explicit ScriptHost(ScriptLimits limits = {});
  ~ScriptHost();
  ScriptHost(const ScriptHost&) = delete;
  ScriptHost& operator=(const ScriptHost&) = delete;

  /// Runs `source` (named `script_path` in messages; relative file names resolve beside it) and returns
  /// the scene it describes. Every override must match a parameter, else InvalidInput with a suggestion;
  /// those named in `may_go_unused` may match none (unused_overrides() lists them then).
  SceneConfig load(const std::string& source, const std::filesystem::path& script_path, const Overrides& overrides,
                   const std::set<std::string>& may_go_unused = {});

  /// Overrides among `keys` that set a boolean field may say 1 or 0 for true or false, as --set took them
  /// before December 2026 (a resumed checkpoint's own); any other must say true or false.
  void accept_digit_booleans(const std::set<std::string>& keys);

  /// The overrides of `may_go_unused` that the last load() found no parameter for, in key order.
  const std::vector<std::string>& unused_overrides() const { return unused_; }

  /// Rule functions of the loaded script as cells::Rules (empty members where the script gave none).
  /// A rule that errors throws core::InvalidInput naming the rule, the step and the cell id.
  cells::Rules rules();

  /// The venation source rule of the loaded script (empty if it gave a number).
  venation::SourceRule source_rule();

  /// The step number that rule errors report. Also reseeds the script's math.random from the run's seed
  /// and this step, so that rules drawing random numbers give the same results for the same seed, on any
  /// thread count, and after a resume.
  void set_step(std::uint64_t step);

  /// Throws core::InvalidInput, naming the knob and `step`, if a rule function changed a knob of params{}
  /// by the end of that step (in it, or in a rule called before the first step): the knobs are read-only (run.json
  /// records them as made, and a resume would start from them). Call after each step.
  void check_knobs(std::uint64_t step);

  /// The run's seed, for math.random in rules (set_step). While a script is read, math.random is seeded
  /// with 0.
  void set_seed(std::uint64_t seed) { seed_ = seed; }

  /// Where print() in a script goes (default: nowhere).
  void set_print(std::function<void(const std::string&)> print);
  /// The function set_print gave (empty before it).
  const std::function<void(const std::string&)>& print_function() const;

  /// What to do when the script is stuck in one call of a library function (ScriptLimits::library_seconds)
  /// and the process must end: called on the watchdog's thread with the message (no "cellform: " in
  /// front) just before _exit, while the script's thread is still inside that call. It must not touch this
  /// host or anything the stuck call may be changing. Empty = none (the message then says no outputs were
  /// written). StuckHandler sets one for a scope.
  void set_on_stuck(std::function<void(const std::string&)> handler);

  // Internal state used by the Lua C functions.
  struct Impl;

 private:
  class Watchdog;
  std::vector<std::string> unused_;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<Watchdog> watchdog_;  // after impl_: stopped first
  std::uint64_t step_ = 0;
  std::uint64_t seed_ = 0;
};

/// A host's stuck handler for one scope (it may capture that scope's locals).
class StuckHandler {
 public:
  StuckHandler(ScriptHost& host, std::function<void(const std::string&)> handler) : host_(host) {
    host_.set_on_stuck(std::move(handler));
  }
  ~StuckHandler() { host_.set_on_stuck({}); }
  StuckHandler(const StuckHandler&) = delete;
  StuckHandler& operator=(const StuckHandler&) = delete;

 private:
  ScriptHost& host_;
};

/// A message of venation/ in the script's terms (colonisation.scale_step -> colonisation.length_step,
/// leaf.initial_nodes -> leaf.seeds, ...): the library names its own fields, the script its parameters.
std::string script_colonisation_message(const std::string& message);

}  // namespace cellform::app
