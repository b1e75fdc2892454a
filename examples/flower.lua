-- A crumpled, flower-like disc: its cells split around its centre (circumferential anisotropic
-- growth), so the rim lengthens faster than the radius and the disc crumples into a thick, ruffled mass
-- (growth in the whole sheet outruns the springs: cells pack about half a rest length apart).

local P = params {
  size = 7000,
}

run { steps = 500, seed = 5 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 0.5,
  separation = 0.05,
  drag = {0.85, 0.85, 0.85},
}

division {
  trigger = "age",
  age = 25,
  min_age = 10,
  probability = 0.4,
  direction = "circumferential",
  axis = {0, 0, 1},
  centre = {0, 0, 0},
  max_cells = P.size,
}

disc { radius = 5 }
petiole { at = {0, 0, 0} }
