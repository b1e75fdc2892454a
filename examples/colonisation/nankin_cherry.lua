-- Nankin cherry, Prunus tomentosa (Runions et al. 2005, Table 1 row "Nankin cherry", Figure 16):
-- open venation in an elliptic, serrate blade growing at its margin.
-- Table 1: open, d_k = 30, b_s = b_v = 1, L_i = 1100, marginal growth to L_f = 5500
-- by Delta L = 11 per step, rho = 40 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.2, grows the leaf from 220 to 1100 (on one core here:
-- growth 0.3 s, print 1.6 s); `--set scale=1` gives the paper's size: 320,000 nodes in about 30 s here
-- (the margin outruns the veins and sources pile up, so the time grows faster than the nodes).
-- Printed 120 mm across, every vein is raised to print.min_radius (0.4 mm): the fine veins merge into
-- the main ones, which print apart (veins.svg and veins.png keep the widths).

local P = params {
  scale = 0.2,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 16 }

leaf { shape = "ellipse", width = 0.55, teeth = 60, tooth_depth = 0.01 }

colonisation {
  type = "open",
  kill_distance = 30,   -- d_k
  birth_distance = 1,  -- b_s = b_v
  growth = "marginal",
  initial_length = 1100 * P.scale,  -- L_i
  final_length = 5500 * P.scale,  -- L_f
  length_step = 11 * P.scale,  -- Delta L
  darts = 40,  -- rho x 10^6
  murray_exponent = 2,
  node_flow = 0.05,  -- Section 3.5: main veins widened for the veinlets this open pattern leaves out
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
