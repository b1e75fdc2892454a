// The cellform command.
#include <csignal>
#include <iostream>

#include "app/cli.h"
#include "app/run.h"

namespace {
void on_interrupt(int) {
  if (cellform::app::g_interrupt.exchange(true)) std::_Exit(130);  // a second Ctrl-C quits at once
}
}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  std::vector<std::string> args(argv + 1, argv + argc);
  return cellform::app::cli_main(args, std::cout, std::cerr);
}
