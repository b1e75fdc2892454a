// The cell population as plain data: structure of arrays, one slot per cell.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/types.h"

namespace cellform::cells {

using core::Index;
using core::kNoIndex;
using core::Vec3;

/// Cell types of the cell-division venation paper, section "Cell Differentiation".
enum class CellType : std::uint8_t {
  general = 0,  ///< meristem-like cell: divides, produces auxin, may turn into any other type
  petiole = 1,  ///< start point of the form and sink of the auxin flow; may be fixed
  vein = 2,     ///< formed by canalisation; has a vein parent and children and straightens between them
};

/// All cells. Every per-cell vector has size() entries; `links` has size() * link_stride.
/// Indices change when cells are reordered in memory; `id` never does.
struct Cells {
  std::vector<Vec3> position;             ///< model units
  std::vector<Vec3> velocity;             ///< model units per time unit
  std::vector<Vec3> acceleration;         ///< model units per time unit squared (last computed)
  std::vector<std::uint32_t> age;         ///< steps since birth or last division
  std::vector<std::uint32_t> generation;  ///< divisions between the initial cell and this one
  std::vector<CellType> type;
  std::vector<std::uint8_t> fixed;  ///< 1 = static cell: never moves, still divides if its rule says so
  std::vector<std::uint64_t> id;    ///< stable identity, shown to users ("cell 812")
  std::vector<Index> vein_parent;   ///< vein parent of a vein cell (kNoIndex for roots and non-vein cells)

  /// k nearest cells of each cell, sorted by distance, padded with kNoIndex; stride = link_stride.
  std::vector<Index> links;
  int link_stride = 6;

  /// Named per-cell scalars (e.g. "flow", or ones set by script rules); resized, copied to daughters
  /// and reordered with the cells.
  std::map<std::string, std::vector<double>> attributes;

  std::uint64_t next_id = 0;  ///< id given to the next new cell

  std::size_t size() const { return position.size(); }
};

/// Appends a cell with zero velocity and no links; returns its index.
Index add_cell(Cells& cells, const Vec3& position, CellType type = CellType::general, bool fixed = false);

/// Adds (or finds) a named per-cell attribute filled with `initial`; returns it.
std::vector<double>& attribute(Cells& cells, const std::string& name, double initial = 0.0);

/// Vein children of every cell in compressed form: the children of i are
/// child[start[i] .. start[i+1]), in increasing index order.
struct VeinChildren {
  std::vector<Index> start;
  std::vector<Index> child;
};
/// The vein children of every cell (its cells whose vein_parent it is), in O(cells).
VeinChildren vein_children(const Cells& cells);

/// Reorders all per-cell data by perm (perm[new] = old) and remaps every stored index.
void reorder(Cells& cells, const std::vector<Index>& perm);

}  // namespace cellform::cells
