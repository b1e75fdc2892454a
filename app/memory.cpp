// How much memory the process may still take (app/memory.h).
#include "app/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"

namespace cellform::app {

namespace {

/// A memory control group's files: its limit, its usage, and the statistics that split the usage.
struct GroupFiles {
  std::filesystem::path limit, usage, stat;
  bool v2;
};

/// Of each memory control group `cgroup` names, from its own up to the root.
std::vector<GroupFiles> group_files(std::istream& cgroup, const std::filesystem::path& root) {
  std::vector<GroupFiles> files;
  for (std::string line; std::getline(cgroup, line);) {  // "0::/path" (v2), "N:memory:/path" (v1)
    const std::size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
    if (b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1);
    if (!controllers.empty() && controllers.find("memory") == std::string::npos) continue;
    const bool v2 = controllers.empty();
    const std::filesystem::path base = v2 ? root : root / "memory";
    for (std::filesystem::path at = line.substr(b + 1);; at = at.parent_path()) {
      const std::filesystem::path dir = base / at.relative_path();
      files.push_back({dir / (v2 ? "memory.max" : "memory.limit_in_bytes"),
                       dir / (v2 ? "memory.current" : "memory.usage_in_bytes"), dir / "memory.stat", v2});
      if (at.empty() || at == at.parent_path()) break;
    }
  }
  return files;
}

/// The number a control group file holds; 0 if none ("max", a missing file).
double group_number(const std::filesystem::path& file) {
  std::ifstream in(file);
  double bytes = 0;
  return in >> bytes && bytes > 0 ? bytes : 0.0;
}

/// Bytes of the inactive file cache in a group's usage (memory.stat, v1's of the whole subtree), which the kernel
/// reclaims before it runs out: a build's cache is not memory taken (as Docker and Kubernetes count; the active
/// files hold programs' mapped pages too).
double group_file_cache(const GroupFiles& g) {
  std::ifstream in(g.stat);
  double cache = 0;
  std::string key;
  for (double bytes = 0; in >> key >> bytes;)
    if (key == (g.v2 ? "inactive_file" : "total_inactive_file")) cache += bytes;
  return cache;
}

}  // namespace

double control_group_memory_limit(std::istream& cgroup, const std::filesystem::path& root) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const GroupFiles& g : group_files(cgroup, root))
    if (const double bytes = group_number(g.limit); bytes > 0) lowest = std::min(lowest, bytes);
  return lowest;
}

double control_group_memory_left(std::istream& cgroup, const std::filesystem::path& root) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const GroupFiles& g : group_files(cgroup, root))
    if (const double bytes = group_number(g.limit); bytes > 0) {  // all the group's processes, not its file cache
      const double taken = std::max(group_number(g.usage) - group_file_cache(g), 0.0);
      lowest = std::min(lowest, std::max(bytes - taken, 0.0));
    }
  return lowest;
}

MemoryHeadroom tightest_headroom(double address_limit, double address_used, double group_left,
                                 double machine_available) {
  MemoryHeadroom room;
  const auto bound = [&](double limit, double used, const char* name) {
    if (!std::isfinite(limit)) return;
    const double left = std::max(limit - (std::isfinite(used) ? used : 0.0), 0.0);
    if (left < room.bytes) room = {left, name};
  };
  bound(address_limit, address_used, "what the address-space limit (ulimit -v) leaves this process");
  bound(group_left, 0, "what this container's memory limit leaves");
  bound(machine_available, 0, "this machine's available memory and swap");
  return room;
}

namespace {

/// Bytes of the "Name:  N kB" line of /proc/meminfo; NaN if there is none.
double meminfo_bytes(const std::string& text, const std::string& name) {
  const std::size_t at = text.find("\n" + name + ":");
  if (at == std::string::npos) return std::nan("");
  try {
    return std::stod(text.substr(at + name.size() + 2)) * 1024;
  } catch (const std::exception&) {
    return std::nan("");
  }
}

}  // namespace

void check_file_fits(double file_bytes, double per_byte, const MemoryHeadroom& room, const std::string& what) {
  const double need = file_bytes * per_byte;
  if (!(need > room.bytes)) return;
  const auto gb = [](double b) { return core::number_text(std::round(b / 1e8) / 10) + " GB"; };
  throw core::InvalidInput(what + " is " + gb(file_bytes) + ": reading it takes about " + gb(need) +
                           " of memory, more than " + room.name + " (" + gb(room.bytes) +
                           "); give a smaller file (fewer triangles or points)");
}

void check_file_fits(const std::filesystem::path& path, double per_byte, const std::string& what) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < (std::uintmax_t{1} << 26)) return;  // (64 MB: not worth reading the machine's limits for)
  check_file_fits(static_cast<double>(size), per_byte, memory_headroom(), what);
}

MemoryHeadroom memory_headroom() {
  const double page = static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  double address_limit = std::numeric_limits<double>::infinity();
  if (rlimit r{}; ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    address_limit = static_cast<double>(r.rlim_cur);
  double size = std::nan("");
  if (std::ifstream statm("/proc/self/statm"); statm >> size) size *= page;
  std::ifstream groups("/proc/self/cgroup");
  const double group_left = control_group_memory_left(groups, "/sys/fs/cgroup");
  std::ifstream meminfo("/proc/meminfo");
  std::string text(1, '\n');  // (each name is looked for after a line break)
  text.append(std::istreambuf_iterator<char>(meminfo), {});
  const double available = meminfo_bytes(text, "MemAvailable") + meminfo_bytes(text, "SwapFree");
  return tightest_headroom(address_limit, size, group_left, available);
}

}  // namespace cellform::app
