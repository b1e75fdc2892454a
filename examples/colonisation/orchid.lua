-- Orchid (Runions et al. 2005, Table 1 row "Orchid", Figure 14 left): closed venation with
-- hierarchically organised primary and secondary veins and ladder-like tertiary veins in a long, narrow
-- leaf that does not grow (the sources are thrown into the full-size blade).
-- Table 1: closed, d_k = 1, b_s = b_v = 10, leaf length L_i = 6500, no growth,
-- rho = 600 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies the leaf length (d_k, b_s and rho stay, in vein segments). The full size takes
-- far longer (vein nodes grow with the leaf area, 1 / scale^2): the default, scale = 0.3, makes the leaf
-- 1950 long (on one core here: growth 2.7 s, print 2.8 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins fuse into a plate; `--set scale=0.1` (a smaller leaf, fewer veins) prints its veins
-- apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.3,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 15 }

leaf { shape = "ellipse", width = 0.3 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 10,  -- b_s = b_v
  growth = "none",
  initial_length = 6500 * P.scale,  -- L_i
  darts = 600,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
