-- Tertiary vein emergence (Runions et al. 2005, Table 1 row "Tertiary vein emergence", Figure 13
-- right): closed venation in an entire, elliptic leaf; sequences of tertiary veins grow towards the
-- margin off the bottom secondary veins.
-- Table 1: closed, d_k = 1, b_s = b_v = 1, L_i = 3500, marginal growth to L_f = 24,000
-- by Delta L = 60 per step, rho = 20 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.05, grows the leaf from 175 to 1200 (on one core here:
-- growth 0.8 s, print 3.7 s); `--set scale=1` gives the paper's size.
-- Made for veins.svg and veins.png: printed 120 mm across, with every vein raised to print.min_radius
-- (0.4 mm), the veins print as a dense lattice with small holes; `--set scale=0.02` (a smaller leaf,
-- fewer veins) prints its veins apart, with space between most of them (veins closer than their widths fuse).

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.05,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 14 }

leaf { shape = "ellipse", width = 0.55 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 1,  -- b_s = b_v
  growth = "marginal",
  initial_length = 3500 * P.scale,  -- L_i
  final_length = 24000 * P.scale,  -- L_f
  length_step = 60 * P.scale,  -- Delta L
  darts = 20,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
