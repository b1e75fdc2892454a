-- Reticulate pattern (Runions et al. 2005, Table 1 row "Reticulate pattern", Figure 15): closed venation
-- with a fine reticulate net of tertiary veins in an isogonically (uniformly) growing ovate leaf. Every
-- source pulls all vein nodes in its relative neighbourhood (Eq. 2), so veins converge on shared sources
-- and join into loops.
-- Table 1: closed, d_k = 1, b_s = b_v = 15, L_i = 225, isogonic growth to L_f = 4500
-- by Delta L = 40.5 per step, rho = 200 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.5, grows the leaf from 112.5 to 2250 (on one core here:
-- growth 3 s, print 4 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins fuse into a plate; `--set scale=0.1` (a smaller leaf, fewer veins) prints its veins
-- apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.5,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 5 }

leaf { shape = "ovate", width = 0.7 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 15,  -- b_s = b_v
  growth = "isogonic",
  initial_length = 225 * P.scale,  -- L_i
  final_length = 4500 * P.scale,  -- L_f
  length_step = 40.5 * P.scale,  -- Delta L
  darts = 200,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
