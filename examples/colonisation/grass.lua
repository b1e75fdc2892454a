-- Grass (Runions et al. 2005, Table 1 row "Grass", Figures 14 right and 17): parallel venation in a
-- segment of a grass leaf (a strip read from grass_segment.txt): a row of initial vein nodes along the
-- base instead of one, and a birth distance tuned to the distance between the veins. No growth.
-- Table 1: closed, d_k = 1, b_s = b_v = 30, leaf length L_i = 13,000, no growth,
-- rho = 100 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies the leaf length (d_k, b_s and rho stay, in vein segments). The full size takes
-- far longer (vein nodes grow with the leaf area, 1 / scale^2): the default, scale = 0.3, makes the leaf
-- 3900 long (on one core here: growth 1.9 s, print 2.6 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins fuse into a plate; `--set scale=0.15` (a smaller leaf, fewer veins) prints its veins
-- apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.3,  -- fraction of Table 1's leaf size (1 = the paper's)
  veins = 0,     -- initial vein nodes along the base (0 = one per b_s of base width: parallel veins)
}

run { seed = 17 }

local length = 13000 * P.scale
local seeds = P.veins > 0 and P.veins or math.max(2, math.floor(0.24 * length / 30 + 0.5))
leaf { file = "grass_segment.txt", seeds = seeds, seed_spread = 0.24 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 30,  -- b_s = b_v
  growth = "none",
  initial_length = length,  -- L_i
  darts = 100,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
