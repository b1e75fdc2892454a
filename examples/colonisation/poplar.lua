-- Poplar (Runions et al. 2005, Table 1 row "Poplar", Figures 18 and 19): a fine reticulate pattern in an
-- isogonically growing, broadly ovate (deltoid-like) leaf with a crenate margin.
-- Table 1: closed, d_k = 1, b_s = b_v = 2, L_i = 115, isogonic growth to L_f = 3500
-- by Delta L = 9 per step, rho = 200 x 10^-6 darts per unit area per step, Murray n = 2.
-- `scale` multiplies L_i, L_f and Delta L (same number of steps and relative growth per step; d_k,
-- b_s and rho stay, in vein segments). The full size takes far longer (vein nodes grow with the leaf
-- area, 1 / scale^2): the default, scale = 0.2, grows the leaf from 23 to 700 (on one core here:
-- growth 0.9 s, print 3.5 s); `--set scale=1` gives the paper's size: 3.9 million nodes, the veins in
-- 2.5 to 3.5 minutes on 2 cores (the machine's load varies) and the whole run with its print about a
-- minute more (see docs/benchmarks.md). Made for veins.svg and veins.png: printed 120 mm across, with
-- every vein raised to print.min_radius (0.4 mm), the veins fuse into a plate; `--set scale=0.05` (a
-- smaller leaf, fewer veins) prints its veins apart, with space between most of them (veins closer than
-- their widths fuse).
-- It ends "stalled" with 5 sources left, inside the blade where no vein can step towards them (the step
-- would leave the blade or run back along a vein); every other source is reached.

local P = params {
  neighbourhood = "exact",  -- or "urquhart", the approximation of Section 5.2 (slower here: up to 25 times in the presets, more in larger leaves; exact keeps sector bests)
  scale = 0.2,  -- fraction of Table 1's leaf size (1 = the paper's)
}

run { seed = 18 }

leaf { shape = "ovate", width = 0.85, teeth = 40, tooth_depth = 0.008 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,   -- d_k
  birth_distance = 2,  -- b_s = b_v
  growth = "isogonic",
  initial_length = 115 * P.scale,  -- L_i
  final_length = 3500 * P.scale,  -- L_f
  length_step = 9 * P.scale,  -- Delta L
  darts = 200,  -- rho x 10^6
  murray_exponent = 2,
  max_nodes = 5000000,  -- the full size grows 3.9 million nodes; the default limit stops at 2 million
}

-- The reticulum is finer than a print can be at 120 mm: veins b_s = 2 segments apart are 0.33 mm apart
-- at the default scale (about 0.07 mm at full size), under the 0.4 mm printable radius, so the leaf prints as a
-- closed plate with pinholes (a lattice needs a print several times larger, or a smaller leaf: above). At full size
-- 4.45 million segments thicken in about 47 s with 3 GB at the peak; the estimate before thickening says
-- 4.5 GB, above the default limit of 2000 MB, hence max_memory.
print { formats = "stl", lay_flat = true, max_memory = 5000 }
output { png = true }  -- veins.png, a preview of veins.svg
