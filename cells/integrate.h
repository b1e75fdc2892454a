// Private: the integrator with the fastest speed reported back (for StepReport).
#pragma once

#include <cstdint>

#include "cells/cells.h"
#include "cells/params.h"

namespace cellform::cells {

/// integrate() that also returns the largest speed after the step (model units per time unit).
double integrate_and_measure(Cells& cells, const Params& params, std::uint64_t step, int threads);

}  // namespace cellform::cells
