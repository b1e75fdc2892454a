// Internal to the run command: what run.cpp (cell runs) and run_colonisation.cpp (space-colonisation
// runs) share. Not part of the app's interface.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/run.h"
#include "app/script_host.h"
#include "cells/cells.h"
#include "core/errors.h"
#include "export/printable.h"
#include "venation/canalisation.h"

namespace cellform::app {

constexpr std::uint32_t kCheckpointVersion = 1;
constexpr const char* kCheckpointKind = "CKPT";
constexpr const char* kCheckpointName = "checkpoint.cfck";

/// run.json's "veins": the last canalisation's figures. Its report when one ran in this process (Report::cells
/// counts the cells it saw); else those the checkpoint kept (`saved`: a resume that reached no canalisation
/// yet); else what the cells' saved attributes tell (an older checkpoint: cells with no path to a petiole: null).
nlohmann::json vein_summary(const cells::Cells& cells, const venation::Report& last, const nlohmann::json& saved);

/// Before the steps first + 1 to target of a cell run: a note for each petiole due after them, and for
/// canalisation whose first pass (at step venation.every) comes after them, so that no vein can grow.
void say_late_starts(std::ostream& err, const forms::SceneDescription& scene, std::uint64_t first,
                     std::uint64_t target);

/// At the end of a cell run whose last canalisation (`last`) ran in this process: a warning of the cells
/// that drain to no petiole; with `notes`, a note for each petiole that grew no vein (where, its auxin, why).
void say_vein_findings(std::ostream& err, const cells::Cells& cells, const venation::Report& last,
                       const venation::Params& params, bool notes);

/// At the end of a cell run (links made for the cells as they lie): a note if fixed cells, a shell's supports,
/// hold no link to the cells that move, which then came loose from them.
void say_loose_supports(std::ostream& err, const cells::Cells& cells);
/// Why a colonisation run that ended well grew no vein, if it did not: no source placed (with what to change),
/// or every source within the kill distance when it came.
void say_no_veins(std::ostream& err, const ColonisationSpec& spec, const venation::ColonisationReport& rep,
                  const venation::VeinTree& tree, bool stopped_before_step, bool planar);

/// An input problem (bad script, parameter or input file): exit code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a run is continuing from or starting with.
struct Start {
  std::string source;
  std::filesystem::path script_path;
  Overrides sets;
  std::optional<std::uint64_t> seed;
  std::uint64_t target_steps = 0;
  bool has_target = false;
  std::filesystem::path out_dir;
  std::string cells_bytes;                   // resume only: the cells (colonisation on cells: the grown sheet)
  std::string colonisation_bytes;            // resume only: a space-colonisation state (Colonisation::save)
  std::uint64_t step = 0;                    // resume only
  bool sheet_partial = false;                // resume only: a checkpoint taken while surface{cells = true}'s sheet grew
  std::size_t initial_cells = 0;             // cells when the run (not this resume) started; 0 = not known yet
  std::optional<std::uint64_t> sheet_steps;  // surface{cells = true}: the steps its sheet grew (older: not known)
  bool resume = false;
  std::optional<std::uint64_t> checkpoint_every;  // --checkpoint-every of the run (kept by its checkpoints)
  nlohmann::json physics;  // the run's cell, division and venation values (physics_of); resume: as saved, or null
  // resume only: the checkpoint's own script and --set overrides (what made the frames before it)
  std::string checkpoint_source;  // the checkpoint's script
  std::string checkpoint_script_hash;
  Overrides checkpoint_sets;
  std::set<std::string> digit_booleans;  // the checkpoint's overrides given as 1 or 0 (see accept_digit_booleans)
                                         // and not given otherwise on this command line
  std::set<std::string> checkpoint_digit_booleans;  // all of the checkpoint's, for reloading its own script
  // resume --script: the checkpoint's script was replaced by `source` (its path was replaced_path)
  bool script_replaced = false;
  std::string replaced_path;
  // the scripts this run has had before `source`, oldest first: {path, hash, until_step, parameters};
  // kept by its checkpoints (run.json's script.replaces)
  nlohmann::json replaced = nlohmann::json::array();
  std::string kept_checkpoint;         // resume --script: the file the resumed checkpoint was copied to, if any
  bool copy_before_replacing = false;  // copy the folder's checkpoint before the first write (keep_resumed_checkpoint)
  // that copy is of the folder's own checkpoint, not the one resumed (a kept copy, or a file elsewhere, was
  // resumed into the folder)
  bool copy_is_folders = false;
  nlohmann::json replaced_parameters;  // resume --script: the run's own script's resolved values, if it loads
  bool script_unchanged = false;       // resume --script with the script the checkpoint keeps: a plain resume
  // resume only: the checkpoint's own target and --checkpoint-every (before this command's options)
  std::uint64_t checkpoint_target = 0;
  std::optional<std::uint64_t> checkpoint_every_of_run;
  // resume of a space-colonisation run: this resume changes colonisation.max_steps (by --set, or an edited
  // script), which then becomes the run's step limit unless --steps gives one
  bool max_steps_changed = false;
  std::string checkpoint_mark;  // resume only: checkpoint_mark of the checkpoint resumed
  nlohmann::json vein_summary;  // resume only: run.json's "veins" at the checkpoint (null = not kept)
  // "fnv1a64:<hex>" of each mesh{} obstacle's file, in script order (SceneConfig::mesh_files): on a resume
  // first the checkpoint's (none: an older cellform did not record them), then this run's, which its
  // checkpoints keep
  std::optional<std::vector<std::string>> obstacle_meshes;
  // "fnv1a64:<hex>" of each mesh{} obstacle as the run uses it (scaled and moved: its vertices and triangles), in
  // script order: on a resume first the checkpoint's (none: an older cellform did not record them), then this run's
  std::optional<std::vector<std::string>> obstacle_geometry;
  // resume --script: the mesh{} obstacles of this run (indices in SceneConfig::scene.obstacles.meshes, which
  // mesh_files follows) that are none of those the checkpoint grew against (by obstacle_geometry, or by
  // obstacle_meshes for a checkpoint that kept only those), which check_resumed_cells tests against its cells'
  // links; none when it kept neither (its cells may have grown links across its own meshes)
  std::vector<std::size_t> new_meshes;
};

/// "fnv1a64:<hex>" of a script's text, as run.json and the checkpoints name it.
std::string script_hash(const std::string& source);

/// What `o` starts from: its script, or the checkpoint it resumes (read and checked against the options;
/// with --script, the edited script instead of the one the checkpoint keeps). Throws InputError.
Start start_from(const RunOptions& o);

/// resume --script: adds the checkpoint's own script (and s.replaced_parameters, its resolved values, when
/// known) to s.replaced; notes whether the checkpoint resumed is `dir`'s checkpoint.cfck, which this run's
/// checkpoints will replace (keep_resumed_checkpoint copies it first).
void record_replaced_script(Start& s, const RunOptions& o, const std::filesystem::path& dir);

/// A resume of another checkpoint (a copy kept as checkpoint-stepN.cfck, or a file elsewhere) into a folder
/// that holds a checkpoint.cfck of its own: plans a copy of that one too (keep_resumed_checkpoint), as --script
/// keeps the checkpoint it replaces. Call after record_replaced_script.
void plan_keeping_folder_checkpoint(Start& s, const RunOptions& o, const std::filesystem::path& dir);

/// Before a resumed run first replaces `dir`'s checkpoint.cfck (with --script, the one it resumed; or the
/// folder's own, see plan_keeping_folder_checkpoint): copies it beside as checkpoint-stepN.cfck (the first free
/// name), notes a resumed one's copy in s.replaced and says so on `err`. Throws core::FileError if the copy
/// cannot be made (then the checkpoint must not be replaced either).
void keep_resumed_checkpoint(Start& s, const std::filesystem::path& dir, std::ostream& err);

/// --checkpoint-every N, of this command or of the run resumed, applies exactly: every N steps, with no
/// seconds between them. Sets `output` (when given) and the output section of `resolved` (run.json's
/// parameters) so; nothing when `every` is empty.
void apply_checkpoint_every(std::optional<std::uint64_t> every, OutputSpec* output, nlohmann::json& resolved);

/// A resume of a space-colonisation run whose --set or edited script changed colonisation.max_steps: that is
/// the run's step limit now, unless --steps gives one. Throws InputError for a limit below the checkpoint's step.
/// A cell run (or a sheet still growing) reads its mesh{} files again: on a resume they must be the ones it
/// grew against (InputError naming those that changed), or its cells would go on against walls that were not
/// there; an edited script (resume --script) takes them as they are, with a note on `err`. Then records this
/// run's fingerprints in `s` for its checkpoints.
void adopt_mesh_files(Start& s, const RunOptions& o, const SceneConfig& cfg, std::ostream& err);

/// Refuses (core::InvalidInput) a resume with an edited script (resume --script) whose obstacles hold some of the
/// checkpoint's cells (those of `scene`, made from `cfg`), as a new run's shapes inside an obstacle are, or whose
/// venation{} has no petiole cell to drain to: none among the cells and no petiole{} due after the checkpoint's
/// step and by venation's first pass.
void check_resumed_cells(const Start& s, const SceneConfig& cfg, const forms::Scene& scene, int threads);

void adopt_max_steps(Start& s, const RunOptions& o, const SceneConfig& cfg);

/// Refuses --steps N beside a --set of the step limit (run.steps where cells grow, colonisation.max_steps) to
/// another value: --steps would win unsaid, and run.json's overrides would show the --set as in force.
void refuse_two_step_limits(const Start& s, const RunOptions& o, const SceneConfig& cfg);

/// resume --script, once the edited script is read into `cfg`: reads the run's own script again to record
/// its values as the run used them (s.replaced_parameters), warns on `err` of shapes and petioles the
/// edited script changes that will not be placed, and keeps the run's target unless run.steps changed.
void adopt_edited_script(Start& s, const RunOptions& o, const SceneConfig& cfg, std::ostream& err);

/// resume --script: the scene the checkpoint's own script describes (read again, with its --sets), or
/// nothing and the reason in `why` when it no longer loads (a file beside it is gone). Rethrows a Ctrl-C.
std::optional<SceneConfig> load_run_script(const Start& s, const ScriptLimits& limits, std::string& why);

/// resume --script: what `now` (the edited script) places at or before the checkpoint's step (shapes,
/// petioles) that `before` (the run's script) did not, in words; empty when nothing differs. Those are not
/// placed: the checkpoint's cells are kept. For a colonisation checkpoint whose cell sheet is grown, any
/// change to shapes, petioles, cells{} or division{}.
std::string unplaced_changes(const Start& s, const SceneConfig& before, const SceneConfig& now);

/// A line recalling the knobs `sets` gives that `message` (a refused parameter) does not name, or "": a
/// knob's --set reaches the parameters through the script's arithmetic (--set scale=-1 was said only as
/// "initial_length ... got -3200").
std::string knob_recall(const Overrides& sets, const std::string& message);

/// Writes a run.json atomically (text that is not UTF-8, from a script's error say, is replaced).
void write_run_json(const std::filesystem::path& path, const nlohmann::json& run);

/// A path or word as a POSIX shell reads it back: as it is when plain, else in single quotes.
std::string shell_word(const std::string& p);

/// The line that tells how to go on from `checkpoint` with the script corrected after an error: cellform
/// resume with --script, and the --out and --steps of this command that still apply.
std::string resume_hint(const RunOptions& o, const std::filesystem::path& checkpoint,
                        const std::filesystem::path& script);
/// That command alone: "cellform resume CHECKPOINT --script SCRIPT [--out DIR] [--steps N]", EDITED.lua for an
/// empty `script`; with `all`, also this command's --checkpoint-every and every --set.
std::string resume_command(const RunOptions& o, const std::filesystem::path& checkpoint,
                           const std::filesystem::path& script, bool all = false);
/// The run's script file if it still holds the text the checkpoint keeps, else empty (gone, or changed since).
std::filesystem::path script_as_run(const Start& s);
/// After a divergence's resume_hint: a line saying the run's --set values (`sets`) carry over to the resume
/// (a value that made it diverge may be one), and that --set gives another; "" when there are none.
std::string sets_carry_over(const Overrides& sets);

/// run.json's "script": path and hash; after resume --script also what it replaced, and from which step.
nlohmann::json script_record(const Start& s);
/// What a resume changes of a colonisation run's own values, in words (see run_start.cpp).
std::string changed_colonisation_values(const Start& s, const SceneConfig& cfg);
/// " --lua-memory 2048 ..." for the script limits that differ from the defaults ("" if none), which every resume
/// command a run suggests carries: a checkpoint does not keep them.
std::string limit_options(const ScriptLimits& limits);
/// "cellform resume CHECKPOINT" (quoted for a shell) with limit_options(): the command that goes on with a run.
std::string continue_command(const std::filesystem::path& checkpoint, const ScriptLimits& limits);
/// What a resume changes of the source domain (leaf{}, volume{}, surface{}) a colonisation run grew in, in
/// words ("leaf.width = 0.7 (was 0.6)"): --set overrides and, with --script, the edited script's values.
std::string changed_domain_values(const Start& s, const SceneConfig& cfg);

/// The scalar values of `resolved`'s cells, division and venation sections (rule functions left out): what
/// a cell checkpoint keeps, so that a resume steps with the values the run was saved with even when
/// cellform's defaults have changed since.
nlohmann::json physics_of(const nlohmann::json& resolved);

/// `overrides` plus, for every value of `physics` (physics_of, or a part of it) that they do not set, that
/// value as an override text that reads back the same.
Overrides with_physics(const Overrides& overrides, const nlohmann::json& physics);

/// The metadata every checkpoint keeps (start_from reads it back): program, version, script path (absolute),
/// --set overrides, seed, --checkpoint-every, the step limit, the step, and the output folder. Each kind
/// of checkpoint adds its own (mode, initial cells, physics).
nlohmann::json checkpoint_meta(const Start& s, std::uint64_t seed, std::uint64_t target, std::uint64_t step);
/// The checkpoint's "meta" chunk: `meta` as JSON text, bytes of a path that are not UTF-8 replaced by U+FFFD
/// (the outputs go beside the checkpoint; the script's path is kept byte for byte in "script_bytes").
std::string checkpoint_meta_text(const nlohmann::json& meta);

/// `p` made absolute (against the current directory) for a checkpoint, so that resume works from
/// anywhere; `p` itself if the current directory cannot be read.
std::string absolute_path_text(const std::filesystem::path& p);

/// Writes checkpoint bytes atomically (a temporary file, then a rename), after mark_superseded() of its
/// folder; if the checkpoint cannot be written (a full disk), that run.json is put back as it was.
void write_checkpoint(const std::filesystem::path& path, const std::string& bytes);

/// A checkpoint is about to replace the one an earlier run left in `dir`: that run's run.json, which a kill
/// of this run would leave beside the new checkpoint, gets status "superseded" and a note saying so (its
/// outputs list stays, for the cleanup when this run commits). Nothing if there is no cellform run.json
/// or it says so already.
void mark_superseded(const std::filesystem::path& dir);

/// For a resume that runs no step from `dir`'s own checkpoint (`resumed`), whose rewrite marks the folder's
/// run.json superseded: that run.json's text, to put back if the outputs then fail ("" when unreadable);
/// nullopt for any other run.
std::optional<std::string> own_record(const std::filesystem::path& resumed, const std::filesystem::path& dir);

/// The message of an error while writing the outputs, naming the files where they go in `dir`, not in the
/// `staging` folder they are written to first.
std::string output_error(const std::exception& e, const std::filesystem::path& staging,
                         const std::filesystem::path& dir);

/// After a run that has no checkpoint of its own in `dir` (`run`'s "checkpoint" is null: a full disk) replaced
/// the folder's outputs, the checkpoint an earlier run left there no longer goes with them (a resume would
/// continue that run over these outputs): it is removed. The checkpoint this run resumed from (`resumed`), an
/// earlier state of the same run, stays.
void drop_earlier_checkpoint(const std::filesystem::path& dir, const nlohmann::json& run,
                             const std::filesystem::path& resumed);

/// When the periodic checkpoints of a run are due: every `every` steps (0: never), but not within
/// `seconds` of the last one written. A large state written every 1000 steps of a fast run would otherwise
/// cost more than the steps (a full-size poplar: 29 checkpoints of 250 MB). The first one due is always
/// written: a run that fails in its first minute keeps it to go on from.
class CheckpointClock {
 public:
  using Clock = std::chrono::steady_clock;
  /// Every `every` steps (0: none), skipped `seconds` (s) after the last one; and `minutes` (min, 0: never) after
  /// the last one (or this clock's start) at any step, so that a long run between two of `every` is not lost
  /// to a failure.
  CheckpointClock(std::uint64_t every, double seconds, double minutes, Clock::time_point start = Clock::now())
      : every_(every), seconds_(seconds), minutes_(minutes), last_(start) {}
  /// output.checkpoint_every, checkpoint_seconds and checkpoint_minutes, from `start`.
  explicit CheckpointClock(const OutputSpec& o, Clock::time_point start = Clock::now())
      : CheckpointClock(o.checkpoint_every, o.checkpoint_seconds, o.checkpoint_minutes, start) {}
  /// True if a checkpoint is due after `step` at `now`; then counts it as written now.
  bool due(std::uint64_t step, Clock::time_point now = Clock::now()) {
    if (every_ == 0) return false;
    const double since = std::chrono::duration<double>(now - last_).count();  // s
    const bool by_steps = step % every_ == 0 && (!written_ || since >= seconds_);
    if (!by_steps && !(minutes_ > 0 && since >= std::max(60 * minutes_, seconds_))) return false;
    last_ = now;
    written_ = true;
    return true;
  }
  /// When the last checkpoint was due, or this clock's start.
  Clock::time_point last() const { return last_; }

 private:
  std::uint64_t every_;
  double seconds_, minutes_;
  bool written_ = false;    // one was due (and counted as written) already
  Clock::time_point last_;  // of the last one, or the start
};

/// Writes the cell outputs (cells.ply/obj, and the vein graph with `veins`, the run's canalisation) of `c` into
/// `dir`; returns their names. cells.ply has canalisation's attributes with `veins`, also before its first pass.
std::vector<std::string> write_outputs(const std::filesystem::path& dir, const OutputSpec& spec, const cells::Cells& c,
                                       const venation::Params* veins);

/// The output folder is locked by another run: the caller must leave the folder alone (even an empty one
/// it made a moment ago: the other run may be about to write into it).
class FolderBusy : public core::FileError {
 public:
  using core::FileError::FileError;
};

/// print{} found nothing grown to print (no vein, no sheet): other print.* values cannot help, growth can.
class NothingToPrint : public core::InvalidInput {
 public:
  using core::InvalidInput::InvalidInput;
};

/// The output folder holds a run.json a run there would wrongly replace (another program's, or not a file),
/// or cannot be made: an input error, the user's to resolve by choosing another folder.
class FolderRefused : public core::FileError {
 public:
  using core::FileError::FileError;
};

/// An exclusive lock on an output folder (flock on the folder itself: nothing is left in it), held while
/// a run writes there, so that two runs never mix their files in one folder.
class FolderLock {
 public:
  /// Throws core::FileError naming the folder (and the other run's process when known) if it is locked.
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  /// False on a file system without locks (the run goes on unlocked).
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

/// A short fingerprint of a checkpoint file's bytes ("fnv1a64:<hex>").
std::string checkpoint_mark(const std::string& bytes);

/// The name of the file in a staging folder that holds, a line each, the checkpoint_mark of the checkpoints
/// whose frames (up to their step) it holds: the one its run last wrote, and while it writes the next,
/// that one too (mark_staging). A resume of such a checkpoint after a kill knows the folder by it.
inline constexpr const char* kStagingMark = "checkpoint.mark";

/// Creates `dir`, locks it into `lock` and makes a private staging folder inside it, where a run's outputs
/// wait until all are complete. Refuses (core::FileError) a folder whose run.json cellform did not write:
/// a run replaces run.json and deletes the earlier outputs it lists. The staging folders and drafts of
/// killed runs are removed (with the lock held, every other one there; without, those whose process is
/// gone), except the staging folder marked with the checkpoint now in `dir`: its path goes to `kept` (empty
/// when there is none), to be removed once this run has replaced that checkpoint. `checkpoint_mark_out`
/// gets the checkpoint_mark of that checkpoint (empty when `dir` has none).
std::filesystem::path make_staging(const std::filesystem::path& dir, std::optional<FolderLock>& lock,
                                   std::filesystem::path* kept = nullptr, std::string* checkpoint_mark_out = nullptr);
/// Refuses (FolderRefused) a `dir` where a folder takes the place of checkpoint.cfck, run.json or one of the
/// files `names` a run writes there: the run would fail only at its end, after every step, or (the checkpoint)
/// go on unable to be resumed.
void check_output_places(const std::filesystem::path& dir, std::vector<std::string> names);
/// The files a run of `cfg` writes into its output folder at its end (not run.json, the checkpoint or frames).
std::vector<std::string> output_names(const SceneConfig& cfg);
/// Refuses (FolderRefused) a `dir` whose frames/ is a file or a link to nothing: output.every writes there,
/// and the run would fail only at its end.
void check_frames_folder(const std::filesystem::path& dir);

/// Writes `marks` (checkpoint_mark of checkpoints whose frames `staging` holds) into `staging`, replacing
/// what was there. Returns false if it could not.
bool mark_staging(const std::filesystem::path& staging, const std::vector<std::string>& marks);

/// A resume after a kill: the frames (frames/cells_NNNNNN.ply, step <= up_to) the killed run left in its
/// staging folder `from` (make_staging kept it) are linked (or copied) into `staging`. Returns their steps
/// and names, ascending. `from` is left as it is: should this run be killed too before its own checkpoint,
/// the next resume finds them there; the caller removes it once that checkpoint is written.
std::vector<std::pair<std::uint64_t, std::string>> salvage_frames(const std::filesystem::path& from,
                                                                  const std::filesystem::path& staging,
                                                                  std::uint64_t up_to);

/// mm per model unit the print of `segments` and `shell` uses (exporters::print_scale), known before
/// anything is voxelised: veins.svg is drawn at it when the print fails. Throws as print_scale.
double planned_print_scale(const PrintSpec& spec, const std::vector<exporters::Segment>& segments,
                           const std::vector<std::array<core::Vec3, 3>>& shell);

/// Thickens vein segments (model units, Murray radii) and shell triangles into a printable solid and
/// writes the requested formats into `dir`. Appends the file names to `names`; returns what run.json
/// records. Throws on failure (core::Cancelled on Ctrl-C).
/// `close_holes`: model units, the radius of the shell's closing (exporters::ThickenParams::close_holes).
/// `sheet`: there is a cell sheet print.shell could add (a form apart is then told it can join through it).
nlohmann::json thicken_and_write(const std::filesystem::path& dir, const PrintSpec& spec,
                                 const std::vector<exporters::Segment>& segments,
                                 const std::vector<std::array<core::Vec3, 3>>& shell, int threads,
                                 std::vector<std::string>& names, std::ostream& err, bool quiet, double close_holes = 0,
                                 bool sheet = false);

/// Draws the leaf's veins.svg into `staging` (adding it to `outputs`; a large file is noted on `err`) at
/// output.svg_size, or else at the print's scale (`printed`'s, or, if the print failed, the scale planned
/// for `segments` and `shell`), or else 200 mm. Returns run.json's "svg": the page's scale and size in mm.
nlohmann::json draw_veins_svg(const std::filesystem::path& staging, const OutputSpec& output, const PrintSpec* print,
                              const nlohmann::json& printed, const std::vector<exporters::Segment>& segments,
                              const std::vector<std::array<core::Vec3, 3>>& shell, const venation::VeinTree& tree,
                              const venation::Outline& outline, std::vector<std::string>& outputs, std::ostream& err);

/// The segments a colonisation run prints: every tree edge with the radii of its two nodes (a side branch, of
/// another order than its parent's, with its own radius at both ends), then each loop's
/// closing edge at the radius of the finer vein it joins, at both ends (it carries no flow of its own; veins.svg
/// and veins.png draw it so too). Model units.
std::vector<exporters::Segment> vein_segments(const venation::VeinTree& tree);

/// The notes of a colonisation run that stalled, `sources_left` out of every vein's reach: on a surface, why
/// a vein may not cross to them; in a leaf (`outline`: the grown blade), how many lie outside it, and why.
void say_sources_left(std::ostream& err, const ColonisationSpec& spec, const std::vector<core::Vec3>& sources_left,
                      const venation::Outline* outline);

/// A veins.svg of at least this many bytes is said to be large.
constexpr std::uintmax_t kLargeSvgBytes = 50'000'000;
/// The note on a veins.svg of `bytes` (file_size's -1: unknown), or "" under kLargeSvgBytes; `joined`: drawn
/// a path per vein already (output.svg_paths = "veins").
std::string large_svg_note(std::uintmax_t bytes, bool joined);

/// Wall-clock seconds from `start` to now.
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Writes a periodic checkpoint with `write`, adding the seconds it took to `seconds` (run.json's
/// timings.checkpoints_s). A failure (a full disk) is reported on `err` the first time (`warned`) and the run
/// goes on, to try again at the next one; returns whether it was written.
bool periodic_checkpoint(const std::function<void()>& write, std::ostream& err, bool& warned, double& seconds);

/// run.json's checkpoint fields: "checkpoint" names the file a resume starts from, or is null when there
/// is none; when the final checkpoint failed, "checkpoint_error" says why and, if an earlier (periodic)
/// checkpoint of this run is in the folder, "checkpoint" still names it and "checkpoint_step" gives its
/// step (absent for one taken while a colonisation's cell sheet grew).
void record_checkpoint(nlohmann::json& run, const std::string& error, bool earlier_saved,
                       std::optional<std::uint64_t> earlier_step);

/// The line a finished print says: "printable solid: T triangles, P part(s), C closed cavities, scale ...".
void say_printed(std::ostream& err, const nlohmann::json& printed);

/// Says that the print failed with `message` (then `after`, if any, in brackets) and, with `retry` (a checkpoint of
/// the run is written and the failure was not that nothing grew), how to print it again with other values.
void say_print_failed(std::ostream& err, const std::string& message, const std::string& after, bool retry,
                      const std::filesystem::path& checkpoint, const ScriptLimits& limits = {});

/// print{} for a cell run: the vein graph and, if asked, the cell sheet (print.cpp).
nlohmann::json write_printable(const std::filesystem::path& dir, const PrintSpec& spec, const cells::Cells& cells,
                               bool has_veins, int threads, std::vector<std::string>& names, std::ostream& err,
                               bool quiet);

/// The radius of the shell's closing for print.close_holes (cell spacings) on this sheet: half that many
/// median link lengths, model units (0 without links).
double shell_closing(const cells::Cells& cells, double close_holes);

/// The median length of the cells' links, model units (0 without links): the sheet's cell spacing.
double median_link_length(const cells::Cells& cells);

/// The highest of `dir` and its parents that does not exist yet (absolute), or empty when `dir` exists.
std::filesystem::path first_missing(const std::filesystem::path& dir);

/// `--out` as a folder to create: each ".." that follows a folder that does not exist drops that folder
/// ("new/../z" is "z": creating it would make a "new" that nothing uses); other parts stay as given.
std::filesystem::path out_folder(const std::filesystem::path& dir);

/// Removes `dir` and then its parents, up to and including `top`, while they are empty folders; nothing
/// when `top` is empty.
void remove_empty_up_to(const std::filesystem::path& dir, const std::filesystem::path& top);

/// Says on `err` why the outputs cannot be written to `dir` (`e`, thrown while preparing the folder) and gives
/// the exit code: FolderBusy leaves the folder alone (another run's now: failure); FolderRefused (usage) and
/// any other error (failure) remove the folders `--out` made on its way (`created`, as remove_empty_up_to).
int refuse_outputs(const std::exception_ptr& e, const std::filesystem::path& dir, const std::filesystem::path& created,
                   std::ostream& err);

/// For a run that could write no checkpoint of its own (a full disk): when `dir` holds another run's
/// checkpoint.cfck (not `resumed`, which a commit keeps), says so after `checkpoint_error` on `err`, removes
/// `staging` (this run's outputs are dropped) and the folders `--out` made (`created`) and returns true:
/// committing would delete that run's checkpoint with its outputs, and leave neither run to resume. False,
/// doing nothing, otherwise.
bool keep_other_run(const std::filesystem::path& dir, const std::filesystem::path& resumed,
                    const std::string& checkpoint_error, const std::filesystem::path& staging,
                    const std::filesystem::path& created, std::ostream& err);

/// Moves every file of `staging` (recursively) into `dir`, then removes the outputs of an earlier run
/// (listed in its run.json) that this run did not write again and `keep` does not name. The old run.json
/// is removed before the first move and the new one moved last, so a folder left between two runs' files
/// (a kill, a failed move) has no run.json; meanwhile kOutputsManifest lists both runs' outputs, and a
/// commit into a folder without run.json cleans up after those it lists.
inline constexpr const char* kOutputsManifest = ".cellform-outputs";
void commit_outputs(const std::filesystem::path& staging, const std::filesystem::path& dir,
                    const std::vector<std::string>& names, const std::vector<std::string>& keep = {});

/// The frames (frames/cells_NNNNNN.ply) of step <= up_to that dir's run.json lists and that exist, if that
/// run.json is of the same script (hash "fnv1a64:..."), seed and overrides (output.* and print.* aside):
/// on resume, the frames the run wrote before its checkpoint, and never another run's.
std::vector<std::string> earlier_frames(const std::filesystem::path& dir, std::uint64_t up_to,
                                        const std::string& script_hash, std::uint64_t seed, const Overrides& overrides);

/// A space-colonisation run (run_colonisation.cpp); returns the exit code. Never throws.
int run_colonisation(const RunOptions& o, Start& s, SceneConfig& cfg, ScriptHost& host, std::uint64_t seed,
                     std::ostream& out, std::ostream& err, std::chrono::steady_clock::time_point t0);

}  // namespace cellform::app
