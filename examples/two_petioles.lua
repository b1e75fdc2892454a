-- A leaf with several petioles: two sinks from the start, and a third created while the blade grows
-- (the paper's "venation beams which connect between petiole cells"). Each petiole collects its own
-- vein tree; the trees meet where their catchments do.

local P = params {
  size = 6000,
  vein_spacing = 30,
}

run { steps = 1800, seed = 4 }

cells {
  time_step = 0.15,
  planar = 0.6,
  separation = 0.05,
  drag = {0.85, 0.85, 0.3},
}

division {
  trigger = "neighbours",
  radius = 1.25,
  min_neighbours = 6,
  min_age = 5,
  probability = 0.3,
  direction = "tangent",
  max_cells = P.size,
}

venation { threshold = P.vein_spacing }

rectangle { width = 14, height = 5 }
petiole { at = {-7, 0, 0} }
petiole { at = {7, 0, 0} }
-- a new sink appears in the middle of the growing blade; it collects the cells nearer to it than to any vein,
-- so it must come before the veins of the other two fill the middle (at step 600 it would get about 30 cells' auxin and
-- grow no vein: the run says so)
petiole { at = {0, 2, 0}, step = 140 }

print { formats = "stl", pieces = "any" }   -- one vein tree per petiole: separate pieces are expected
