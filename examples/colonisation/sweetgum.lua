-- Sweetgum, Liquidambar styraciflua (Runions et al. 2005, Table 1 row "Sweetgum", Figure 12): open,
-- actinodromous venation in a star-shaped (digitate) blade of five lobes.
-- Table 1: open, d_k = 1, b_s = b_v = 1, L_i = 1200, marginal growth to L_f = 6700
-- by Delta L = 7 per step, rho = 200 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.1, grows the leaf from 120 to 670 (on one core here:
-- growth 0.9 s, print 4.5 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins fuse into a plate; `--set scale=0.03` (a smaller leaf, fewer veins) prints its veins
-- apart, with space between most of them (veins closer than their widths fuse).
-- It ends "stalled" with 5 sources left, between teeth where no vein can step towards them (the step
-- would leave the blade across the notch); every other source is reached.

local P = params {
  scale = 0.1,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 12 }

leaf { shape = "palmate", lobes = 5, lobe_depth = 0.55, width = 1.5, teeth = 60, tooth_depth = 0.006 }

colonisation {
  type = "open",
  kill_distance = 1,   -- d_k
  birth_distance = 1,  -- b_s = b_v
  growth = "marginal",
  initial_length = 1200 * P.scale,  -- L_i
  final_length = 6700 * P.scale,  -- L_f
  length_step = 7 * P.scale,  -- Delta L
  darts = 200,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
