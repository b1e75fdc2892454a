-- Slow marginal growth (Runions et al. 2005, Table 1 row "Slow marginal growth", Figure 9i): open
-- venation whose vein tips closely follow a slowly growing margin, each fed by the sources along its own
-- stretch of margin (parameters otherwise like Figure 9b).
-- Table 1: open, d_k = 40, b_s = b_v = 1, L_i = 4500, marginal growth to L_f = 112,000
-- by Delta L = 34 per step, rho = 300 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf area,
-- 1 / scale^2): the default, scale = 0.03, grows the leaf from 135 to 3360 (about 11 s here);
-- `--set scale=1` gives the paper's size.
-- Larger scales are much slower: sources pile up ahead of the veins (scale = 0.05 had not finished
-- after 150 s).
-- One departure: b_v = d_k = 40 instead of 1. The paper reveals precomputed sources at the growing
-- margin; here darts fall on the whole blade every step, and with b_v = 1 each dart landing within d_k
-- of a vein would still pull one vein node before it is removed, covering the blade in short spurs.

local P = params {
  scale = 0.03,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 9 }

leaf { shape = "ovate", width = 0.6 }

colonisation {
  type = "open",
  kill_distance = 40,   -- d_k
  birth_distance = 1,  -- b_s
  vein_birth_distance = 40,  -- b_v = d_k, see above (Table 1: 1)
  growth = "marginal",
  initial_length = 4500 * P.scale,  -- L_i
  final_length = 112000 * P.scale,  -- L_f
  length_step = 34 * P.scale,  -- Delta L
  darts = 300,  -- rho x 10^6
  murray_exponent = 2,
}

print { formats = "stl" }
