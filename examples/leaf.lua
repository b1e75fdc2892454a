-- A flat, waving leaf with its veins, printed as its vein tree in one piece (the cell paper's figures 2 and 3;
-- docs/papers.md). Marginal growth: cells at the rim have few neighbours nearby and divide within the
-- sheet. Drag in z (the cell paper's Eq. 7) keeps the blade nearly horizontal while it waves a little
-- where the rim outgrows the middle.
-- Auxin flows from every cell to the petiole; where it concentrates, cells become veins, and the veins
-- are thickened with their Murray radii into printable.stl.

local P = params {
  size = 6000,          -- cells when growth stops
  vertical_drag = 0.3,  -- velocity factor in z per step: 0 = perfectly flat, 0.85 (the in-plane drag) buckles
                        -- freely (16 units high at 3000 cells); 1 damps nothing and the sheet flies apart upwards
  vein_spacing = 30,    -- canalisation threshold: upstream cells needed to make a vein
}

run { steps = 1800, seed = 1 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 0.6,
  separation = 0.05,
  drag = {0.85, 0.85, P.vertical_drag},
}

division {
  trigger = "neighbours",   -- marginal growth
  -- radius (neighbours counted within it): 1.25 rest lengths unless given, so it follows cells.rest_length
  min_neighbours = 6,
  min_age = 5,
  probability = 0.3,
  direction = "tangent",    -- daughters stay in the blade
  max_cells = P.size,
}

venation { threshold = P.vein_spacing }

disc { radius = 4 }
petiole { at = {0, -4, 0} }

print { veins = true, size = 120, formats = "stl,scad" }
