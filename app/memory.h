// How much memory the process may still take: the limits a print is checked against before it starts.
#pragma once

#include <filesystem>
#include <istream>
#include <limits>
#include <string>

namespace cellform::app {

/// Bytes: the lowest memory limit of the control groups `cgroup` (the text of /proc/self/cgroup) names, from
/// each group up to the root, read under `root` (/sys/fs/cgroup): memory.max (v2) or memory/.../
/// memory.limit_in_bytes (v1); infinity if none is set ("max", a missing file).
double control_group_memory_limit(std::istream& cgroup, const std::filesystem::path& root);

/// Bytes: the least any of those groups has left below its limit (the limit less the group's usage,
/// memory.current or memory.usage_in_bytes beside it, which counts every process of the group, less the inactive
/// file cache memory.stat gives, which the kernel reclaims); infinity if none is limited.
double control_group_memory_left(std::istream& cgroup, const std::filesystem::path& root);

/// Bytes of memory reading a byte of a mesh file (OBJ or STL) takes at the peak, and of an outline file: 3.2 and
/// 6.3 measured on files of a gigabyte (December 2026, the OBJ through OpenMesh's reader; forms::parse_obj, which
/// reads OBJ now, holds about 1.3: positions, corners and faces of a 132 MB file), rounded up.
inline constexpr double kMeshBytesPerByte = 4;
inline constexpr double kOutlineBytesPerByte = 7;

/// Bytes the process may still take, and how a message names that bound ("what ulimit -v leaves this process").
struct MemoryHeadroom {
  double bytes = std::numeric_limits<double>::infinity();
  std::string name;
};

/// The tightest of the bounds, each in bytes (infinity or NaN where not known): the address-space limit
/// (ulimit -v) less the process's address space; what the control groups have left; the machine's available
/// memory and free swap.
MemoryHeadroom tightest_headroom(double address_limit, double address_used, double group_left,
                                 double machine_available);

/// tightest_headroom() of this process now (getrlimit, /proc/self/statm, /proc/self/cgroup, /proc/meminfo).
MemoryHeadroom memory_headroom();

/// Throws core::InvalidInput when reading a file of `file_bytes` bytes takes more than `room`: about
/// `per_byte` bytes of memory a byte of it. `what` names the file in the message ("mesh 'site.obj'").
void check_file_fits(double file_bytes, double per_byte, const MemoryHeadroom& room, const std::string& what);

/// check_file_fits() of the file at `path` (when its size can be read) against memory_headroom(): a file of
/// gigabytes is refused before it is read, rather than running the machine out of memory a minute later.
void check_file_fits(const std::filesystem::path& path, double per_byte, const std::string& what);

}  // namespace cellform::app
