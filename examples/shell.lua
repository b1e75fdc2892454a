-- A shell grown under reverse gravity from a ground plane: a ring of fixed cells on the ground
-- anchors the sheet, an upward unary force lifts it, and growth at the rim pushes in more sheet than
-- a smooth vault holds, so it buckles into a ruffled, folded canopy (cells.obj, the one-layer surface,
-- is open where folds crowd each other; see examples/ribbed_shell.lua for a lower vault with ribs).
-- The print thickens every triangle of the sheet into one closed solid.

local P = params {
  size = 6000,
  lift = 0.008,   -- upward acceleration (model units per time unit squared); at 0.02 the sheet, grown to 6000
                  -- cells, pulled free of its supports (a note says so) and the print had nothing to stand on
}

run { steps = 1500, seed = 2 }

cells {
  rest_length = 1.0,
  time_step = 0.15,
  spring = 1.0,
  planar = 0.6,
  separation = 0.05,
  unary = {0, 0, P.lift},       -- reverse gravity
  drag = {0.85, 0.85, 0.85},
}

division {
  trigger = "neighbours",  -- growth at the rim
  -- radius (neighbours counted within it): 1.25 rest lengths unless given, so it follows cells.rest_length
  min_neighbours = 6,
  min_age = 5,
  probability = 0.3,
  direction = "tangent",
  max_cells = P.size,
}

ground { height = 0 }
disc { radius = 6, centre = {0, 0, 0.5} }

-- the supports: fixed cells around the rim of the footprint
for i = 0, 11 do
  local a = i / 12 * 2 * math.pi
  cell { at = {7 * math.cos(a), 7 * math.sin(a), 0.5}, fixed = true }
end

print { veins = false, shell = true, fill_cavities = true, size = 120 }
