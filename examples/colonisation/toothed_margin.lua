-- Toothed margin (Runions et al. 2005, Table 1 row "Toothed margin", Figure 13 left): closed venation
-- with anastomoses in a toothed leaf with a lobe on each side; the veins extend into the lobes and
-- teeth. Table 1: closed, d_k = 1, b_s = b_v = 10, L_i = 6600, marginal growth to L_f = 26,000
-- by Delta L = 40 per step, rho = 10 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.1, grows the leaf from 660 to 2600 (on one core here:
-- growth 3.5 s, print 6.9 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins fuse into a plate; `--set scale=0.03` (a smaller leaf, fewer veins) prints its veins
-- apart, with space between most of them (veins closer than their widths fuse).
-- It ends "stalled" with 151 sources left outside the grown blade, below the lobes and teeth: the young
-- blade, growing at its margin, covered them where the grown one leaves a gap (docs/scripting.md, growth).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.1,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 13 }

leaf { shape = "lobed", lobes = 1, lobe_depth = 0.3, width = 0.7, teeth = 36, tooth_depth = 0.015 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 10,  -- b_s = b_v
  growth = "marginal",
  initial_length = 6600 * P.scale,  -- L_i
  final_length = 26000 * P.scale,  -- L_f
  length_step = 40 * P.scale,  -- Delta L
  darts = 10,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
