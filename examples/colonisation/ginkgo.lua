-- Ginkgo (Runions et al. 2005, Table 1 row "Ginkgo", Figure 10): open venation in a fan-shaped blade
-- with a central notch (ginkgo_fan.txt), growing at its margin. The rounded, tangentially expanding
-- margin makes vein tips fork when they drift too far apart.
-- Table 1: open, d_k = 100, b_s = b_v = 1, L_i = 10, marginal growth to L_f = 50,000
-- by Delta L = 15 per step, rho = 300 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf area,
-- 1 / scale^2): the default, scale = 0.05, grows the leaf from 0.5 to 2500 (about 5 s here);
-- `--set scale=1` gives the paper's size.
-- Larger scales are much slower: the margin outruns the veins and sources pile up (scale = 0.1 had not
-- finished after 90 s).
-- One departure: b_v = d_k = 100 instead of 1. The paper reveals precomputed sources at the growing
-- margin; here darts fall on the whole blade every step, and with b_v = 1 each dart landing within d_k
-- of a vein would still pull one vein node before it is removed, covering the blade in short spurs.

local P = params {
  scale = 0.05,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 10 }

leaf { file = "ginkgo_fan.txt" }  -- a fan with a notch; no parametric shape has a wedge base

colonisation {
  type = "open",
  kill_distance = 100,   -- d_k
  birth_distance = 1,  -- b_s
  vein_birth_distance = 100,  -- b_v = d_k, see above (Table 1: 1)
  growth = "marginal",
  initial_length = 10 * P.scale,  -- L_i
  final_length = 50000 * P.scale,  -- L_f
  length_step = 15 * P.scale,  -- Delta L
  darts = 300,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl" }
