-- An open (tree-like) venation pattern by space colonisation (Runions et al. 2005), in a toothed
-- ovate leaf growing at its margin: a scaled-down version of the paper's open patterns (Table 1:
-- Alchemilla, Sweetgum). Lengths are in vein segments (D = 1). Writes veins.svg for plotters and laser
-- cutters, the vein graph as PLY/OBJ, and the veins thickened into printable.stl.

local P = params {
  length = 120,        -- final leaf length in vein segments (the paper's leaves are 4,500 to 112,000)
  kill_distance = 1,   -- d_k: smaller gives more, denser veins
}

-- seed 4 reaches every source; with some seeds (3, 5) one source the young blade held lies below a tooth of
-- the grown one, out of every vein's reach, and the run ends "stalled" (docs/scripting.md, marginal growth)
run { seed = 4 }

leaf { shape = "ovate", width = 0.6, teeth = 12, tooth_depth = 0.03 }

colonisation {
  type = "open",
  kill_distance = P.kill_distance,
  birth_distance = 3,          -- b_s = b_v
  growth = "marginal",
  initial_length = 20,
  final_length = P.length,
  length_step = 1,
  darts = 2000,                -- rho x 10^6 per step
}

print { formats = "stl" }
