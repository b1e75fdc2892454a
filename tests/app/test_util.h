// Helpers for app tests: temporary directories and files, running the CLI in-process or as a process.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.h"
#include "tests/files.h"

namespace cellform::test {

/// A small cell run (a disc with a petiole, 30 steps, up to 400 cells): seconds to run.
inline const char* kSmall =
    "local P = params { size = 400 }\n"
    "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.5} }\n"
    "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = P.size }\n"
    "run { steps = 30 }\n"
    "disc { radius = 3 }\n"
    "petiole { at = {0, 0, 0} }\n";

/// A small 3-D space colonisation (a ball's worth of veins from its centre), the colonisation counterpart of
/// kSmall: about 50 kB of checkpoint, a few kB of vein files.
inline const char* kSmallVeins =
    "volume { ball = { radius = 5 }, seeds = {{0, 0, 0}} }\n"
    "colonisation { type = 'open', birth_distance = 1, kill_distance = 1, darts = 1e6 }\n";

struct CliResult {
  int code;
  std::string out, err;
};

inline CliResult cli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = app::cli_main(args, out, err);
  return {code, out.str(), err.str()};
}

/// The built cellform binary's path and `args`, as execv takes them (`storage` keeps the strings).
inline std::vector<char*> cellform_argv(const std::vector<std::string>& args, std::vector<std::string>& storage) {
  storage = {std::string(CELLFORM_BINARY_DIR) + "/bin/cellform"};
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : storage) argv.push_back(a.data());
  argv.push_back(nullptr);
  return argv;
}

/// While it lives, writes past `bytes` fail as on a full disk (RLIMIT_FSIZE: EFBIG, SIGXFSZ ignored).
struct FileSizeLimit {
  rlimit old{};
  void (*old_handler)(int) = nullptr;
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old);
    old_handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = old;
    small.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &small);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, old_handler);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
};

/// Starts the built cellform binary with `args` as a child process, for tests that send it signals.
/// SIGHUP is at its default, as from a terminal (ctest may run under nohup); stdout and stderr go to
/// `output` when it is a descriptor (>= 0); `address_limit` bytes (> 0), its address space, as ulimit -v sets it.
/// Returns the child's pid.
inline pid_t spawn_cellform(const std::vector<std::string>& args, int output = -1, rlim_t address_limit = 0) {
  std::vector<std::string> storage;
  std::vector<char*> argv = cellform_argv(args, storage);
  const pid_t pid = fork();
  if (pid == 0) {
    signal(SIGHUP, SIG_DFL);
    if (address_limit > 0) {
      const rlimit limit{address_limit, address_limit};
      setrlimit(RLIMIT_AS, &limit);
    }
    if (output >= 0) {
      dup2(output, 1);
      dup2(output, 2);
    }
    execv(argv[0], argv.data());
    _exit(99);
  }
  return pid;
}

/// spawn_cellform with stdout and stderr into the file `log` (made anew); -1 if it cannot be opened.
/// A cell run of `steps` steps whose print takes seconds (closing the shell of a disc of radius 30: about 4 s), to
/// signal while it prints.
inline std::string slow_print_script(const std::string& steps) {
  return "cells { time_step = 0.2, drag = {0.8, 0.8, 0.5} }\ndivision { trigger = 'none' }\nrun { steps = " + steps +
         " }\ndisc { radius = 30 }\nprint { veins = false, shell = true }\n";
}

/// Whether `text` appears in the file `log` within `seconds` (read every 0.1 s).
inline bool wait_for_text(const std::filesystem::path& log, const std::string& text, int seconds) {
  for (int i = 0; i < 10 * seconds; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (slurp(log).find(text) != std::string::npos) return true;
  }
  return false;
}

inline pid_t spawn_cellform_logged(const std::vector<std::string>& args, const std::filesystem::path& log,
                                   rlim_t address_limit = 0) {
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return -1;
  const pid_t pid = spawn_cellform(args, fd, address_limit);
  ::close(fd);
  return pid;
}

/// Sends `sig` to `pid` from a child process of its own, as a second terminal or `kill` command would (the
/// same signal again from this process within a quarter second is taken as one stop sent twice, as GNU
/// timeout sends it).
inline void kill_from_another_process(pid_t pid, int sig) {
  const pid_t sender = fork();
  if (sender == 0) _exit(kill(pid, sig) == 0 ? 0 : 1);
  REQUIRE(sender > 0);
  int status = 0;
  REQUIRE(waitpid(sender, &status, 0) == sender);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
}

/// A child's wait status as a shell's $? gives it: the exit code, or 128 + the signal that ended it
/// (a Ctrl-C ends cellform by SIGINT: 130, as exit(130) would).
inline int shell_status(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

/// shell_status of child `pid` if it ends within `seconds`; otherwise kills it and returns -2.
inline int exit_within(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return shell_status(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -2;
}

/// Waits for child `pid` to end: its shell_status (-1 if it cannot be waited for). `signal`, if given,
/// gets the signal that ended it (0: it exited).
inline int wait_exit(pid_t pid, int* signal = nullptr) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  if (signal) *signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return shell_status(status);
}

}  // namespace cellform::test
