// Argument parsing for cellform run, resume, params, --help, --version.
#include "app/cli.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <map>
#include <set>
#include <string_view>

#include "app/check.h"
#include "app/run.h"
#include "app/run_internal.h"
#include "app/schema.h"
#include "core/errors.h"

namespace cellform::app {

namespace {

const char* const kUsage =
    "usage: cellform <command> [options]\n"
    "\n"
    "Grows forms from cells and veins and writes them for printing and modelling.\n"
    "\n"
    "commands:\n"
    "  run SCRIPT        run a growth script (examples/*.lua)\n"
    "  resume CHECKPOINT continue an interrupted, failed or finished run (--script: with an edited script);\n"
    "                    CHECKPOINT is a run's checkpoint.cfck or the output folder holding it\n"
    "  check FILE        is an STL, OBJ or PLY mesh printable? (exit 0 yes, 1 no, 2 unreadable)\n"
    "  params            print every script parameter with its default, range and unit (Markdown)\n"
    "\n"
    "options:\n"
    "  -h, --help        show help (cellform run --help for run options)\n"
    "  --version         print the version\n"
    "\n"
    "exit codes: 0 success, 1 runtime failure, 2 usage or input error, 130 interrupted\n";

const char* const kRunUsage =
    "usage: cellform run SCRIPT [options]\n"
    "       cellform resume CHECKPOINT [options]\n"
    "\n"
    "options (also as --option=VALUE):\n"
    "  --out DIR               output directory (default out/<script name>/; resume: the checkpoint's folder)\n"
    "  --seed N                seed of every random choice (default: run.seed of the script, 1)\n"
    "  --steps N               steps to run (resume: the total to reach); 0 writes the cells as placed;\n"
    "                          space colonisation: the step limit, at least 1\n"
    "  --threads N             worker threads, 0 = all cores (the results are identical for any N)\n"
    "  --set NAME=VALUE        override a script parameter: a params{} knob or section.name,\n"
    "                          e.g. --set cells.spring=2 --set division.max_cells=5000 (repeatable)\n"
    "  --checkpoint-every N    write a checkpoint every N steps, exactly (default: output.checkpoint_every,\n"
    "                          and then no two within output.checkpoint_seconds, 60 s, and one after\n"
    "                          the first step that ends output.checkpoint_minutes, 10, after the last)\n"
    "  --lua-instructions N    instruction budget of the script (default 500000000)\n"
    "  --lua-memory MB         memory limit of the script (default 512)\n"
    "  --lua-seconds S         longest one call of a Lua library function may run, such as a string\n"
    "                          pattern that backtracks (default 60)\n"
    "  --script FILE           resume only: continue with FILE, an edited copy of the run's script (after\n"
    "                          a rule error, say): the checkpoint's cells, step and seed are kept, FILE's\n"
    "                          parameters and rules apply (--set still overrides; its run.steps if changed);\n"
    "                          the checkpoint it replaces is kept as checkpoint-stepN.cfck\n"
    "  --quiet, -q             only notes, warnings and errors: no progress, and no summary when it ends well\n"
    "\n"
    "Outputs: cells.ply, cells.obj (with venation{} also veins.ply, veins.obj; space colonisation instead\n"
    "veins.ply, veins.obj, in a leaf veins.svg, with output{png = true} veins.png, and on the grown cell\n"
    "sheet (surface{cells = true}) cells.ply, cells.obj too), printable.stl and the other formats print{}\n"
    "asks for, run.json (everything needed to reproduce the run) and checkpoint.cfck in the output directory.\n"
    "Ctrl-C stops after the current step, writes the outputs and a checkpoint; `cellform resume\n"
    "DIR/checkpoint.cfck` (or `cellform resume DIR`) continues to the identical result.\n";

/// The options of run and resume.
constexpr std::array<std::string_view, 12> kRunOptions = {"--out",
                                                          "--seed",
                                                          "--steps",
                                                          "--threads",
                                                          "--set",
                                                          "--quiet",
                                                          "--help",
                                                          "--checkpoint-every",
                                                          "--lua-instructions",
                                                          "--lua-memory",
                                                          "--lua-seconds",
                                                          "--script"};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::uint64_t parse_count(const std::string& flag, const std::string& text, std::uint64_t max, std::uint64_t min = 0) {
  std::uint64_t v = 0;
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || v > max || v < min)
    throw UsageError(flag + " takes a whole number from " + std::to_string(min) + " to " + std::to_string(max) +
                     ", got '" + text + "'");
  return v;
}

}  // namespace

int cli_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  try {
    if (args.empty()) {
      err << kUsage;
      return usage;
    }
    const std::string& cmd = args[0];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
      // cellform --help run (or help check): that command's help
      if (args.size() == 2 && (args[1] == "run" || args[1] == "resume" || args[1] == "check" || args[1] == "params"))
        return cli_main({args[1], "--help"}, out, err);
      if (args.size() > 2)
        throw UsageError("cellform " + cmd + " takes one COMMAND (run, resume, check or params), got '" + args[2] +
                         "' too");
      if (args.size() == 2)  // "cellform help foo" said the general help, exit 0, as if foo were known
        throw UsageError("no help for '" + args[1] + "': the commands are run, resume, check and params (cellform " +
                         cmd + " COMMAND)");
      out << kUsage;
      return ok;
    }
    if (cmd == "params" && args.size() == 2 && (args[1] == "-h" || args[1] == "--help")) {
      out << "usage: cellform params\nPrints every script parameter: its default, allowed values, unit and meaning.\n";
      return ok;
    }
    if ((cmd == "--version" || cmd == "version" || cmd == "params") && args.size() > 1)
      throw UsageError("cellform " + cmd + " takes no arguments, got '" + args[1] + "'");
    if (cmd == "--version" || cmd == "version") {
      out << "cellform " << version() << "\n";
      return ok;
    }
    if (cmd == "params") {
      out << "# cellform script parameters\n" << schema_markdown();
      return ok;
    }
    if (cmd == "check") {
      bool json = false;
      double min_wall = 0;
      std::vector<std::string> files;
      std::string wall_given;  // as run and resume: an option given twice is refused, not the last one taken
      for (std::size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--json") {
          if (json) throw UsageError("--json is given twice; give it once");
          json = true;
        } else if (args[i] == "--min-wall" || args[i].rfind("--min-wall=", 0) == 0) {
          const bool joined = args[i].size() > 10;
          if (!joined && i + 1 == args.size()) throw UsageError("--min-wall needs a thickness (file units, mm)");
          const std::string v = joined ? args[i].substr(11) : args[++i];
          if (!wall_given.empty())
            throw UsageError("--min-wall is given twice (" + wall_given + " and " + v + "); give it once");
          wall_given = v;
          const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), min_wall);  // no spaces, no hex
          if (ec != std::errc() || end != v.data() + v.size() || !(min_wall > 0 && min_wall <= 1e6))
            throw UsageError("--min-wall must be a thickness > 0 and at most 1e6 (the file's units, mm), got '" + v +
                             "'");
        } else if (args[i] == "-h" || args[i] == "--help") {
          out << "usage: cellform check FILE [--json] [--min-wall T]\n"
                 "Reports triangles, vertices, parts, holes (boundary edges), non-manifold edges and vertices,\n"
                 "orientation, self-intersections, volume, bounding box, genus and wall thickness of an STL, OBJ\n"
                 "or PLY mesh. Exit code 0: printable (watertight, 2-manifold, oriented outward, no\n"
                 "self-intersections; with --min-wall T also no more than 1% of the surface over walls thinner\n"
                 "than T, in the file's units: mm for cellform's prints); 1: not printable; 2: the file cannot\n"
                 "be read, or the report cannot be written.\n";
          return ok;
        } else if (!args[i].empty() && args[i][0] == '-') {
          // cut short (--min-wal) or misspelt, as run's options are said
          const std::string a = args[i].substr(0, args[i].find('='));
          const std::vector<std::string> names = {"--json", "--min-wall", "--help"};
          if (a == "--json" || a == "--help") throw UsageError(a + " takes no value, got '" + args[i] + "'");
          std::string near = a.size() > 3 && std::string("--min-wall").rfind(a, 0) == 0 ? "--min-wall"
                             : a.size() > 3 && std::string("--json").rfind(a, 0) == 0   ? "--json"
                                                                                        : core::closest_name(a, names);
          throw UsageError("unknown option '" + args[i] + "' for check" +
                           (near.empty() ? "" : "; did you mean '" + near + "'?"));
        } else
          files.push_back(args[i]);
      }
      if (files.size() != 1) throw UsageError("cellform check takes one FILE (see cellform check --help)");
      return check_command(files[0], json, min_wall, out, err);
    }
    if (cmd != "run" && cmd != "resume") {
      const std::string near = core::closest_name(cmd, std::vector<std::string>{"run", "resume", "params", "check"});
      throw UsageError("unknown command '" + cmd + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
                       " (see cellform --help)");
    }
    RunOptions o;
    std::vector<std::string> positional;
    std::map<std::string, std::string> once;  // option -> value: one value each (--set: one per name)
    // --steps=5 as --steps 5 (GNU style), for the options that take a value
    std::vector<std::string> opts{args.front()};
    std::set<std::size_t> bound;  // indices in opts of values given after '=': values, whatever they look like
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& a = args[i];
      const std::size_t eq = a.find('=');
      const std::string name = a.substr(0, eq);
      if (a.rfind("--", 0) == 0 && eq != std::string::npos && name != "--quiet" && name != "--help" &&
          std::find(kRunOptions.begin(), kRunOptions.end(), name) != kRunOptions.end()) {
        opts.push_back(name);
        bound.insert(opts.size());
        opts.push_back(a.substr(eq + 1));
      } else {
        opts.push_back(a);
      }
    }
    for (std::size_t i = 1; i < opts.size(); ++i) {
      const std::string& a = opts[i];
      auto value = [&]() -> const std::string& {
        if (i + 1 >= opts.size()) throw UsageError(a + " needs a value");
        const std::string& next = opts[i + 1];
        if (!bound.count(i + 1) && (next == "-q" || next == "-h" ||
                                    std::find(kRunOptions.begin(), kRunOptions.end(), next) != kRunOptions.end()))
          throw UsageError(a + " needs a value, got the option " + next +
                           (a == "--out" || a == "--script" ? " (a file or folder so named is ./" + next + ")" : ""));
        if (a != "--set") {  // the last of two would win unsaid: which one was meant?
          const auto [it, first] = once.emplace(a, next);
          if (!first && it->second != next)
            throw UsageError(a + " is given twice (" + it->second + " and " + next + "); give it once");
        }
        return opts[++i];
      };
      if (a == "-h" || a == "--help") {
        out << kRunUsage;
        return ok;
      } else if (a == "--out") {
        o.out = value();
        if (o.out->empty()) throw UsageError("--out needs a folder name, got an empty one");
        std::error_code ec;
        if (std::filesystem::exists(*o.out, ec) && !std::filesystem::is_directory(*o.out, ec))
          throw UsageError("--out " + o.out->string() + " is a file, not a folder; name a folder for the outputs");
        if (o.out->has_root_path() && o.out->lexically_normal() == o.out->root_path())
          throw UsageError("--out " + o.out->string() +
                           " is the root of the file system; name a folder for the outputs");
      } else if (a == "--seed") {
        o.seed = parse_count(a, value(), 9007199254740992ull);  // as run.seed: 2^53
      } else if (a == "--steps") {
        o.steps = parse_count(a, value(), 1'000'000'000ull);
      } else if (a == "--threads") {
        o.threads = static_cast<int>(parse_count(a, value(), 256));
      } else if (a == "--checkpoint-every") {
        o.checkpoint_every = parse_count(a, value(), 1'000'000'000ull);
      } else if (a == "--lua-instructions") {
        o.limits.instructions = parse_count(a, value(), ~0ull, 1);
      } else if (a == "--lua-seconds") {
        o.limits.library_seconds = static_cast<double>(parse_count(a, value(), 86400, 1));
      } else if (a == "--lua-memory") {
        const std::uint64_t mb = parse_count(a, value(), 65536, 1);  // MB
        o.limits.memory_bytes = static_cast<std::size_t>(mb) << 20;
      } else if (a == "--set") {
        const std::string& kv = value();
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError("--set takes NAME=VALUE, got '" + kv + "'");
        const std::string name = kv.substr(0, eq), given = kv.substr(eq + 1);
        if (!core::is_utf8(kv))  // run.json and the checkpoint record it
          throw UsageError("--set " + core::printable(kv) +
                           ": not UTF-8 text, which run.json and the checkpoint record; give the value in UTF-8");
        if (const auto before = o.sets.find(name); before != o.sets.end() && before->second != given)
          err << "cellform: note: --set " << name << " is given twice; the last, " << given << ", is used (not "
              << before->second << ")\n";
        o.sets[name] = given;
      } else if (a == "--script") {
        o.replace_script = value();
        if (cmd != "resume")
          throw UsageError(
              "--script is for cellform resume (continue a checkpoint with an edited script); "
              "cellform run takes the script itself: cellform run " +
              o.replace_script->string());
        if (o.replace_script->empty()) throw UsageError("--script needs a file name, got an empty one");
      } else if (a == "--quiet" || a == "-q") {
        o.quiet = true;
      } else if (a.rfind("--quiet=", 0) == 0 || a.rfind("--help=", 0) == 0) {
        throw UsageError(a.substr(0, a.find('=')) + " takes no value, got '" + a + "'");
      } else if (a.size() > 1 && a[0] == '-') {
        // an option cut short (--ste) is the one it begins, if only one does; else the closest by spelling
        std::vector<std::string> begun;
        for (const std::string_view name : kRunOptions)
          if (a.size() > 3 && name.substr(0, a.size()) == a) begun.emplace_back(name);
        const std::string near =
            begun.size() == 1 ? begun[0]
                              : core::closest_name(a, std::vector<std::string>(kRunOptions.begin(), kRunOptions.end()));
        throw UsageError("unknown option '" + a + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?"));
      } else {
        positional.push_back(a);
      }
    }
    if (positional.size() != 1)
      throw UsageError(cmd == "run" ? "cellform run takes one SCRIPT (see cellform run --help)"
                                    : "cellform resume takes one CHECKPOINT (see cellform run --help)");
    if (cmd == "run")
      o.script = positional[0];
    else
      o.checkpoint = positional[0];
    // the other command's file: said so, as a script given to resume is (a checkpoint read as Lua said
    // "syntax error", run.json "not a cellform file")
    if (cmd == "run" && o.script.extension() == ".cfck")
      throw UsageError("'" + o.script.string() +
                       "' is a checkpoint, not a script: continue its run with cellform resume " +
                       shell_word(o.script.string()));
    if (cmd == "resume" && o.checkpoint.filename() == "run.json")
      throw UsageError(
          "'" + o.checkpoint.string() + "' is the record of a run, not its checkpoint: resume the run's " +
          "folder, cellform resume " +
          shell_word(o.checkpoint.parent_path().empty() ? std::string(".") : o.checkpoint.parent_path().string()));
    // a run's folder: the checkpoint in it (a folder without one is refused when the checkpoint is read)
    std::error_code ec;
    if (cmd == "resume" && std::filesystem::is_directory(o.checkpoint, ec) &&
        std::filesystem::is_regular_file(o.checkpoint / "checkpoint.cfck", ec))
      o.checkpoint /= "checkpoint.cfck";
    return run_command(o, out, err);
  } catch (const UsageError& e) {
    err << "cellform: " << e.what() << "\n";
    return usage;
  } catch (const std::exception& e) {
    err << "cellform: " << core::error_text(e) << "\n";
    return failure;
  }
}

}  // namespace cellform::app
