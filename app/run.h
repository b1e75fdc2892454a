// `cellform run` and `cellform resume`: script -> scene -> steps -> outputs, checkpoint and run.json.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "app/script_host.h"

namespace cellform::app {

/// Options of one run, as the command line gives them.
struct RunOptions {
  std::filesystem::path script;              ///< the growth script (run)
  std::filesystem::path checkpoint;          ///< the checkpoint to continue (resume)
  std::optional<std::filesystem::path> out;  ///< output directory (default out/<script name>/)
  std::optional<std::uint64_t> seed;         ///< overrides run.seed
  std::optional<std::uint64_t> steps;        ///< overrides run.steps (resume: the total to reach)
  int threads = 0;                           ///< 0 = all cores
  Overrides sets;                            ///< --set key=value
  bool quiet = false;
  ScriptLimits limits;
  std::optional<std::uint64_t> checkpoint_every;  ///< overrides output.checkpoint_every
  /// resume --script: continue the checkpoint's state with this script instead of the one it keeps
  std::optional<std::filesystem::path> replace_script;
};

/// Exit codes of the command.
enum ExitCode : int { ok = 0, failure = 1, usage = 2, interrupted = 130 };

/// Set by the SIGINT handler; the run stops after the current step, writes outputs and a checkpoint.
extern std::atomic<bool> g_interrupt;
/// Set while a print runs that a first Ctrl-C asked for (the steps stopped, the outputs are due): the
/// next Ctrl-C sets g_print_cancel and cancels that print, keeping the other outputs; one more quits.
extern std::atomic<bool> g_print_after_interrupt;
/// Set while a script is read (ScriptHost::load): a first Ctrl-C then takes it (clears it) and says it stops
/// the reading, which ends at the script's next instruction or, in the host's own work, at the reading's end.
extern std::atomic<bool> g_reading_script;
extern std::atomic<bool> g_print_cancel;
/// Set once a run knows it ends with print{}: a Ctrl-C's message then says the printable solid is skipped.
extern std::atomic<bool> g_print_planned;
/// Set while a print runs that no Ctrl-C asked for (the steps ended): a first Ctrl-C's message then says it skips
/// that print.
extern std::atomic<bool> g_printing;
/// The signal of the first interrupt: SIGINT or SIGTERM (0: none, or a hang-up).
extern std::atomic<int> g_interrupt_signal;

/// Ends the process at once with `code` (async-signal-safe). A process that a Ctrl-C (SIGINT) stopped
/// ends by SIGINT instead, whatever `code`: a shell running it in a loop (for f in *.lua; do cellform run
/// "$f"; done) then stops the loop too, as after any program a Ctrl-C ends; after a plain exit(130) bash
/// goes on with the next. The shell's $? is 130 either way.
[[noreturn]] void exit_process(int code);

/// Runs a script (or resumes a checkpoint when options.checkpoint is set); reports to `out`/`err`
/// and returns an exit code. Never throws.
int run_command(const RunOptions& options, std::ostream& out, std::ostream& err);

/// Program version string.
std::string version();

}  // namespace cellform::app
