// Cells to bytes and back, for checkpoints.
#pragma once

#include <string>

#include "cells/cells.h"

namespace cellform::cells {

/// Every per-cell array, bit for bit.
std::string save(const Cells& cells);

/// Inverse of save(); core::FileError naming `what` if the bytes are inconsistent.
Cells load(const std::string& bytes, const std::string& what);

}  // namespace cellform::cells
