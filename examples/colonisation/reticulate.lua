-- A closed (reticulate) venation pattern by space colonisation (Runions et al. 2005): every source
-- pulls all vein nodes in its relative neighbourhood (Eq. 2), so veins converge on shared sources and
-- join into loops. Isogonic growth, as the paper's reticulate and poplar patterns (Table 1), scaled down.

local P = params {
  length = 100,          -- final leaf length in vein segments
  neighbourhood = "exact", -- or "urquhart", the paper's faster approximation
}

run { seed = 5 }

leaf { shape = "ovate", width = 0.7 }

colonisation {
  type = "closed",
  neighbourhood = P.neighbourhood,
  kill_distance = 1,
  birth_distance = 4,
  growth = "isogonic",
  initial_length = 20,
  final_length = P.length,
  length_step = 1,
  darts = 2000,
}

print { formats = "stl" }
