-- A coral-like mass: uniform growth by age with little drag crumples the sheet into folds that
-- grow back onto themselves and form new connections (a non-manifold surface). Growth in the whole
-- sheet outruns the springs: the folds pack densely, cells about half a rest length apart.

local P = params {
  size = 8000,
}

run { steps = 500, seed = 3 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 0.4,
  separation = 0.08,
  drag = {0.8, 0.8, 0.8},
}

division {
  trigger = "age",
  age = 30,
  min_age = 10,
  probability = 0.3,
  direction = "random",   -- uniform growth
  max_cells = P.size,
}

sphere { radius = 3 }
