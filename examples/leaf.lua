-- A flat, waving leaf-like surface (the paper's figures 2 and 3).
-- Marginal growth: cells at the rim have few neighbours and divide. Strong drag in z keeps the sheet
-- nearly horizontal, so it grows out as a broad blade that ripples where the rim grows faster than
-- the middle can make room.

local P = params {
  size = 6000,       -- cells at the end of growth
  vertical_drag = 0.2, -- velocity factor in z per step (1 = free, 0 = flat)
}

run { steps = 600, seed = 1 }

cells {
  rest_length = 1.0,
  time_step = 0.2,
  spring = 1.0,
  planar = 0.6,
  separation = 0.05,
  drag = {0.85, 0.85, P.vertical_drag},
}

division {
  trigger = "neighbours",  -- rim cells have fewer neighbours nearby
  radius = 1.6,
  min_neighbours = 6,
  min_age = 6,
  probability = 0.5,
  max_cells = P.size,
}

disc { radius = 4 }
petiole { at = {0, -4, 0} }

output { every = 0 }
