// Where a run starts from: its script, or a checkpoint to resume (with the script it keeps, or an edited
// one given by --script); and the run.json and checkpoint pieces that depend on it.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>

#include "app/run_internal.h"
#include "app/schema.h"
#include "core/atomic_file.h"
#include "core/chunk_file.h"
#include "core/errors.h"

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
/// A vector such as cells.drag, as physics_of records it and --set reads it back (x,y,z).
bool is_vector(const json& v) {
  return v.is_array() && v.size() == 3 && std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); });
}
}  // namespace

json physics_of(const json& resolved) {
  json out = json::object();
  const auto scalar = [](const json& v) { return v.is_primitive() && !v.is_null() && v != "<function>"; };
  for (const char* section : {"cells", "division", "venation"}) {
    if (!resolved.contains(section) || !resolved[section].is_object()) continue;
    for (const auto& [k, v] : resolved[section].items()) {
      if (scalar(v) || is_vector(v))
        out[section][k] = v;   // a value, or a vector such as cells.drag
      else if (v.is_object())  // the weights of a cell type: cells.vein.cohesion
        for (const auto& [k2, v2] : v.items())
          if (scalar(v2)) out[section][k + "." + k2] = v2;
    }
  }
  return out;
}

Overrides with_physics(const Overrides& overrides, const json& physics) {
  Overrides out = overrides;
  if (!physics.is_object()) return out;
  for (const auto& [section, values] : physics.items())
    for (const auto& [k, v] : values.items()) {
      const std::string key = section + "." + k;
      if (out.count(key)) continue;
      const auto number = [](const json& x) {
        if (x.is_number_integer()) return x.dump();
        char buf[32];  // the shortest text that reads back as the same double
        const auto r = std::to_chars(buf, buf + sizeof buf, x.get<double>());
        return std::string(buf, r.ptr);
      };
      std::string text;
      if (v.is_boolean()) {
        text = v.get<bool>() ? "true" : "false";
      } else if (v.is_string()) {
        text = v.get<std::string>();
      } else if (v.is_array()) {  // x,y,z, as --set takes a vector
        for (const json& x : v) {
          if (!text.empty()) text += ',';
          text += number(x);
        }
      } else {
        text = number(v);
      }
      out[key] = text;
    }
  return out;
}

std::string checkpoint_mark(const std::string& bytes) {
  return "fnv1a64:" + core::hex64(core::fnv1a64(bytes.data(), bytes.size()));
}

std::string script_hash(const std::string& source) {
  return "fnv1a64:" + core::hex64(core::fnv1a64(source.data(), source.size()));
}

void write_run_json(const fs::path& path, const json& run) {
  core::write_file_atomically(
      path, [&](std::ostream& os) { os << run.dump(2, ' ', false, json::error_handler_t::replace) << "\n"; });
}

json script_record(const Start& s) {
  json r = {{"path", absolute_path_text(s.script_path)}, {"hash", script_hash(s.source)}};  // wherever run from
  if (!s.replaced.empty()) r["replaces"] = s.replaced;
  return r;
}

json checkpoint_meta(const Start& s, std::uint64_t seed, std::uint64_t target, std::uint64_t step) {
  json meta = {{"program", "cellform"},
               {"version", version()},
               {"script", absolute_path_text(s.script_path)},
               {"overrides", s.sets},
               {"seed", seed},
               {"checkpoint_every", s.checkpoint_every ? json(*s.checkpoint_every) : json(nullptr)},
               {"target_steps", target},
               {"step", step},
               {"out", absolute_path_text(s.out_dir)},
               {"replaced_scripts", s.replaced}};
  if (s.obstacle_meshes) meta["obstacle_meshes"] = *s.obstacle_meshes;
  if (s.obstacle_geometry) meta["obstacle_geometry"] = *s.obstacle_geometry;
  // a script path that is not UTF-8 (which JSON holds with U+FFFD) also as its bytes: a resume finds the
  // script's files (a mesh, an outline) beside it
  const std::string path = absolute_path_text(s.script_path);
  if (!core::is_utf8(path)) meta["script_bytes"] = std::vector<std::uint8_t>(path.begin(), path.end());
  return meta;
}

std::string checkpoint_meta_text(const json& meta) { return meta.dump(-1, ' ', false, json::error_handler_t::replace); }

std::string absolute_path_text(const fs::path& p) {
  std::error_code ec;
  const fs::path a = fs::absolute(p, ec);
  return ec ? p.string() : a.lexically_normal().string();
}

Start start_from(const RunOptions& o) {
  Start s;
  try {
    if (!o.checkpoint.empty()) {
      const std::string what = "checkpoint '" + o.checkpoint.string() + "'";
      std::error_code ec;
      if (fs::is_directory(o.checkpoint, ec)) {
        // a folder named checkpoint.cfck (given, or inside the folder given) is no checkpoint file
        fs::path given = o.checkpoint.lexically_normal();  // "x/checkpoint.cfck/", as a shell completes it
        if (given.filename().empty()) given = given.parent_path();
        const fs::path named = given.filename() == "checkpoint.cfck" ? given : given / "checkpoint.cfck";
        if (fs::is_directory(named, ec))
          throw core::FileError("checkpoint '" + named.string() +
                                "' is a folder, not a checkpoint file (a run writes checkpoint.cfck as a file; move "
                                "that folder away)");
        std::string busy;  // a run still writing there has not written its checkpoint yet: said
        try {
          const FolderLock probe(o.checkpoint);
        } catch (const FolderBusy& e) {
          busy = std::string("; ") + e.what();
        } catch (const core::FileError&) {  // not readable: the message below says enough
        }
        throw core::FileError(what +
                              " is a folder with no checkpoint.cfck in it (a run writes one into its output "
                              "folder when it ends, is stopped or fails)" +
                              busy);
      }
      if (o.checkpoint.extension() == ".lua")  // a script given to resume: say how to run it
        throw core::FileError(what + " is a script, not a checkpoint: run it with cellform run " +
                              o.checkpoint.string() + ", or resume its run's checkpoint.cfck");
      const std::string bytes = core::read_file(o.checkpoint);
      s.checkpoint_mark = checkpoint_mark(bytes);
      const core::ChunkFile f = core::read_chunk_file(bytes, kCheckpointKind, kCheckpointVersion, what);
      json meta;
      try {
        meta = json::parse(f.at("meta", what));
        s.script_path = meta.at("script").get<std::string>();
        if (meta.contains("script_bytes")) {  // the path's bytes, where they are not UTF-8
          const auto raw = meta["script_bytes"].get<std::vector<std::uint8_t>>();
          s.script_path = std::string(raw.begin(), raw.end());
        }
        s.sets = meta.at("overrides").get<Overrides>();
        // --set took a boolean field as 1 or 0 before December 2026: the checkpoint's own such texts still read
        for (const auto& [key, text] : s.sets)
          if (text == "1" || text == "0") s.digit_booleans.insert(key);
        s.checkpoint_digit_booleans = s.digit_booleans;
        // counts must be whole numbers >= 0 (a negative one would wrap round to a huge step)
        for (const char* key : {"seed", "target_steps", "step"})
          if (!meta.at(key).is_number_unsigned())
            throw core::FileError(what + " is corrupt (metadata '" + key + "' is not a whole number >= 0)");
        s.seed = meta.at("seed").get<std::uint64_t>();
        s.target_steps = meta.at("target_steps").get<std::uint64_t>();
        s.step = meta.at("step").get<std::uint64_t>();
        for (const char* key : {"target_steps", "step"})  // no run goes further (run.steps, --steps, max_steps)
          if (meta.at(key).get<std::uint64_t>() > 1000000000)
            throw core::FileError(what + " is corrupt (metadata '" + key +
                                  "' is over 1e9, the most steps a run takes)");
        s.replaced = meta.value("replaced_scripts", json::array());  // older checkpoints: none
        if (s.replaced.is_null()) s.replaced = json::array();
        bool listed = s.replaced.is_array();
        for (const json& r : listed ? s.replaced : json::array())
          listed = listed && r.is_object() && r.value("path", json()).is_string() &&
                   r.value("hash", json()).is_string() && r.value("until_step", json()).is_number_unsigned();
        if (!listed) throw core::FileError(what + " is corrupt (metadata 'replaced_scripts')");
        s.out_dir = meta.at("out").get<std::string>();
        if (meta.contains("initial_cells") && !meta["initial_cells"].is_number_unsigned())
          throw core::FileError(what + " is corrupt (metadata 'initial_cells' is not a whole number >= 0)");
        s.initial_cells = meta.value("initial_cells", std::size_t{0});  // older checkpoints: unknown
        if (meta.contains("sheet_steps") && meta["sheet_steps"].is_number_unsigned())
          s.sheet_steps = meta["sheet_steps"].get<std::uint64_t>();
        s.physics = meta.value("physics", json());  // older checkpoints: not recorded
        // sections of values as physics_of makes them (they are read back as --set texts)
        bool physics_ok = s.physics.is_null() || s.physics.is_object();
        if (s.physics.is_object())
          for (const auto& [section, values] : s.physics.items()) {
            physics_ok = physics_ok && values.is_object();
            if (values.is_object())
              for (const auto& [k, v] : values.items())
                physics_ok = physics_ok && (v.is_number() || v.is_boolean() || v.is_string() || is_vector(v));
          }
        if (!physics_ok)
          throw core::FileError(
              what + " is corrupt (metadata 'physics' holds a value that is no number, boolean, text or {x, y, z})");
        if (meta.contains("veins") && !meta["veins"].is_object())
          throw core::FileError(what + " is corrupt (metadata 'veins')");
        // lists of "fnv1a64:<hex>" (older checkpoints recorded neither, or only the first)
        for (const auto& [key, out] :
             {std::pair{"obstacle_meshes", &s.obstacle_meshes}, std::pair{"obstacle_geometry", &s.obstacle_geometry}}) {
          if (!meta.contains(key)) continue;
          bool hashes = meta[key].is_array();
          if (hashes)
            for (const json& h : meta[key]) hashes = hashes && h.is_string();
          if (!hashes) throw core::FileError(what + " is corrupt (metadata '" + key + "')");
          *out = meta[key].get<std::vector<std::string>>();
        }
        const std::string mode = meta.value("mode", std::string("cells"));
        if (mode != "cells" && mode != "colonisation" && mode != "sheet")
          throw core::FileError(what + " is corrupt (unknown run mode '" + mode.substr(0, 40) + "')");
        s.sheet_partial = mode == "sheet";  // surface{cells = true} stopped while its cells grew
        // a sheet checkpoint's target is the step limit its run was given (--steps), if any
        s.has_target = !s.sheet_partial || meta.value("steps_given", false);
        if (mode == "colonisation") {
          s.colonisation_bytes = f.at("colonisation", what);
          if (s.colonisation_bytes.empty()) throw core::FileError(what + " is corrupt (empty colonisation state)");
        }
      } catch (const json::exception&) {
        throw core::FileError(what + " is corrupt (bad metadata)");
      }
      s.source = f.at("script", what);
      if (s.colonisation_bytes.empty() || f.chunks.count("cells")) s.cells_bytes = f.at("cells", what);
      s.resume = true;
      s.checkpoint_source = s.source;
      s.checkpoint_script_hash = script_hash(s.source);
      s.checkpoint_sets = s.sets;
      if (o.replace_script) {  // resume --script: the state goes on under an edited script
        if (o.replace_script->extension() == ".cfck")
          throw InputError("--script " + o.replace_script->string() +
                           " is a checkpoint; give the edited growth script (a .lua file)");
        std::string edited;
        try {
          edited = core::read_file(*o.replace_script);
        } catch (const core::FileError& e) {
          throw InputError(std::string("--script: ") + e.what());
        }
        // the script the checkpoint keeps is a plain resume, unless a --set changes what a plain resume keeps:
        // then the same text is the "edited" script (the way to change a value the run's own --set gave)
        // (a space-colonisation checkpoint keeps no cell values: its --set goes as in a plain resume)
        const bool cell_values_kept = s.colonisation_bytes.empty() || s.sheet_partial;
        const bool changes_kept =
            cell_values_kept && std::any_of(o.sets.begin(), o.sets.end(), [&](const auto& kv) {
              const std::string section = kv.first.substr(0, kv.first.find('.'));
              const auto saved = s.sets.find(kv.first);
              return section != "output" && section != "print" && (saved == s.sets.end() || saved->second != kv.second);
            });
        if (edited == s.source && !changes_kept) {
          s.script_unchanged = true;
        } else {
          s.source = edited;
          s.replaced_path = s.script_path.string();
          s.script_path = *o.replace_script;
          s.script_replaced = true;
        }
      }
      // refused before anything is written: the checkpoint keeps its run's target and seed
      if (o.steps && *o.steps < s.step)
        throw InputError(what + " is at step " + std::to_string(s.step) + "; --steps " + std::to_string(*o.steps) +
                         " would go back (give a total of at least " + std::to_string(s.step) + ")");
      if (o.seed && *o.seed != *s.seed)
        throw InputError("--seed " + std::to_string(*o.seed) + ": a resumed run keeps the seed of " + what + " (" +
                         std::to_string(*s.seed) + "); start a new run to use another seed");
      // a cell run resumed with --script: the edited script's run.steps if it changed it (see run_command)
      if (s.script_replaced && s.colonisation_bytes.empty() && !s.sheet_partial) s.has_target = false;
      s.checkpoint_target = s.target_steps;  // the run's own, before this resume's --steps
      if (o.steps) {
        s.target_steps = *o.steps;
        s.has_target = true;
      }
      // the outputs go beside the checkpoint (its run's folder, wherever that is now), not to the folder
      // it was written in: that one may since hold another run
      s.out_dir = o.out                            ? out_folder(*o.out)
                  : o.checkpoint.has_parent_path() ? o.checkpoint.parent_path()
                                                   : fs::path(".");
      if (meta.contains("veins")) s.vein_summary = meta["veins"];
      if (meta.contains("checkpoint_every") && meta["checkpoint_every"].is_number_unsigned())
        s.checkpoint_every = meta["checkpoint_every"].get<std::uint64_t>();
      s.checkpoint_every_of_run = s.checkpoint_every;
      if (o.checkpoint_every) s.checkpoint_every = o.checkpoint_every;
      for (const auto& [k, v] : o.sets) {
        // a cell run continues bit-identically only with the physics it was saved with; what it writes may
        // change (space colonisation checks its own parameters when its state is read)
        const auto saved_value = s.sets.find(k);
        const std::string section = k.find('.') == std::string::npos ? std::string() : k.substr(0, k.find('.'));
        if ((s.colonisation_bytes.empty() || s.sheet_partial) && !s.script_replaced && section != "output" &&
            section != "print" && (saved_value == s.sets.end() || saved_value->second != v)) {
          if (k == "run.steps") {  // the one value a resume takes by an option of its own, as a whole number
            double x = 0;
            const auto [end, bad] = std::from_chars(v.data(), v.data() + v.size(), x);
            const bool whole =
                bad == std::errc() && end == v.data() + v.size() && x >= 0 && x <= 1e9 && x == std::floor(x);
            throw InputError("--set run.steps=" + v + ": a resume is given its total of steps by --steps " +
                             (whole ? std::to_string(static_cast<long long>(x)) : std::string("N (a whole number)")));
          }
          // the command that does it: --script with the run's own script takes any --set (an edited copy too)
          const std::string command = resume_command(o, o.checkpoint, script_as_run(s), true);
          throw InputError("--set " + k + "=" + v + ": " + what +
                           " continues with the parameters it was saved with (only output.* and print.* may change "
                           "when resuming a cell run, or a run stopped while its cell sheet grew); to change " +
                           k + ", give it a script, the run's own or an edited copy: " + command +
                           " (or start a new run)");  // (with --script, the same text and a change is "edited")
        }
        if (k == "colonisation.max_steps" && !s.colonisation_bytes.empty() && !s.sheet_partial &&
            (saved_value == s.sets.end() || saved_value->second != v))
          s.max_steps_changed = true;
        // given now, and otherwise than saved: as --set takes it now (restating the saved 1 keeps it)
        if (saved_value == s.sets.end() || saved_value->second != v) s.digit_booleans.erase(k);
        s.sets[k] = v;
      }
      return s;
    }
    s.script_path = o.script;
    s.source = core::read_file(o.script);
  } catch (const core::FileError& e) {
    throw InputError(e.what());
  }
  s.sets = o.sets;
  s.seed = o.seed;
  s.checkpoint_every = o.checkpoint_every;
  if (o.steps) {
    s.target_steps = *o.steps;
    s.has_target = true;
  }
  // out/<script name>; a script named "..lua" or "...lua" would write into out/ itself or the working folder
  const fs::path stem = o.script.stem();
  s.out_dir = o.out ? out_folder(*o.out)
                    : fs::path("out") / (stem.empty() || stem == "." || stem == ".." ? fs::path("script") : stem);
  return s;
}

void record_replaced_script(Start& s, const RunOptions& o, const fs::path& dir) {
  json entry = {{"path", s.replaced_path}, {"hash", s.checkpoint_script_hash}, {"until_step", s.step}};
  if (!s.replaced_parameters.is_null()) entry["parameters"] = s.replaced_parameters;
  s.replaced.push_back(entry);
  std::error_code ec;
  s.copy_before_replacing = fs::equivalent(o.checkpoint, dir / kCheckpointName, ec);  // else elsewhere
}

void plan_keeping_folder_checkpoint(Start& s, const RunOptions& o, const fs::path& dir) {
  std::error_code ec;
  const fs::path own = dir / kCheckpointName;
  if (!s.resume || s.copy_before_replacing || !fs::is_regular_file(own, ec) || fs::equivalent(o.checkpoint, own, ec))
    return;
  s.copy_before_replacing = s.copy_is_folders = true;
}

void keep_resumed_checkpoint(Start& s, const fs::path& dir, std::ostream& err) {
  if (!s.copy_before_replacing) return;
  std::string step = std::to_string(s.step);  // of the checkpoint copied: the folder's own is read for it
  if (s.copy_is_folders) try {
      const fs::path own = dir / kCheckpointName;
      const core::ChunkFile f =
          core::read_chunk_file(core::read_file(own), kCheckpointKind, kCheckpointVersion, own.string());
      step = std::to_string(json::parse(f.chunks.at("meta")).at("step").get<std::uint64_t>());
    } catch (const std::exception&) {  // copied all the same, under a name that says so
      step.clear();
    }
  const std::string stem = step.empty() ? std::string("checkpoint-unknown-step") : "checkpoint-step" + step;
  std::error_code ec;
  std::string name;
  for (int k = 1; name.empty(); ++k) {  // the first free name: an older copy may be another run's
    const std::string candidate = stem + (k == 1 ? std::string() : "-" + std::to_string(k)) + ".cfck";
    if (!fs::exists(dir / candidate, ec) && !fs::is_symlink(dir / candidate, ec)) name = candidate;
  }
  const fs::path part = dir / (name + ".partial");  // then renamed: a kill leaves no half copy under the name
  if (!fs::copy_file(dir / kCheckpointName, part, fs::copy_options::overwrite_existing, ec) ||
      (fs::rename(part, dir / name, ec), ec)) {
    fs::remove(part, ec);
    throw core::FileError(std::string("cannot keep a copy of ") +
                          (s.copy_is_folders ? "the folder's own checkpoint" : "the checkpoint resumed") + " as '" +
                          (dir / name).string() + "' before this run replaces it: " + ec.message());
  }
  s.copy_before_replacing = false;
  if (s.copy_is_folders) {
    err << "cellform: note: the folder's own " << kCheckpointName
        << (step.empty() ? std::string() : " (step " + step + ")") << " is kept as " << (dir / name).string()
        << " (this run, resumed from another checkpoint, replaces it)\n";
    return;
  }
  s.kept_checkpoint = name;
  s.replaced.back()["checkpoint"] = name;
  err << "cellform: note: the checkpoint resumed is kept as " << (dir / name).string() << " (this run's "
      << kCheckpointName << " replaces it)\n";
}

void apply_checkpoint_every(std::optional<std::uint64_t> every, OutputSpec* output, json& resolved) {
  if (!every) return;
  if (output) {
    output->checkpoint_every = *every;
    output->checkpoint_seconds = 0;
    output->checkpoint_minutes = 0;  // exactly every N steps: none between
  }
  if (resolved.contains("output")) {
    resolved["output"]["checkpoint_every"] = *every;
    resolved["output"]["checkpoint_seconds"] = 0;
    resolved["output"]["checkpoint_minutes"] = 0;
  }
}

void adopt_edited_script(Start& s, const RunOptions& o, const SceneConfig& cfg, std::ostream& err) {
  std::string why;
  const std::optional<SceneConfig> before = load_run_script(s, o.limits, why);
  if (!before) {
    err << "cellform: note: the run's own script (" << s.replaced_path << ") no longer loads (" << why << "), so what "
        << s.script_path.string() << " changes in its shapes and petioles is not checked\n";
    // its max_steps is not known: the edited script's counts as a change where it differs from the run's limit
    if (cfg.colonisation && !s.colonisation_bytes.empty() && !s.sheet_partial &&
        cfg.colonisation->params.max_steps != s.checkpoint_target)
      s.max_steps_changed = true;
    return;
  }
  const bool cell_run = s.colonisation_bytes.empty() && !s.sheet_partial;
  const bool colonisation = !s.colonisation_bytes.empty() && !s.sheet_partial;  // its sheet, if any, is grown
  // its values as the run used them: with the run's seed, target and --checkpoint-every
  s.replaced_parameters = before->resolved;
  json& was = s.replaced_parameters;
  if (was.contains("run")) {
    was["run"]["seed"] = *s.seed;
    if (cell_run) was["run"]["steps"] = s.checkpoint_target;
  }
  if (colonisation && was.contains("colonisation")) was["colonisation"]["max_steps"] = s.checkpoint_target;
  if (colonisation && before->colonisation && cfg.colonisation &&
      before->colonisation->params.max_steps != cfg.colonisation->params.max_steps)
    s.max_steps_changed = true;
  apply_checkpoint_every(s.checkpoint_every_of_run, nullptr, was);
  const std::string unplaced = unplaced_changes(s, *before, cfg);
  if (!unplaced.empty())
    err << "cellform: warning: " << s.script_path.string() << " changes the " << unplaced
        << (colonisation ? "; they do not apply (the checkpoint's cell sheet is grown already)"
                         : "; they are not placed (a resume keeps the checkpoint's cells, at step " +
                               std::to_string(s.step) + ")")
        << ": start a new run for them\n";
  // a cell run keeps its target (its --steps too) unless the edited script changes run.steps
  if (!o.steps && cell_run && before->steps == cfg.steps) s.has_target = true;
}

std::optional<SceneConfig> load_run_script(const Start& s, const ScriptLimits& limits, std::string& why) {
  try {
    ScriptHost old(limits);
    old.accept_digit_booleans(s.checkpoint_digit_booleans);  // it loads the checkpoint's own --set texts
    return old.load(s.checkpoint_source, s.replaced_path, s.checkpoint_sets);
  } catch (const core::InvalidInput& e) {
    if (g_interrupt.load()) throw;  // a Ctrl-C while it was read stops the resume, as in the first reading
    why = e.what();
  } catch (const std::exception& e) {
    why = core::error_text(e);
  }
  return std::nullopt;
}

std::string knob_recall(const Overrides& sets, const std::string& message) {
  if (message.rfind("--set ", 0) == 0) return {};  // the error is of a value given by --set itself
  std::string knobs;
  for (const auto& [name, value] : sets)
    if (name.find('.') == std::string::npos && message.find("knob " + name) == std::string::npos &&
        message.find("--set " + name + "=") == std::string::npos)
      knobs += (knobs.empty() ? "" : ", ") + name + "=" + value;
  return knobs.empty()
             ? knobs
             : "  (this run sets the script's knobs " + knobs + ", which its parameters may be computed from)\n";
}

std::string unplaced_changes(const Start& s, const SceneConfig& before, const SceneConfig& now) {
  // a space-colonisation checkpoint on cells has its sheet grown: nothing of it applies any more
  const bool grown = !s.colonisation_bytes.empty() && !s.sheet_partial;
  auto due = [&](const std::vector<forms::PetioleSpec>& all) {  // as a set: the order of the lines is no change
    std::vector<std::tuple<double, double, double, bool, std::uint64_t>> out;
    for (const forms::PetioleSpec& p : all)
      if (grown || p.step <= s.step) out.emplace_back(p.at.x(), p.at.y(), p.at.z(), p.fixed, p.step);
    std::sort(out.begin(), out.end());
    return out;
  };
  auto cells = [](const std::vector<InitialCell>& all) {
    std::vector<std::tuple<double, double, double, bool>> out;
    for (const InitialCell& c : all) out.emplace_back(c.position.x(), c.position.y(), c.position.z(), c.fixed);
    return out;
  };
  std::vector<std::string> what;
  if (cells(before.initial_cells) != cells(now.initial_cells))
    what.push_back("shapes (" + std::to_string(now.initial_cells.size()) + " cells, the run's " +
                   std::to_string(before.initial_cells.size()) + ")");
  if (due(before.scene.petioles) != due(now.scene.petioles)) {
    // the lines of the petioles that differ (new or moved), and how many of the run's are gone
    auto old_due = due(before.scene.petioles);
    std::string list;
    for (const forms::PetioleSpec& p : now.scene.petioles) {
      if (!grown && p.step > s.step) continue;
      const auto key = std::make_tuple(p.at.x(), p.at.y(), p.at.z(), p.fixed, p.step);
      if (const auto same = std::find(old_due.begin(), old_due.end(), key); same != old_due.end()) {
        old_due.erase(same);  // unchanged
        continue;
      }
      std::string origin = p.origin;
      while (!origin.empty() && (origin.back() == ' ' || origin.back() == ':')) origin.pop_back();
      list += std::string(list.empty() ? "" : ", ") + (origin.empty() ? "petiole{}" : origin);
    }
    if (!old_due.empty())
      list += std::string(list.empty() ? "" : "; ") + std::to_string(old_due.size()) +
              " of the run's no longer there (moved or removed)";
    what.push_back((grown ? std::string("petioles") : "petioles due by step " + std::to_string(s.step)) + " (" + list +
                   ")");
  }
  if (grown) {
    const json a = physics_of(before.resolved), b = physics_of(now.resolved);
    for (const char* section : {"cells", "division"})
      if (a.value(section, json()) != b.value(section, json())) what.push_back(std::string(section) + "{...}");
  }
  std::string text;
  for (std::size_t k = 0; k < what.size(); ++k) text += (k == 0 ? "" : k + 1 == what.size() ? " and " : ", ") + what[k];
  return text;
}

/// What a resume changes of a colonisation run's own values, in words ("colonisation.darts = 2 (was 1)"):
/// the --set overrides that differ from the run's, and with --script the edited script's colonisation
/// values that differ from the run's script's. Leaves out threads, the limits (max_steps, max_nodes, max_sources)
/// and the widths (murray_exponent, tip_radius, node_flow: computed from the veins at the end), which may change.
std::string changed_colonisation_values(const Start& s, const SceneConfig& cfg) {
  std::vector<std::string> changed;
  auto may_change = [](const std::string& key) {
    return key == "threads" || key == "max_steps" || key == "max_nodes" || key == "max_sources" ||
           key == "murray_exponent" || key == "tip_radius" || key == "node_flow";
  };
  for (const auto& [k, v] : s.sets) {
    const auto was = s.checkpoint_sets.find(k);
    const std::string name = k.rfind("colonisation.", 0) == 0 ? k.substr(sizeof("colonisation.") - 1) : std::string();
    if ((was == s.checkpoint_sets.end() || was->second != v) && !may_change(name) && k.rfind("output.", 0) != 0 &&
        k.rfind("print.", 0) != 0)
      changed.push_back("--set " + k + "=" + v);
  }
  const json before = s.replaced_parameters.is_object() ? s.replaced_parameters.value("colonisation", json()) : json();
  const json now = cfg.resolved.value("colonisation", json());
  if (before.is_object() && now.is_object())
    for (const auto& [k, v] : now.items())
      if (!may_change(k) && before.contains(k) && before[k] != v)
        changed.push_back("colonisation." + k + " = " + v.dump() + " (was " + before[k].dump() + ")");
  std::string text;
  for (std::size_t i = 0; i < changed.size(); ++i) text += (i ? ", " : "") + changed[i];
  return text;
}

std::string changed_domain_values(const Start& s, const SceneConfig& cfg) {
  std::vector<std::string> changed;
  const char* const sections[] = {"leaf", "volume", "surface"};
  auto of_domain = [&](const std::string& key) {
    return std::any_of(std::begin(sections), std::end(sections),
                       [&](const char* d) { return key.rfind(std::string(d) + ".", 0) == 0; });
  };
  for (const auto& [k, v] : s.sets) {
    const auto was = s.checkpoint_sets.find(k);
    if (of_domain(k) && (was == s.checkpoint_sets.end() || was->second != v)) changed.push_back("--set " + k + "=" + v);
  }
  for (const char* d : sections) {
    const json before = s.replaced_parameters.is_object() ? s.replaced_parameters.value(d, json()) : json();
    const json now = cfg.resolved.value(d, json());
    if (!before.is_object() || !now.is_object()) continue;
    for (const auto& [k, v] : now.items())
      if (!before.contains(k) || before[k] != v)
        changed.push_back(std::string(d) + "." + k + " = " + v.dump() + " (was " +
                          (before.contains(k) ? before[k].dump() : std::string("not given")) + ")");
    for (const auto& [k, v] : before.items())
      if (!now.contains(k)) changed.push_back(std::string(d) + "." + k + " not given (was " + v.dump() + ")");
  }
  std::string text;
  for (std::size_t i = 0; i < changed.size(); ++i) text += (i ? ", " : "") + changed[i];
  return text;
}

}  // namespace cellform::app
