// The command line of `cellform`: parses arguments and dispatches; used by main() and by tests.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace cellform::app {

/// Runs the command line `args` (without the program name); returns the exit code. Never throws.
int cli_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace cellform::app
