// The watchdog of a script host: the one guard that reaches a script stuck inside a C library call.
// Internal to app/script_host.cpp (needs ScriptHost::Impl from app/script_impl.h).
#pragma once

#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "app/script_impl.h"

namespace cellform::app {

/// Stops the process when a script is stuck inside one call of a C library function, which the instruction
/// budget and Ctrl-C (both checked by the hook, between Lua instructions) cannot reach: no hook call for
/// ScriptLimits::library_seconds while Lua code runs, or for 2 s after a Ctrl-C. Nothing can unwind the
/// call, so it writes its message with write(2), lets the run's handler (ScriptHost::set_on_stuck) leave its
/// folder as after a script error, and ends the process with _exit.
class ScriptHost::Watchdog {
 public:
  /// Constructed on the thread that runs the script: its CPU time is what is measured.
  explicit Watchdog(Impl& i) : i_(i), script_cpu_(cpu_clock_of_this_thread()), thread_([this] { watch(); }) {}
  ~Watchdog() {
    {
      const std::lock_guard<std::mutex> lock(m_);
      quit_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  static clockid_t cpu_clock_of_this_thread() {
    clockid_t id = CLOCK_MONOTONIC;  // without a thread clock: wall time
    if (pthread_getcpuclockid(pthread_self(), &id) != 0) id = CLOCK_MONOTONIC;
    return id;
  }
  /// Seconds of the script thread's CPU time: a process stopped (Ctrl-Z) or blocked on output uses none.
  double script_seconds() const {
    timespec t{};
    clock_gettime(script_cpu_, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  void watch() {
    using clock = std::chrono::steady_clock;
    std::unique_lock<std::mutex> lock(m_);
    std::uint64_t last = 0;
    double since = script_seconds();
    std::optional<clock::time_point> interrupted;  // when this thread first saw the Ctrl-C
    double stop_seen = -1;                         // script CPU seconds when a pending stop was first seen
    while (!cv_.wait_for(lock, std::chrono::milliseconds(100), [this] { return quit_; })) {
      if (!interrupted && g_interrupt.load()) interrupted = clock::now();
      if (interrupted && std::chrono::duration<double>(clock::now() - *interrupted).count() >= 0.5)
        i_.interrupt_at_calls.store(true, std::memory_order_relaxed);
      // A stop (the budget, a Ctrl-C) raises at every instruction until the call ends, but Lua runs an
      // xpcall message handler and __close handlers with the hook off: one that loops escapes it.
      const bool stop = i_.stop_pending.load(std::memory_order_acquire) && i_.in_script.load(std::memory_order_acquire);
      if (!stop)
        stop_seen = -1;
      else if (stop_seen < 0)
        stop_seen = script_seconds();
      else if (script_seconds() - stop_seen >= 2)
        die(interrupted ? 130 : 2,
            script_ +
                ": the script did not stop when it was stopped (an xpcall message handler or a __close handler "
                "that loops runs beyond Lua's hook)" +
                rule_in_progress() + "; stopped",
            "");
      const std::uint64_t beats = i_.beats.load(std::memory_order_relaxed);
      if (!i_.in_script.load(std::memory_order_acquire) || beats != last) {
        last = beats;
        since = script_seconds();
        continue;
      }
      // every call the script's code makes begins with a beat (the hook), so no beat while Lua code runs
      // is one library call
      const double stuck = script_seconds() - since;
      if (stuck >= 0.2) i_.ask_caller.store(true, std::memory_order_relaxed);
      const double since_interrupt =
          interrupted ? std::chrono::duration<double>(clock::now() - *interrupted).count() : 0.0;
      if (interrupted && std::min(stuck, since_interrupt) >= 2)
        die(130,
            "interrupted, but " + script_ +
                " is inside one call of a Lua library function (a string pattern that backtracks?) that cannot stop "
                "cleanly" +
                rule_in_progress() + ": stopped",
            "");
      if (stuck >= i_.limits.library_seconds)
        die(2,
            script_ + ": the script spent more than " + core::number_text(i_.limits.library_seconds) +
                " s in one call of a Lua library function (a string pattern that backtracks?) and was stopped" +
                rule_in_progress(),
            "; raise the limit with --lua-seconds");
    }
  }
  /// " (in RULE at step S for cell C)" while a rule function runs, else empty.
  std::string rule_in_progress() const {
    const char* rule = i_.call_rule.load(std::memory_order_acquire);
    if (!rule) return {};
    return std::string(" (in ") + rule + " at step " + std::to_string(i_.call_step.load(std::memory_order_relaxed)) +
           " for cell " + std::to_string(i_.call_cell.load(std::memory_order_relaxed)) + ")";
  }
  /// Ends the process (m_ held): the message, then what the run's handler has to say and do.
  [[noreturn]] void die(int code, const std::string& what, const std::string& advice) {
    const std::string message = "cellform: " + what + (on_stuck_ ? "" : " without writing outputs") + advice + "\n";
    i_.dying.store(true, std::memory_order_release);  // a call that ends now goes no further
    const ssize_t ignored = ::write(2, message.data(), message.size());
    (void)ignored;
    if (on_stuck_) try {
        on_stuck_(what + advice);
      } catch (...) {  // nothing more can be done: the process ends anyway
      }
    exit_process(code);
  }

 public:
  std::string script_;  // set before the script runs (load), read only while it runs

  void set_on_stuck(std::function<void(const std::string&)> f) {
    const std::lock_guard<std::mutex> lock(m_);
    on_stuck_ = std::move(f);
  }

 private:
  Impl& i_;
  clockid_t script_cpu_;
  std::mutex m_;
  std::condition_variable cv_;
  bool quit_ = false;
  std::function<void(const std::string&)> on_stuck_;  // under m_
  std::thread thread_;
};

}  // namespace cellform::app
