-- A ribbed vault: a low, ruffled shell of cells (about 43 x 33 x 14 rest lengths) grown under reverse gravity from a ring of supports on the ground
-- (as examples/shell.lua), then closed space colonisation (Runions et al. 2005) over the grown sheet
-- draws a net of ribs from the supports across it. The sheet is printed as a thin shell with the ribs
-- as its thickened veins: one piece.
-- Every source is reached. Other seeds (`--seed 1`) can end "stalled" with 1 source left behind a fold of
-- the sheet thinner than about 3 vein segments, which no vein on the other side can reach.

local P = params {
  size = 3000,       -- cells in the grown sheet
  spacing = 3,       -- b_s: distance between auxin sources on the sheet, in rest lengths
}

run { steps = 900, seed = 2 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 0.6,
  separation = 0.05,
  unary = {0, 0, 0.02},       -- reverse gravity lifts the sheet into a vault
  drag = {0.85, 0.85, 0.85},
}

division {
  trigger = "neighbours",
  -- radius (neighbours counted within it): 1.25 rest lengths unless given, so it follows cells.rest_length
  min_neighbours = 6,
  min_age = 5,
  probability = 0.3,
  direction = "tangent",
  max_cells = P.size,
}

ground { height = 0 }
disc { radius = 5, centre = {0, 0, 0.5} }
for i = 0, 5 do
  local a = i / 6 * 2 * math.pi
  cell { at = {6 * math.cos(a), 6 * math.sin(a), 0.5}, fixed = true }
  petiole { at = {6 * math.cos(a), 6 * math.sin(a), 0.5} }
end

surface { cells = true }

colonisation {
  type = "closed",
  kill_distance = 1,
  birth_distance = P.spacing,
  darts = 20000,
  murray_exponent = 2,
  tip_radius = 0.12,
}

print { formats = "stl", shell = true, pieces = "one", fill_cavities = true, flat_base = 2 }  -- 2 mm off the bottom: its six supports stand on flat feet
