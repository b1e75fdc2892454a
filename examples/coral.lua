-- A coral-like form: a sphere of cells grows into ruffled lobes that fold back onto themselves and form
-- new connections (a non-manifold surface). A cell divides only while fewer than 8 other cells lie within
-- 1.5 model units, 1.5 rest lengths here (the paper's division "by amount of neighbours"), so growth goes
-- where the sheet has room: a compressed patch or a fold pressed against another stops growing, and the
-- form stays a sheet instead of packing into a foam. Splits lie in the sheet (tangent).

local P = params {
  size = 8000,
}

-- growth slows as the form fills out (about 1,200 steps to 8,000 cells, 2,200 to 100,000): the run
-- lengthens with size
run { steps = 1500 + math.max(0, math.floor(300 * math.log(P.size / 8000, 2))), seed = 3 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 1.0,
  separation = 0.08,
  drag = {0.8, 0.8, 0.8},
}

division {
  trigger = "neighbours",
  min_neighbours = 8,
  radius = 1.5,          -- model units: the second ring of a sheet at rest lies beyond it, at 1.73
  min_age = 10,
  probability = 0.3,
  direction = "tangent",  -- random, within the sheet
  max_cells = P.size,
}

sphere { radius = 3 }

-- printed as one watertight shell of the sheet (0.6 mm walls, 120 mm across), perforated where the sheet has
-- gaps; on one core here the growth takes 4 s and the print 36 s
print { formats = "stl", shell = true, veins = false }
