-- Slow marginal growth (Runions et al. 2005, Table 1 row "Slow marginal growth", Figure 9i): open
-- venation whose vein tips closely follow a slowly growing margin, each fed by the sources along its own
-- stretch of margin (parameters otherwise like Figure 9b).
-- Table 1: open, d_k = 40, b_s = b_v = 1, L_i = 4500, marginal growth to L_f = 112,000
-- by Delta L = 34 per step, rho = 300 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.02, grows the leaf from 90 to 2240 (on one core here:
-- growth 1 s, print 2 s). From scale = 0.03 the leaf tip moves more than a vein segment per step
-- (34 x 0.03 > 1): sources pile up ahead of the veins (0.03, on one core: growth 6 s, print 3 s, 18 s
-- in all with the sources precomputed and the files written). The
-- paper's size, `--set scale=1`, would precompute about 7 x 10^9 darts (rho for each of the 3,160 steps
-- over the final blade's box), more than the 10^9 allowed; the sources precomputed from them are held
-- to 5 x 10^7, so the largest scale that runs is about 0.08 (0.09 is refused).
-- One departure: b_v = d_k = 40 instead of 1. Sources appear at the growing margin (precomputed, as in
-- the paper), but rho darts per unit area for each of the 3,160 steps make about one dart per unit area,
-- nearly a b_s = 1 packing: with b_v = 1 each of the many sources the margin uncovers within d_k of a
-- vein pulls its own node before it is removed, and short twigs fill the blade. b_v = d_k drops those
-- sources, and the vein tips follow the margin, as in Figure 9i.
-- Printed 120 mm across, every vein is raised to print.min_radius (0.4 mm): the fine veins merge into
-- the main ones, which print apart (veins.svg and veins.png keep the widths).

local P = params {
  scale = 0.02,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 9 }

leaf { shape = "ovate", width = 0.6 }

colonisation {
  type = "open",
  kill_distance = 40,   -- d_k
  birth_distance = 1,  -- b_s
  vein_birth_distance = 40,  -- b_v = d_k, see above (Table 1: 1)
  growth = "marginal",
  initial_length = 4500 * P.scale,  -- L_i
  final_length = 112000 * P.scale,  -- L_f
  length_step = 34 * P.scale,  -- Delta L
  darts = 300,  -- rho x 10^6
  murray_exponent = 2,
  node_flow = 0.05,  -- Section 3.5: main veins widened for the veinlets this open pattern leaves out
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
