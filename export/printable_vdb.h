// Private to export/ (and its tests): the level set's OpenVDB grid, shared by printable.cpp (voxelising) and
// printable_mesh.cpp (meshing), the only files of cellform that include OpenVDB (its headers are heavy).
#pragma once

#include <openvdb/openvdb.h>

#include <limits>
#include <mutex>

#include "export/printable.h"

namespace cellform::exporters {

struct LevelSet::Impl {
  openvdb::FloatGrid::Ptr grid;
  double voxel_size = 0;
  double scale = 0;
  std::size_t active_voxels = 0;
  double base_z = std::numeric_limits<double>::quiet_NaN();  ///< mm: the flat_base cut plane, NaN without one
};

namespace detail {

/// openvdb::initialize(), once per process.
inline void init_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

}  // namespace detail

}  // namespace cellform::exporters
