// Helpers for app tests: temporary directories and files, running the CLI in-process.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.h"

namespace cellform::test {

/// A small cell run (a disc with a petiole, 30 steps, up to 400 cells): seconds to run.
inline const char* kSmall =
    "local P = params { size = 400 }\n"
    "cells { time_step = 0.2, separation = 0.05, drag = {0.8, 0.8, 0.5} }\n"
    "division { trigger = 'age', age = 6, min_age = 3, probability = 0.5, max_cells = P.size }\n"
    "run { steps = 30 }\n"
    "disc { radius = 3 }\n"
    "petiole { at = {0, 0, 0} }\n";

/// A fresh directory under the system temp dir, removed at scope end.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name) {
    path = std::filesystem::temp_directory_path() / ("cellform-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct CliResult {
  int code;
  std::string out, err;
};

inline CliResult cli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = app::cli_main(args, out, err);
  return {code, out.str(), err.str()};
}

}  // namespace cellform::test
