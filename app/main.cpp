// The cellform command.
#include <unistd.h>

#include <csignal>
#include <iostream>

#include "app/cli.h"
#include "app/run.h"

namespace {
void on_interrupt(int) {
  if (cellform::app::g_interrupt.exchange(true)) std::_Exit(130);  // a second Ctrl-C quits at once
  // the first waits for the step (or the script's own code) to end: say so, or a busy step looks hung
  static const char kMessage[] =
      "\ncellform: stopping after the current step; Ctrl-C again quits at once, without outputs\n";
  const ssize_t written = ::write(2, kMessage, sizeof kMessage - 1);  // async-signal-safe, unlike iostreams
  (void)written;
}
}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  std::vector<std::string> args(argv + 1, argv + argc);
  return cellform::app::cli_main(args, std::cout, std::cerr);
}
