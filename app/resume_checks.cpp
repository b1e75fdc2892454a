// What a resume must still agree with, or take over, from the run it continues: the step limits, the obstacle
// mesh files it grew against, and (with an edited script) obstacles that hold none of its cells and a sink for
// venation added; and the commands a message gives to resume.
#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "app/run_internal.h"
#include "app/schema.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "forms/obstacles.h"

namespace cellform::app {

namespace fs = std::filesystem;

/// `p` as a shell word: quoted when it holds anything but letters, digits and -_./+,:@%=
std::string shell_word(const std::string& p) {
  if (!p.empty() && p.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./+,:@%=") ==
                        std::string::npos)
    return p;
  std::string q = "'";
  for (const char c : p) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string resume_hint(const RunOptions& o, const fs::path& checkpoint, const fs::path& script) {
  return "  to go on from it with the script corrected: " + resume_command(o, checkpoint, script);
}

std::string resume_command(const RunOptions& o, const fs::path& checkpoint, const fs::path& script, bool all) {
  std::string hint = "cellform resume " + shell_word(checkpoint.string()) + " --script " +
                     (script.empty() ? std::string("EDITED.lua") : shell_word(absolute_path_text(script)));
  // a new checkpoint is in this command's folder, where a resume writes anyway; the one resumed may not be
  if (o.out && checkpoint == o.checkpoint) hint += " --out " + shell_word(o.out->string());
  if (o.steps) hint += " --steps " + std::to_string(*o.steps);
  if (all && o.checkpoint_every) hint += " --checkpoint-every " + std::to_string(*o.checkpoint_every);
  if (all)
    for (const auto& [k, v] : o.sets) hint += " --set " + shell_word(k + "=" + v);
  return hint + limit_options(o.limits);
}

std::string continue_command(const fs::path& checkpoint, const ScriptLimits& limits) {
  return "cellform resume " + shell_word(checkpoint.string()) + limit_options(limits);
}

std::string limit_options(const ScriptLimits& limits) {
  // the script's limits are not kept in the checkpoint: a resume needs them given again
  const ScriptLimits defaults;
  std::string given;
  if (limits.instructions != defaults.instructions)
    given += " --lua-instructions " + std::to_string(limits.instructions);
  if (limits.memory_bytes != defaults.memory_bytes)
    given += " --lua-memory " + std::to_string(limits.memory_bytes >> 20);
  if (limits.library_seconds != defaults.library_seconds)
    given += " --lua-seconds " + std::to_string(static_cast<std::uint64_t>(limits.library_seconds));
  return given;
}

fs::path script_as_run(const Start& s) {
  std::ifstream in(s.script_path, std::ios::binary);
  const std::string text(std::istreambuf_iterator<char>(in), {});
  return in && text == s.source ? s.script_path : fs::path();
}

std::string sets_carry_over(const Overrides& sets) {
  std::string listed;
  for (const auto& [k, v] : sets) listed += (listed.empty() ? "" : ", ") + k + "=" + v;
  return listed.empty()
             ? listed
             : "  (the run's --set values carry over: " + listed + "; with --script, --set NAME=VALUE gives another)\n";
}

void adopt_mesh_files(Start& s, const RunOptions& o, const SceneConfig& cfg, std::ostream& err) {
  std::vector<std::string> meshes, geometry;
  for (const auto& [path, hash] : cfg.mesh_files) meshes.push_back(hash);
  for (const forms::TriangleMesh& m : cfg.scene.obstacles.meshes) {
    const std::uint64_t h = core::fnv1a64(m.vertices.data(), m.vertices.size() * sizeof(core::Vec3));
    geometry.push_back("fnv1a64:" +
                       core::hex64(core::fnv1a64(m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]), h)));
  }
  // the walls as the run uses them, scaled and moved: a file scaled otherwise is another wall, one written again
  // the same is not (its cells grew links across their own walls' corners: those are not tested again)
  s.new_meshes.clear();
  for (std::size_t k = 0; s.obstacle_geometry && k < geometry.size(); ++k)
    if (std::find(s.obstacle_geometry->begin(), s.obstacle_geometry->end(), geometry[k]) == s.obstacle_geometry->end())
      s.new_meshes.push_back(k);
  std::vector<std::size_t> new_files;  // files the checkpoint did not grow against
  for (std::size_t k = 0; k < meshes.size(); ++k)
    if (!s.obstacle_meshes ||
        std::find(s.obstacle_meshes->begin(), s.obstacle_meshes->end(), meshes[k]) == s.obstacle_meshes->end())
      new_files.push_back(k);
  // a checkpoint that kept its files' fingerprints but not the walls' (the release before): the new files
  if (!s.obstacle_geometry && s.obstacle_meshes) s.new_meshes = new_files;
  s.obstacle_geometry = geometry;
  if (s.resume && (!cfg.colonisation || s.sheet_partial) && s.obstacle_meshes && *s.obstacle_meshes != meshes) {
    if (!s.script_replaced) {  // the same script names the same files, in the same order: those that differ changed
      std::string changed;
      for (std::size_t k = 0; k < meshes.size(); ++k)
        if (k >= s.obstacle_meshes->size() || (*s.obstacle_meshes)[k] != meshes[k])
          changed += (changed.empty() ? "'" : ", '") + cfg.mesh_files[k].first.string() + "'";
      throw InputError("checkpoint '" + o.checkpoint.string() +
                       "' grew against other mesh{} obstacles: " + (changed.empty() ? std::string("a file") : changed) +
                       " changed since it was saved; put back the file it was grown with, or start a new run "
                       "(resume --script with an edited script takes the files as they are now)");
    }
    // an edited script may name other files, in another order: a file is told by its content alone
    std::string added;
    for (const std::size_t k : new_files)
      added += (added.empty() ? "'" : ", '") + cfg.mesh_files[k].first.string() + "'";
    const auto gone = std::count_if(s.obstacle_meshes->begin(), s.obstacle_meshes->end(), [&](const std::string& h) {
      return std::find(meshes.begin(), meshes.end(), h) == meshes.end();
    });
    std::string what;
    if (!added.empty()) what = added + (new_files.size() == 1 ? " is" : " are") + " not among them";
    if (gone > 0)
      what += (what.empty() ? "" : "; ") + std::to_string(gone) + " of the " +
              std::to_string(s.obstacle_meshes->size()) + (gone == 1 ? " it grew against is" : " it grew against are") +
              " gone";
    if (what.empty()) what = "the same files, in another order or repeated";
    err << "cellform: note: the mesh{} obstacles differ from those the checkpoint grew against (" << what
        << "); the run goes on against them as they are now\n";
  }
  s.obstacle_meshes = meshes;
}

void refuse_two_step_limits(const Start& s, const RunOptions& o, const SceneConfig& cfg) {
  // run.steps counts the cells' steps: of a new run, or of a resume --script that grows cells (a plain resume
  // refuses a changed run.steps itself, and a grown sheet's run.steps does nothing)
  const bool cells_steps = !s.resume || (s.script_replaced && (s.colonisation_bytes.empty() || s.sheet_partial));
  for (const std::string name : {"run.steps", "colonisation.max_steps"}) {
    const auto set = o.sets.find(name);
    if (!o.steps || set == o.sets.end() || (name == "run.steps" ? !cells_steps : !cfg.colonisation)) continue;
    double x = 0;
    if (parse_double(set->second, x) && x != static_cast<double>(*o.steps))
      throw InputError("--steps " + std::to_string(*o.steps) + " and --set " + name + "=" + set->second +
                       " both give the step limit; give one of them");
  }
}

void adopt_max_steps(Start& s, const RunOptions& o, const SceneConfig& cfg) {
  if (!s.max_steps_changed || o.steps || !cfg.colonisation) return;  // --steps wins
  const std::uint64_t limit = cfg.colonisation->params.max_steps;
  if (limit < s.step)
    throw InputError("colonisation.max_steps = " + std::to_string(limit) + " is below the checkpoint's step " +
                     std::to_string(s.step) + "; give " + std::to_string(s.step) + " or more");
  s.target_steps = limit;
  s.has_target = true;
}

void check_resumed_cells(const Start& s, const SceneConfig& cfg, const forms::Scene& scene, int threads) {
  if (!s.resume || !s.script_replaced) return;  // the run's own script: its cells are as it left them
  const cells::Cells& cells = scene.simulation().cells();
  try {
    forms::check_outside(cfg.scene.obstacles, cells.position, cfg.scene.obstacle_names, threads, &scene.obstacles());
  } catch (const core::InvalidInput& e) {
    throw core::InvalidInput(std::string(e.what()) + "; " + s.script_path.string() +
                             " places it over the cells of the checkpoint's step " + std::to_string(s.step) +
                             ", which it would throw to its far side: move it off them, or start a new run");
  }
  // a mesh{} not among those the checkpoint grew against, cut through its cells (its own grew with them)
  if (!s.new_meshes.empty()) {
    forms::Obstacles added;
    forms::ObstacleNames names;
    for (const std::size_t k : s.new_meshes) {
      added.meshes.push_back(cfg.scene.obstacles.meshes[k]);
      if (k < cfg.scene.obstacle_names.meshes.size()) names.meshes.push_back(cfg.scene.obstacle_names.meshes[k]);
    }
    try {
      forms::check_links_clear(forms::PreparedObstacles(std::move(added)), cells, names, threads);
    } catch (const core::InvalidInput& e) {
      throw core::InvalidInput(std::string(e.what()) + "; " + s.script_path.string() +
                               " places it across the cells of the checkpoint's step " + std::to_string(s.step) +
                               ": move it clear of them, or start a new run");
    }
  }
  // venation{} added by the edited script: its sink must be a cell by its first pass
  if (!cfg.scene.venation || std::count(cells.type.begin(), cells.type.end(), cells::CellType::petiole) > 0) return;
  const std::uint64_t every = std::max<std::uint64_t>(cfg.scene.venation->every, 1);
  const std::uint64_t pass = (s.step / every + 1) * every;  // placed at a step, a petiole is there for its pass
  for (const forms::PetioleSpec& p : cfg.scene.petioles)
    if (p.step > s.step && p.step <= pass) return;
  const std::string next = std::to_string(s.step + 1), at = std::to_string(s.step);
  std::string m = cfg.scene.venation_origin;  // (appended: GCC 12 warns falsely of "literal" + a temporary)
  m += "venation needs a petiole cell by its first pass (step ";
  m += std::to_string(pass) + "), and the checkpoint's cells (step " + at + ") have none; ";
  m += cfg.scene.petioles.empty()
           ? "add petiole{at = {x, y, z}, step = " + next + "}"
           : "a resume does not place a petiole{} due by step " + at + ": give it step = " + next;
  throw core::InvalidInput(m);
}

}  // namespace cellform::app
