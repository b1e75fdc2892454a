-- A standing column of veins: open space colonisation (Runions et al. 2005) in a 3-D volume instead of
-- a leaf blade. Auxin sources appear anywhere in a box standing on the ground; the veins start from one
-- seed in the middle of its floor and branch towards the sources until the box is filled, forming a
-- vase-like lattice. Every vein joins the seed, so the thickened veins (Murray widths) print as one
-- standing piece. Lengths are in vein segments (D = 1); darts are per 10^6 unit^3 per step.

local P = params {
  width = 24,          -- side of the box's square floor
  height = 32,         -- height of the box
  spacing = 4,         -- b_s: distance between sources; larger gives fewer, coarser branches
  darts = 2000,        -- rho x 10^6 per unit^3 per step
}

run { seed = 4 }

volume {
  box = { min = {-P.width / 2, -P.width / 2, 0}, max = {P.width / 2, P.width / 2, P.height} },
  seeds = {{0, 0, 0}},
}

colonisation {
  type = "open",
  kill_distance = 2,
  birth_distance = P.spacing,
  darts = P.darts,
  murray_exponent = 2.5,
  tip_radius = 0.25,
}

print { formats = "stl", pieces = "one", min_radius = 0.6, flat_base = 1 }  -- stands on a flat foot
