// cellform-bench: runs named benchmarks, prints median/min/max, writes JSON.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "bench/bench.h"
#include "core/atomic_file.h"

namespace cellform::bench {

std::vector<Benchmark>& registry() {
  static std::vector<Benchmark> r;
  return r;
}

namespace {
double status_field(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(std::strlen(key))) * 1024.0;
  return 0;
}
}  // namespace

double peak_rss_bytes() { return status_field("VmHWM:"); }
double current_rss_bytes() { return status_field("VmRSS:"); }
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace cellform::bench

int main(int argc, char** argv) {
  using namespace cellform::bench;
  std::vector<std::string> names;
  std::string json_path;
  bool json_given = false, list = false;
  int reps_override = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--json" || a == "--repetitions") && i + 1 >= argc) {
      std::cerr << "cellform-bench: " << a << " needs a value\n";
      return 2;
    }
    // a value that is an option (--json --list) was taken as the file name, and every benchmark ran
    if ((a == "--json" || a == "--repetitions") && std::string_view(argv[i + 1]).starts_with("--")) {
      std::cerr << "cellform-bench: " << a << " needs a value, got the option '" << argv[i + 1] << "'"
                << (a == "--json" ? std::string(" (a file named so: ./") + argv[i + 1] + ")" : std::string()) << "\n";
      return 2;
    }
    if ((a == "--json" && json_given) || (a == "--repetitions" && reps_override > 0)) {
      std::cerr << "cellform-bench: " << a << " is given twice; give it once\n";
      return 2;
    }
    if (a == "--json") {
      json_path = argv[++i];
      json_given = true;
    } else if (a == "--repetitions") {
      const std::string v = argv[++i];
      long n = 0;
      const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
      if (ec != std::errc() || end != v.data() + v.size() || n < 1 || n > 1000000) {
        std::cerr << "cellform-bench: --repetitions needs a whole number from 1 to 1000000, got '" << v << "'\n";
        return 2;
      }
      reps_override = static_cast<int>(n);
    } else if (a == "--list") {
      list = true;
    } else if (a == "-h" || a == "--help") {
      std::cout << "usage: cellform-bench [NAME-PREFIX...] [--json FILE] [--repetitions N] [--list]\n"
                   "Runs the benchmarks whose names start with a given prefix (all if none), prints the\n"
                   "median, min and max of several repetitions, and writes them as JSON (after each\n"
                   "benchmark, so that an interrupted or failed sweep keeps those that finished). A name\n"
                   "ending in '$' must match whole (venation.colonisation.poplar.0.7$ runs that one alone).\n"
                   "--list lists the benchmarks the prefixes choose, without running them.\n";
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "cellform-bench: unknown option '" << a << "'\n";
      return 2;
    } else if (a.empty() || a == "$") {  // "$NAME" with NAME unset would run every benchmark, for hours
      std::cerr << "cellform-bench: an empty NAME-PREFIX ('" << a
                << "') matches every benchmark; give none to run them all\n";
      return 2;
    } else
      names.push_back(a);
  }
  std::vector<const Benchmark*> chosen;
  for (const Benchmark& b : registry()) {
    bool match = names.empty();
    for (const std::string& n : names)
      match = match || (n.ends_with('$') ? b.name == n.substr(0, n.size() - 1) : b.name.rfind(n, 0) == 0);
    if (match) chosen.push_back(&b);
  }
  if (chosen.empty()) {
    std::cerr << "cellform-bench: no benchmark matches; see cellform-bench --list\n";
    return 2;
  }
  if (list) {
    for (const Benchmark* b : chosen) std::cout << b->name << "\t" << b->unit << "\t" << b->doc << "\n";
    return 0;
  }
  if (json_given) {  // before the benchmarks, which may take many minutes: a file can be made there
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path parent = json_path.empty() ? fs::path() : fs::absolute(json_path, ec).parent_path();
    // a file of our own, made anew (never one that is there, nor through a link), then removed
    auto can_make_file = [&] {
      const std::string probe = (parent / ".cellform-bench-probe-XXXXXX").string();
      std::vector<char> name(probe.begin(), probe.end());
      name.push_back('\0');
      const int fd = ::mkstemp(name.data());
      if (fd < 0) return false;
      ::close(fd);
      ::unlink(name.data());
      return true;
    };
    const char* problem = json_path.empty()                 ? "is empty"
                          : fs::is_directory(json_path, ec) ? "is a folder"
                          : !fs::is_directory(parent, ec)   ? "is in a folder that does not exist"
                          : !can_make_file()                ? "is in a folder where no file can be made"
                                                            : nullptr;
    if (problem) {
      std::cerr << "cellform-bench: --json '" << json_path << "' " << problem << "\n";
      return 2;
    }
  }
  nlohmann::json results = nlohmann::json::array();
  auto write_json = [&] {  // the results so far, replacing the file whole
    if (!json_given) return true;
    try {
      cellform::core::write_file_atomically(json_path, [&](std::ostream& os) {
        // complete: false while benchmarks chosen are still to run (an interrupted sweep's file says so)
        os << nlohmann::json{{"results", results}, {"complete", results.size() == chosen.size()}}.dump(2) << "\n";
      });
      return true;
    } catch (const std::exception& e) {
      std::cerr << "cellform-bench: " << e.what() << "\n";
      return false;
    }
  };
  // at once: an earlier sweep's file there (complete: true) must not outlive a first benchmark that fails
  if (!write_json()) return 1;
  int width = 9;  // the name column, as wide as the longest name chosen
  for (const Benchmark* b : chosen) width = std::max(width, static_cast<int>(b->name.size()));
  std::printf("%-*s %14s %14s %14s  %s\n", width, "benchmark", "median", "min", "max", "unit");
  for (const Benchmark* b : chosen) {
    const int reps = reps_override > 0 ? reps_override : b->repetitions;
    std::vector<double> v;
    try {
      for (int r = 0; r < reps; ++r) v.push_back(b->run());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cellform-bench: %s failed: %s\n", b->name.c_str(), e.what());
      return 1;
    }
    std::sort(v.begin(), v.end());
    const double median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    std::printf("%-*s %14.4g %14.4g %14.4g  %s\n", width, b->name.c_str(), median, v.front(), v.back(),
                b->unit.c_str());
    std::fflush(stdout);
    results.push_back({{"name", b->name},
                       {"value", median},
                       {"unit", b->unit},
                       {"min", v.front()},
                       {"max", v.back()},
                       {"repetitions", reps}});
    if (!write_json()) return 1;
  }
  return 0;
}
