-- A coral-like 3-D form whose veins climb from a petiole on the ground: a small cap of cells sits on
-- the ground plane, grows upward under reverse gravity while its rim folds, and auxin drains down to the
-- fixed petiole at its foot, so the veins become the structural members of the standing form.
-- Growth by age packs the mound's cells densely (about 10 within a rest length, not a sheet's 6); its
-- veins, not its sheet, are what prints. Division by room, as in coral.lua, gives a looser sheet but a
-- low, spreading one whose veins wander sideways, and with some seeds it sheds a few cells.

local P = params {
  size = 8000,
  lift = 0.01,          -- reverse gravity, model units per time unit squared
  vein_spacing = 25,
}

run { steps = 1500, seed = 7 }

cells {
  time_step = 0.15,
  planar = 0.4,
  separation = 0.05,
  unary = {0, 0, P.lift},
  drag = {0.85, 0.85, 0.85},
}

division {
  trigger = "age",
  age = 40,
  min_age = 10,
  probability = 0.3,
  direction = "auxin",   -- non-uniform anisotropic growth along the auxin flow
  max_cells = P.size,
}

venation { threshold = P.vein_spacing }

ground { height = 0 }
disc { radius = 3, centre = {0, 0, 0.5} }
petiole { at = {0, 0, 0.5} }

-- 2.5 mm off the bottom: it stands on the flat feet of its lowest veins (cut 1 mm, it stood on one, and rocked
-- onto the others at a tilt of 2 to 3 degrees)
print { formats = "stl", pieces = "one", flat_base = 2.5 }
