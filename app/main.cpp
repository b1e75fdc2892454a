// The cellform command.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <iostream>
#include <streambuf>
#include <string>

#include "app/cli.h"
#include "app/escaping_buf.h"
#include "app/run.h"
#include "core/errors.h"

namespace {
// Whether what standard error holds so far ends a line (EscapingBuf keeps it; lock-free, so a handler may read it).
std::atomic<bool> g_err_line_start{true};

void say(const char* text, std::size_t size) {
  // a message's leading line break ends a half-written line (a progress bar's); after a whole line, none
  if (g_err_line_start.load() && size > 0 && text[0] == '\n') {
    ++text;
    --size;
  }
  const ssize_t written = ::write(2, text, size);  // async-signal-safe, unlike iostreams
  (void)written;
  g_err_line_start.store(true);  // (every message ends its line)
}

// The first stop signal and its sender, claimed in one step (the two copies GNU timeout sends, to the process
// and to its group, from one process at once, can reach two threads at once), and when it came (0 until
// stored: a copy that finds 0 came with it).
std::atomic<std::uint64_t> g_first_stop{0};
std::atomic<long long> g_first_ns{0};

long long monotonic_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe
  return static_cast<long long>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

void on_interrupt(int sig, siginfo_t* info, void*) {
  using namespace cellform::app;
  const long long now = monotonic_ns();
  // sent by a process (not typed at the terminal, which the kernel sends with no sender)
  const pid_t sender = info && info->si_code == SI_USER ? info->si_pid : 0;
  const std::uint64_t stop =
      static_cast<std::uint64_t>(static_cast<std::uint32_t>(sender)) << 8 | static_cast<std::uint8_t>(sig);
  std::uint64_t first = 0;
  if (g_first_stop.compare_exchange_strong(first, stop)) {
    g_first_ns.store(now);
  } else if (sender != 0 && first == stop) {
    const long long at = g_first_ns.load();
    if (at == 0 || now - at < 250000000LL) return;  // the same stop again, from the same process: not a second
  }
  int none = 0;
  g_interrupt_signal.compare_exchange_strong(none, sig);
  if (g_interrupt.exchange(true)) {
    // a print the first Ctrl-C asked for: this one cancels it, keeping the other outputs
    if (g_print_after_interrupt.load() && !g_print_cancel.exchange(true)) {
      static const char kCancel[] =
          "\ncellform: cancelling the print once its pass under way ends (seconds on a large print); Ctrl-C again "
          "quits at once, without outputs\n";
      say(kCancel, sizeof kCancel - 1);
      return;
    }
    static const char kQuit[] =
        "\ncellform: quit: the output folder keeps its last checkpoint, if one was written (cellform resume goes on "
        "from it); the next run or resume there removes the files this one left half-written\n";
    say(kQuit, sizeof kQuit - 1);
    exit_process(130);  // quits at once
  }
  // said as what came, Ctrl-C or SIGTERM (the same stop, the same escalation); the first waits for the step (or
  // the script's own code) to end: say so, or a busy step looks hung
  const int term = sig == SIGTERM ? 1 : 0;
  static const char* const kReading[2] = {
      "\ncellform: Ctrl-C: stopping the script being read (Ctrl-C again quits at once)\n",
      "\ncellform: SIGTERM: stopping the script being read (another SIGTERM or Ctrl-C quits at once)\n"};
  static const char* const kStop[2][2] = {
      // [term][print planned]
      {"\ncellform: interrupted: the steps stop after the current one and the outputs are written; Ctrl-C again "
       "quits at once, without outputs\n",
       "\ncellform: interrupted: the steps stop after the current one (a printable solid being made is skipped, once "
       "its pass under way ends) and the outputs are written; Ctrl-C again skips a printable solid being made, and "
       "otherwise quits at once, without outputs\n"},
      {"\ncellform: terminated (SIGTERM): the steps stop after the current one and the outputs are written; "
       "another SIGTERM or Ctrl-C quits at once, without outputs\n",
       "\ncellform: terminated (SIGTERM): the steps stop after the current one (a printable solid being made is "
       "skipped, once its pass under way ends) and the outputs are written; another SIGTERM or Ctrl-C skips a "
       "printable solid being made, and otherwise quits at once, without outputs\n"}};
  static const char* const kPrinting[2] = {
      "\ncellform: interrupted during the print: the printable solid is skipped once its pass under way ends, and "
      "the other outputs are kept; Ctrl-C again quits at once, without outputs\n",
      "\ncellform: terminated (SIGTERM) during the print: the printable solid is skipped once its pass under way "
      "ends, and the other outputs are kept; another SIGTERM or Ctrl-C quits at once, without outputs\n"};
  bool reading = true;  // taken from the reading, which stops then (ScriptHost::load sees it at its end, too)
  const char* text = g_reading_script.compare_exchange_strong(reading, false) ? kReading[term]
                     : g_printing.load()                                      ? kPrinting[term]
                                         : kStop[term][g_print_planned.load() ? 1 : 0];
  say(text, std::strlen(text));  // strlen is async-signal-safe
}
void on_hangup(int) {
  using namespace cellform::app;
  if (g_interrupt.exchange(true)) return;  // never escalates: a hang-up may come more than once
  bool reading = true;
  if (g_reading_script.compare_exchange_strong(reading, false)) {  // stopped at its next instruction, or its end
    static const char kReading[] = "\ncellform: hang-up: stopping the script being read\n";
    say(kReading, sizeof kReading - 1);
    return;
  }
  static const char kMessage[] =
      "\ncellform: hang-up: the steps stop after the current one and the outputs and a checkpoint are written\n";
  say(kMessage, sizeof kMessage - 1);
}
}  // namespace

int main(int argc, char** argv) {
  struct sigaction stop {};
  stop.sa_sigaction = on_interrupt;
  stop.sa_flags = SA_SIGINFO | SA_RESTART;
  sigemptyset(&stop.sa_mask);  // one stop handler at a time on a thread
  sigaddset(&stop.sa_mask, SIGINT);
  sigaddset(&stop.sa_mask, SIGTERM);
  sigaction(SIGINT, &stop, nullptr);
  sigaction(SIGTERM, &stop, nullptr);
  // a closed terminal or a dropped ssh: stop as after one Ctrl-C, with a checkpoint (however often it
  // comes); under nohup, which ignores it, go on
  if (std::signal(SIGHUP, SIG_IGN) != SIG_IGN) std::signal(SIGHUP, on_hangup);
  std::signal(SIGPIPE, SIG_IGN);  // a closed pipe on stdout or stderr: the writes fail, the run goes on
  // a file-size limit (ulimit -f) would kill the process mid-write: the write fails instead (EFBIG) and is
  // reported as a full disk is
  std::signal(SIGXFSZ, SIG_IGN);
  std::vector<std::string> args(argv + 1, argv + argc);
  static_assert(std::atomic<bool>::is_always_lock_free);
  cellform::app::EscapingBuf out_buf(std::cout.rdbuf()), err_buf(std::cerr.rdbuf());
  err_buf.track_line_start(&g_err_line_start);
  std::ostream out(&out_buf), err(&err_buf);
  err.setf(std::ios::unitbuf);  // as std::cerr: every message at once, after what stdout holds
  err.tie(&out);
  int code = cellform::app::cli_main(args, out, err);
  out.flush();
  std::cout.flush();
  // a run's product is its files (its lines on stdout only say so); the other commands' is what they print:
  // lost (a full disk, a closed pipe), it is no success
  const bool helps = std::find_if(args.begin(), args.end(), [](const std::string& a) {
                       return a == "-h" || a == "--help";
                     }) != args.end();  // (run --help: its product is the text, as for the others)
  const bool prints_product = args.empty() || (args[0] != "run" && args[0] != "resume") || helps;
  if (prints_product && (!out || !std::cout)) {
    // a pipe fails only when its reader stopped early (cellform params | head), which knows why: not said
    struct stat st {};
    const bool open = ::fstat(1, &st) == 0;
    if (!open)
      err << "cellform: cannot write to standard output: it is closed\n";
    else if (!S_ISFIFO(st.st_mode) && !S_ISSOCK(st.st_mode))
      err << "cellform: cannot write to standard output (a full disk?)\n";
    // check's 1 says "not printable": a report that was not written is 2, as an unread file
    code = !args.empty() && args[0] == "check" ? 2 : code == 0 ? 1 : code;
  }
  // after a Ctrl-C, even one that came as the work ended, by SIGINT (exit_process says why)
  if (cellform::app::g_interrupt_signal.load() == SIGINT) {
    std::cerr.flush();
    cellform::app::exit_process(code);
  }
  return code;
}
