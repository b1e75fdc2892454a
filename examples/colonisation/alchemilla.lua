-- Lady's mantle, Alchemilla vulgaris (Runions et al. 2005, Table 1 row "Alchemilla", Figure 11):
-- open, actinodromous venation in a rounded, shallowly lobed blade growing at its margin.
-- Table 1: open, d_k = 10, b_s = b_v = 1, L_i = 3200, marginal growth to L_f = 4500
-- by Delta L = 9 per step, rho = 200 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.1, grows the leaf from 320 to 450 (on one core here:
-- growth 0.5 s, print 2.7 s); `--set scale=1` gives the paper's size.
-- Printed 120 mm across, every vein is raised to print.min_radius (0.4 mm): the fine veins merge into
-- the main ones, which print apart (veins.svg and veins.png keep the widths).
-- It ends "stalled" with 1 source left, inside the blade where no vein can step towards it (the step would
-- leave the blade or cross a sinus); every other source is reached.

local P = params {
  scale = 0.1,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 11 }

leaf { shape = "palmate", lobes = 9, lobe_depth = 0.1, width = 1.9, teeth = 90, tooth_depth = 0.008 }

colonisation {
  type = "open",
  kill_distance = 10,   -- d_k
  birth_distance = 1,  -- b_s = b_v
  growth = "marginal",
  initial_length = 3200 * P.scale,  -- L_i
  final_length = 4500 * P.scale,  -- L_f
  length_step = 9 * P.scale,  -- Delta L
  darts = 200,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
