-- A flower-like form: a disc whose cells split around its centre (circumferential anisotropic growth)
-- ruffles into concentric petal-like folds, like a rose seen from above. A cell divides only while fewer
-- than 8 other cells lie within 1.5 model units, 1.5 rest lengths here (division "by amount of
-- neighbours"), so folds that press together stop growing and the form stays a sheet instead of packing
-- into a foam.

local P = params {
  size = 7000,
}

-- growth slows as the form fills out (about 1,500 steps to 7,000 cells, 2,200 to 30,000): the run
-- lengthens with size
run { steps = 1500 + math.max(0, math.floor(450 * math.log(P.size / 7000, 2))), seed = 5 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 1.0,
  separation = 0.05,
  drag = {0.85, 0.85, 0.85},
}

division {
  trigger = "neighbours",
  min_neighbours = 8,
  radius = 1.5,  -- model units: the second ring of a sheet at rest lies beyond it, at 1.73
  min_age = 10,
  probability = 0.4,
  direction = "circumferential",
  axis = {0, 0, 1},
  centre = {0, 0, 0},
  max_cells = P.size,
}

disc { radius = 5 }
petiole { at = {0, 0, 0} }

-- printed as one watertight shell of the sheet (0.6 mm walls, 120 mm across), perforated where the sheet has
-- gaps; on one core here the growth takes 2.5 s and the print 49 s
print { formats = "stl", shell = true, veins = false }
