-- Leaf development under non-uniform anisotropic growth (Runions et al. 2005, Table 1 row
-- "Developmental", Figures 5 and 20): the blade grows from a narrow to an almost circular shape while
-- veins of successive orders emerge. Table 1: closed, d_k = 1, b_s = b_v = 3, L_i = 23, nonuniform
-- growth to L_f = 184 (rates as in Figure 5), rho = 5000 x 10^-6, Murray n = 3.
-- Figure 5's growth functions were drawn in a graphical editor and are not given as numbers; here the
-- vertical rate REG_y = 1 + g_y falls from the base to the tip (basipetal growth), scaled so that the
-- leaf grows from L_i to exactly L_f in `steps` steps, and the horizontal rate REG_x = 1 + g_x, a
-- lookup table, takes the narrow ellipse to one `roundness` times as wide as long (Appendix A:
-- x_t = x_0 REG_x(y0)^t, y_t = integral_0^y0 REG_y(y)^t dy, Eq. 4). This is the paper's full size (on
-- one core here: growth 0.2 s, print 4 s). `scale` multiplies L_i and L_f (the shape of growth stays).
-- Printed 120 mm across, it is an open net whose main veins are wider than the rest.

local P = params {
  scale = 1,        -- fraction of Table 1's leaf size (1 = the paper's)
  steps = 60,       -- steps of growth
  roundness = 0.9,  -- final width / final length (Figure 5b is almost circular)
}

local initial_length, final_length, initial_width = 23 * P.scale, 184 * P.scale, 0.3

-- shape of g_y over the initial height y0 (0 = petiole, 1 = tip): growth falls from the base to the tip
local function gy_shape(y) return 1.3 - 0.8 * math.min(math.max(y, 0), 1) end

-- Eq. 4 at t = steps (midpoint rule): y_t / initial_length of initial height y0 for the amplitude a
local function final_height(a, y0)
  local sum, n = 0, 400
  for i = 1, n do sum = sum + (1 + a * gy_shape((i - 0.5) / n * y0)) ^ P.steps end
  return sum / n * y0
end
local function solve(f, target)  -- bisection for the amplitude a > 0 with f(a) = target
  local lo, hi = 0, 1
  while f(hi) < target do hi = hi * 2 end
  for _ = 1, 100 do
    local mid = 0.5 * (lo + hi)
    if f(mid) < target then lo = mid else hi = mid end
  end
  return 0.5 * (lo + hi)
end
local ay = solve(function(a) return final_height(a, 1) end, final_length / initial_length)

-- REG_x as a lookup table (Appendix A): each height widens by what takes the initial ellipse to the final
-- one, roundness times as wide as long (x_t = x_0 REG_x(y0)^t; an ellipse's half-width at height y of a
-- blade of length l and width w is w / 2 * sqrt(1 - (2 y / l - 1)^2), so the ratio needs no special ends)
local growth_x = {}
for i = 0, 40 do
  local y0 = math.min(math.max(i / 40, 0.001), 0.999)
  local u0, u = 2 * y0 - 1, 2 * final_height(ay, y0) * initial_length / final_length - 1
  local widen = (P.roundness * final_length) / (initial_width * initial_length) *
                math.sqrt(math.max(1 - u * u, 0) / (1 - u0 * u0))
  growth_x[#growth_x + 1] = {i / 40, widen ^ (1 / P.steps)}
end

run { seed = 20 }

leaf { shape = "ellipse", width = initial_width }

colonisation {
  type = "closed",
  kill_distance = 1,   -- d_k
  birth_distance = 3,  -- b_s = b_v
  growth = "nonuniform",
  initial_length = initial_length,  -- L_i
  growth_x = growth_x,  -- REG_x, Figure 5c: a table {{y0, rate}, ...}, linear between
  growth_y = function(y0) return 1 + ay * gy_shape(y0) end,  -- REG_y, Figure 5d
  growth_steps = P.steps,
  darts = 5000,        -- rho x 10^6
  murray_exponent = 3, -- n = 3 for the developmental model
}

print { formats = "stl", lay_flat = true }
output { png = true }  -- veins.png, a preview of veins.svg
