// Auxin-flux canalisation inside the cell system (cell-division venation paper, "Venation Growth").
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "cells/cells.h"

namespace cellform::venation {

using cells::Cells;
using core::Index;
using core::kNoIndex;
using core::Vec3;

/// Parameters of canalisation. Flows are in units of auxin per step (one general cell makes `source`).
struct Params {
  double threshold =
      40.0;  ///< flow a cell next to a vein must exceed to become a vein cell (≈ upstream cells); sets vein spacing
  double source = 1.0;         ///< auxin each cell produces per step (every cell is an equal source)
  double murray_exponent = 3;  ///< n of Murray's law r_parent^n = sum r_child^n (2 or 3 typical)
  double radius_scale = 0.05;  ///< model units: radius of a vein carrying unit flow; r = radius_scale * flow^(1/n)
  double min_radius = 0.05;    ///< model units: no vein is thinner
  std::uint32_t every = 1;     ///< steps between canalisation passes (the scene runs it when step % every == 0)
};

/// Throws core::InvalidInput naming "venation.<name>" and what is allowed.
void validate(const Params& params);

/// Per-cell source strength; empty = params.source for every cell. Must return a finite number >= 0.
using SourceRule = std::function<double(const Cells&, Index)>;

/// What one canalisation step did.
struct Report {
  std::size_t promoted = 0;     ///< cells that became vein cells this step
  std::size_t vein_cells = 0;   ///< vein cells after the step (petioles not counted)
  double total_source = 0;      ///< auxin produced by the cells connected to a petiole
  double petiole_inflow = 0;    ///< auxin arriving at all petioles (equals total_source)
  std::size_t unconnected = 0;  ///< cells with no path to any petiole (their auxin goes nowhere)
  std::size_t cells = 0;        ///< cells at that step
};

/// Scratch kept between steps so a step allocates nothing once warm.
struct Workspace {
  std::vector<Index> row;                 // per cell: its neighbours in search order, link_stride + 1 wide
  std::vector<std::uint32_t> row_info;    // per cell: row length, leading mutual lower neighbours, flags
  std::vector<Index> extra_start, extra;  // one-way in-links per target cell (CSR, sources ascending)
  struct Chunk {
    std::vector<std::array<Index, 2>> extra;  // (target, source) of one-way links from this chunk
    std::vector<Index> veins;                 // vein nodes of this chunk, ascending
    std::vector<Index> promoted_cells;        // cells of this chunk promoted this step, ascending
    std::size_t promoted = 0, vein_cells = 0, unconnected = 0;
  };
  std::vector<Chunk> chunks;        // fixed cell ranges, independent of the thread count
  std::vector<std::uint8_t> layer;  // breadth-first layer code (see canalisation.cpp)
  std::vector<Index> queue;         // vein nodes, then the other reached cells in breadth-first order
  std::vector<Index> candidates;    // neighbours in the previous layer of the cell being placed
  std::vector<double> source, key;
  std::vector<Index> downstream;  // chosen downstream neighbour of each reached non-vein cell
  std::vector<Index> vein_id, vein_start, vein_child, vein_order, vein_fill;  // the vein forest
  std::vector<Index> promoted_start, promoted_child;  // the cells promoted this step, by vein parent
};

/// Names of the per-cell attributes canalisation maintains in Cells::attributes.
inline constexpr const char* kFlow = "flow";           ///< auxin flow through the cell (per step)
inline constexpr const char* kRadius = "vein_radius";  ///< Murray radius of vein cells, model units (0 elsewhere)
inline constexpr const char* kOrder = "vein_order";    ///< 1 = primary, 2 = secondary, ... (0 = not a vein)
inline constexpr const char* kFlowX = "flow_dx";       ///< unit direction of the flow (towards downstream)
inline constexpr const char* kFlowY = "flow_dy";
inline constexpr const char* kFlowZ = "flow_dz";

/// Adds the per-cell attributes canalise() writes (the six above), zero where missing: a cell file written
/// before canalisation's first pass then has the layout of the later ones.
void add_attributes(cells::Cells& c);
/// Whether the cells carry all six attributes add_attributes() adds.
bool has_attributes(const cells::Cells& c);

/// One step of canalisation, in the paper's two phases, in time linear in the number of cells and links.
///  1. Towards the veins: starting at the cells adjacent to a vein and moving outward layer by layer
///     (breadth first over the links), each cell picks as downstream the neighbour of the previous
///     layer with the largest flow so far (for the first layer: the neighbouring vein cell with the
///     largest vein flow of the previous step, since this step's vein flows are totals known only after
///     phase 2); ties go to the smaller index. Within a layer, cells are taken in the order the
///     breadth-first search reached them (deterministic). Its auxin is added to that neighbour and,
///     transitively, to everything downstream. Two cells are neighbours here if either links to the
///     other (the symmetric closure of the links, vein parents included), so a one-way link cuts no cell
///     off; the forces use each cell's own links only.
///  2. Through the veins: flows accumulate from the vein tips to the petioles.
/// Then every cell adjacent to a vein whose flow exceeds the threshold becomes a vein cell whose vein
/// parent is its downstream vein cell. Petiole cells are the sinks and roots of the vein forest. Orders
/// are found last, on the forest with the new vein cells: the roots' children are primary; at any other
/// vein node the child of the largest flow (ties: the smaller index) keeps its order, the others take the
/// next.
/// Writes the attributes above. Throws core::InvalidInput if there is no petiole, or a source rule
/// returns a negative or non-finite value (naming the cell id). The per-cell passes run on up to
/// `threads` threads (0 = all cores, 1 = serial; the source rule is always called serially, in index
/// order); the results are bit-identical for any thread count.
Report canalise(Cells& cells, const Params& params, const SourceRule& source, Workspace& workspace, int threads = 0);

/// Radius from flow: max(min_radius, radius_scale * flow^(1/n)). With the flow additive along the vein
/// tree, r_parent^n = sum of r_child^n over every inflow (vein children and the cells draining in).
double murray_radius(double flow, const Params& params);

/// The vein graph as a polyline set: nodes are vein and petiole cells, edges join each to its parent.
struct VeinGraph {
  std::vector<Index> cell;  ///< node -> cell index
  std::vector<Vec3> position;
  std::vector<double> flow, radius;
  std::vector<int> order;
  std::vector<std::array<std::uint32_t, 2>> edges;  ///< (child node, parent node)
};
/// Flow, radius and order come from the attributes canalise() writes. Before any pass (no such attributes)
/// every node has flow 0, the radius of that flow (murray_radius with `params`; 0 without them) and, as a
/// pass would give a petiole that roots no vein, order 1 for a root.
VeinGraph vein_graph(const Cells& cells, const Params* params = nullptr);

}  // namespace cellform::venation
