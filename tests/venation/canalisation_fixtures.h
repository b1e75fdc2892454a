// Small sheets shared by the canalisation tests (canalisation_test.cpp): a chain, a hex leaf, and repeated passes.
#pragma once

#include <cstddef>
#include <vector>

#include "cells/cells.h"
#include "tests/fixtures.h"
#include "venation/canalisation.h"

namespace cellform::test {

/// A chain of n cells along x, each linked to its predecessor and successor, petiole at index 0.
inline cells::Cells chain(int n) {
  cells::Cells c;
  c.link_stride = 2;
  for (int i = 0; i < n; ++i) cells::add_cell(c, core::Vec3(i, 0, 0));
  for (int i = 0; i < n; ++i) {
    c.links[2 * i] = i > 0 ? static_cast<core::Index>(i - 1) : core::kNoIndex;
    c.links[2 * i + 1] = i + 1 < n ? static_cast<core::Index>(i + 1) : core::kNoIndex;
  }
  c.type[0] = cells::CellType::petiole;
  return c;
}

inline const std::vector<double>& attr(const cells::Cells& c, const char* name) { return c.attributes.at(name); }

/// Runs canalisation `steps` times on a fixed sheet.
inline venation::Report grow(cells::Cells& c, const venation::Params& p, int steps) {
  venation::Workspace ws;
  venation::Report r;
  for (int s = 0; s < steps; ++s) r = venation::canalise(c, p, {}, ws);
  return r;
}

/// The hex sheet with a petiole in the middle of its bottom row.
inline cells::Cells leaf(int rows, int cols) {
  cells::Cells c = testing::hex_sheet(rows, cols);
  testing::link_lattice(c);
  c.type[static_cast<std::size_t>(cols / 2)] = cells::CellType::petiole;
  return c;
}

}  // namespace cellform::test
