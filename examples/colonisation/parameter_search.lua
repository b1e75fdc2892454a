-- The parameter searches of Figure 9 (Runions et al. 2005, Table 1 rows "Param. search d_k" and
-- "Param. search rho"): closed venation in an ovate leaf growing at its margin, varying one parameter.
-- Table 1: closed, b_s = b_v = 10, L_i = 270, marginal growth to L_f = 1,600 by Delta L = 8 per step,
-- Murray n = 2, and
--   panels a-e: d_k = 40, 20, 10, 5, 1 with rho = 600 x 10^-6 (denser veins, then loops, as d_k falls);
--   panels f-h: rho = 60, 300, 6000 x 10^-6 (0.00006, 0.0003, 0.006) with d_k = 1 (smoother veins).
-- `panel` picks a figure panel; `kill_distance` or `darts` (> 0) override its value. This is the
-- paper's full size (panel c on one core here: growth 1.6 s, print 3.1 s); `scale` multiplies L_i, L_f
-- and Delta L for quick looks.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins print as a dense lattice with small holes; `--set scale=0.3` (a smaller leaf,
-- fewer veins) prints its veins apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  panel = "c",        -- a, b, c, d, e (d_k search) or f, g, h (rho search)
  kill_distance = 0,  -- d_k; 0 = the panel's
  darts = 0,          -- rho x 10^6; 0 = the panel's
  scale = 1,          -- fraction of Table 1's leaf size (1 = the paper's)
}

local panels = {
  a = { kill_distance = 40, darts = 600 },
  b = { kill_distance = 20, darts = 600 },
  c = { kill_distance = 10, darts = 600 },
  d = { kill_distance = 5, darts = 600 },
  e = { kill_distance = 1, darts = 600 },
  f = { kill_distance = 1, darts = 60 },
  g = { kill_distance = 1, darts = 300 },
  h = { kill_distance = 1, darts = 6000 },
}
local chosen = panels[P.panel]
if not chosen then
  error("params.panel must be one of a, b, c, d, e, f, g, h (Figure 9), got '" .. P.panel .. "'")
end

run { seed = 9 }

leaf { shape = "ovate", width = 0.6 }

colonisation {
  type = "closed",
  kill_distance = P.kill_distance > 0 and P.kill_distance or chosen.kill_distance,  -- d_k
  birth_distance = 10,  -- b_s = b_v
  growth = "marginal",
  initial_length = 270 * P.scale,  -- L_i
  final_length = 1600 * P.scale,   -- L_f
  length_step = 8 * P.scale,       -- Delta L
  darts = P.darts > 0 and P.darts or chosen.darts,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
