-- Trillium petal (Runions et al. 2005, Table 1 row "Trillium", Figure 21): closed venation in a
-- broad, pointed petal that does not grow (venation is not limited to leaves).
-- Table 1: closed, d_k = 1, b_s = b_v = 30, leaf length L_i = 4500, no growth,
-- rho = 100 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies the leaf length (d_k, b_s and rho stay, in vein segments). The full size takes
-- far longer (vein nodes grow with the leaf area, 1 / scale^2): the default, scale = 0.6, makes the leaf
-- 2700 long (on one core here: growth 2.5 s, print 4.5 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins print as a dense lattice with small holes; `--set scale=0.3` (a smaller leaf,
-- fewer veins) prints its veins apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.6,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 21 }

leaf { shape = "ovate", width = 0.5 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 30,  -- b_s = b_v
  growth = "none",
  initial_length = 4500 * P.scale,  -- L_i
  darts = 100,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
