// The parameter table of the script API.
#include "app/schema.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace cellform::app {

namespace {

constexpr double kInf = 1e300;
constexpr double kFar = kFarthest;

Field num(const char* s, const char* n, const char* def, double lo, double hi, bool lo_open, const char* unit,
          const char* doc) {
  return Field{s, n, Kind::number, def, lo, hi, lo_open, "", unit, doc};
}
Field integer(const char* s, const char* n, const char* def, double lo, double hi, const char* unit, const char* doc) {
  return Field{s, n, Kind::integer, def, lo, hi, false, "", unit, doc};
}
Field vec(const char* s, const char* n, const char* def, double lo, double hi, const char* unit, const char* doc) {
  return Field{s, n, Kind::vec3, def, lo, hi, false, "", unit, doc};
}
Field boolean(const char* s, const char* n, const char* def, const char* doc) {
  return Field{s, n, Kind::boolean, def, 0, 1, false, "", "", doc};
}
Field choice(const char* s, const char* n, Kind k, const char* def, const char* choices, const char* doc) {
  return Field{s, n, k, def, 0, 0, false, choices, "", doc};
}
Field text(const char* s, const char* n, const char* def, const char* doc) {
  return Field{s, n, Kind::text, def, 0, 0, false, "", "", doc};
}

std::vector<Field> build() {
  std::vector<Field> f;
  // run{}
  f.push_back(
      integer("run", "steps", "200", 0, 1e9, "steps",
              "cell steps to simulate (--steps overrides; a --set of another value beside it is refused); refused in a "
              "space colonisation that grows no cells (it stops at colonisation.max_steps)"));
  // 2^53: every whole number up to it is exact in Lua's numbers (a larger literal would round to another)
  f.push_back(integer("run", "seed", "1", 0, 9007199254740992.0, "", "seed of every random choice (--seed overrides)"));
  f.push_back(
      integer("run", "max_memory", "0", 0, 1e9, "MB",
              "memory the cells may take at the peak, about 700 bytes a cell: initial shapes that need more "
              "are refused, a division.max_cells that would is noted (before the steps, not while the cells grow); 0 = "
              "three quarters of this machine's memory (or of a container's limit)"));

  // cells{}
  f.push_back(num("cells", "rest_length", "1", 0, kFar, true, "model units",
                  "d of the cell paper's Eq. 2: target distance between linked cells"));
  f.push_back(
      integer("cells", "neighbours", "6", 3, 32, "cells", "k: links per cell, the k nearest (dynamic neighbourhood)"));
  f.push_back(num("cells", "link_range", "1.5", 0, 1e6, false, "rest lengths",
                  "links only reach cells this close (0 = no limit: the rim of a sheet spaced at the rest length then "
                  "pulls inward; in a sheet packed closer than 0.87 rest lengths, as grown sheets are, the second "
                  "ring lies within 1.5 and the rim pulls inward either way)"));
  f.back().nonzero_min = 1;  // cells/params.cpp refuses 0 < link_range < 1: said and checked as it does
  f.push_back(choice("cells", "integrator", Kind::choice, "velocity_acceleration", "velocity|velocity_acceleration",
                     "velocity-only or velocity-acceleration model"));
  f.push_back(num("cells", "time_step", "0.1", 0, kInf, true, "time units",
                  "integration step; too large is refused as unstable"));
  f.push_back(
      num("cells", "spring", "1", 0, kInf, false, "1/time^2", "weight of the spring force (cell paper, Eq. 2)"));
  f.push_back(num("cells", "planar", "0.5", 0, kInf, false, "1/time^2",
                  "weight of planarisation towards the plane of the 3 closest (cell paper, Eq. 3)"));
  f.push_back(
      num("cells", "cohesion", "0", 0, kInf, false, "units^2/time^2",
          "weight of cohesion to the neighbours (cell paper, Eq. 4; closer than a rest length the pull weakens in "
          "proportion to the distance, so the spring keeps the cells it draws together apart)"));
  f.push_back(num("cells", "separation", "0", 0, kInf, false, "units^2/time^2",
                  "weight of separation from neighbours of neighbours (cell paper, Eq. 5)"));
  f.push_back(vec("cells", "unary", "{0, 0, 0}", -kFar, kFar, "units/time^2",
                  "constant acceleration, e.g. gravity {0,0,-g} or reverse gravity (cell paper, Eq. 6)"));
  f.push_back(vec("cells", "drag", "{0.9, 0.9, 0.9}", 0, 1, "factor per step",
                  "velocity factors a, b, c per axis (cell paper, Eq. 7); 1 = no drag (above 1, the cell paper's "
                  "acceleration, is refused for stability: it multiplies the speed every step)"));
  f.push_back(
      num("cells", "vein_cohesion", "4", 0, kInf, false, "factor",
          "factor on the vein cells' cohesion towards their vein parent and children (straightening: it pulls a "
          "bent vein cell towards them, and shortens the vein's segments)"));
  f.push_back(
      num("cells", "vein_separation", "4", 0, kInf, false, "factor",
          "factor on the vein cells' separation from their grandparent and grandchildren (straightening: it "
          "pushes a vein's cells apart along it, which straightens a zig-zag, but where the sheet holds a "
          "straight vein, one far above vein_cohesion makes it buckle; flat leaves' veins are straightest at 1 to "
          "1.5: in examples/leaf.lua a mean bend of 11 degrees between segments, against 17 at 4 and 14 at 0, "
          "over seeds 1 to 3; the holes in cells.ply follow the seed more than this value (boundary loops split "
          "where two touch at a cell: 23, 1 and 0 at 1; 11, 9 and 19 at 4; 24, 4 and 28 at 0), but at 1 the leaf's own "
          "seed, 1, leaves holes of 196 and 108 cells "
          "around, so the examples keep 4; the 3-D vein_coral.lua's veins are straighter at 4, 23 degrees against "
          "25)"));
  f.push_back(num("cells", "max_speed", "1e6 * cells.rest_length", 0, kInf, true, "units/time",
                  "a faster cell stops the run as diverged (the default scales with the form)"));
  f.push_back(Field{"cells", "petiole", Kind::table, "{}", 0, 0, false, "", "",
                    "force weights of petiole cells: {spring=, planar=, cohesion=, separation=}; they move only a "
                    "petiole{fixed = false} (a fixed one, the default, stays where it is)"});
  f.push_back(Field{"cells", "vein", Kind::table, "{}", 0, 0, false, "", "",
                    "force weights of vein cells: {spring=, planar=, cohesion=, separation=}"});

  // per-type weights (cells{petiole = {...}}, cells{vein = {...}}); defaults are the general weights
  for (const char* s : {"cells.petiole", "cells.vein"}) {
    const bool vein = std::string(s) == "cells.vein";
    f.push_back(num(s, "spring", "cells.spring", 0, kInf, false, "1/time^2", "spring weight for this cell type"));
    f.push_back(
        num(s, "planar", "cells.planar", 0, kInf, false, "1/time^2", "planarisation weight for this cell type"));
    f.push_back(num(s, "cohesion", vein ? "0.05" : "cells.cohesion", 0, kInf, false, "units^2/time^2",
                    vein ? "cohesion weight of vein cells; times vein_cohesion towards their vein parent and children"
                         : "cohesion weight for this cell type"));
    f.push_back(num(s, "separation", vein ? "0.05" : "cells.separation", 0, kInf, false, "units^2/time^2",
                    vein ? "separation weight of vein cells; times vein_separation from grandparent and grandchildren"
                         : "separation weight for this cell type"));
  }

  // division{}
  f.push_back(choice("division", "trigger", Kind::choice, "age", "none|age|neighbours",
                     "what makes a cell divide: its age, or few neighbours nearby (marginal growth)"));
  f.push_back(integer("division", "age", "20", 1, 1e9, "steps", "trigger = age: steps between divisions of a cell"));
  f.push_back(num("division", "radius", "1.25 * cells.rest_length", 0, kInf, true, "model units",
                  "trigger = neighbours: radius in which neighbours are counted"));
  f.push_back(integer("division", "min_neighbours", "6", 1, 1000, "cells",
                      "trigger = neighbours: divide when fewer cells than this are within radius"));
  f.push_back(
      integer("division", "min_age", "5", 0, 1e9, "steps", "a cell waits this long after its birth or division"));
  f.push_back(num("division", "probability", "1", 0, 1, true, "0..1",
                  "chance that a triggered cell divides this step (seeded)"));
  f.push_back(choice(
      "division", "direction", Kind::choice_or_function, "random", "random|tangent|axis|radial|circumferential|auxin",
      "split direction (tangent: random within the sheet; axis: along division.axis, which elongates the form "
      "only with trigger = neighbours: with age the sheet grows round, unlike the cell paper's uniform anisotropic "
      "growth; auxin: along the local auxin flow, as tangent where no flow runs yet); or "
      "function(cell) returning {x, y, z}. An axis, a field or a function's vector has no sign: the "
      "daughter goes either way along it, by a seeded draw. The mother stays; the daughter starts half a rest "
      "length from it in that direction, with its velocity"));
  f.push_back(vec("division", "axis", "{1, 0, 0}", -kFar, kFar, "direction", "split axis (axis, circumferential)"));
  f.push_back(
      vec("division", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "field centre (radial, circumferential)"));
  f.push_back(integer("division", "max_cells", "100000", 1, 5e7, "cells", "growth stops at this many cells"));
  f.push_back(Field{"division", "rule", Kind::function, "", 0, 0, false, "", "",
                    "function(cell) returning true when the cell divides; replaces trigger, age, radius and "
                    "min_neighbours (set none of them with it); min_age and probability still apply"});

  // initial shapes
  f.push_back(
      num("disc", "radius", "", 0, kInf, true, "model units", "cells on a hexagonal lattice inside this radius"));
  f.push_back(num("disc", "spacing", "cells.rest_length", 0, kInf, true, "model units", "lattice spacing"));
  f.push_back(vec("disc", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "centre of the disc"));
  f.push_back(vec("disc", "normal", "{0, 0, 1}", -kFar, kFar, "direction", "normal of the disc's plane"));
  f.push_back(num("rectangle", "width", "", 0, kInf, true, "model units", "extent along the plane's first axis"));
  f.push_back(num("rectangle", "height", "", 0, kInf, true, "model units", "extent along the plane's second axis"));
  f.push_back(num("rectangle", "spacing", "cells.rest_length", 0, kInf, true, "model units", "lattice spacing"));
  f.push_back(vec("rectangle", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "centre"));
  f.push_back(vec("rectangle", "normal", "{0, 0, 1}", -kFar, kFar, "direction", "normal of the plane"));
  f.push_back(
      num("sphere", "radius", "", 0, kInf, true, "model units", "cells evenly spread on a sphere of this radius"));
  f.push_back(num("sphere", "spacing", "cells.rest_length", 0, kInf, true, "model units", "distance between cells"));
  f.push_back(vec("sphere", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "centre"));
  f.push_back(vec("line", "from", "", -kFar, kFar, "model units", "first cell"));
  f.push_back(vec("line", "to", "", -kFar, kFar, "model units", "last cell"));
  f.push_back(num("line", "spacing", "cells.rest_length", 0, kInf, true, "model units",
                  "largest distance between cells (the line is divided evenly, a cell at each end)"));
  f.push_back(vec("cell", "at", "", -kFar, kFar, "model units", "one cell at this position"));
  f.push_back(boolean("cell", "fixed", "false", "a fixed (static) cell never moves"));
  f.push_back(vec("petiole", "at", "{0, 0, 0}", -kFar, kFar, "model units",
                  "the nearest cell within half a rest length becomes a petiole, else a new petiole cell is added "
                  "there; a cell must lie within 3 rest lengths (at its step, or the run stops with an error)"));
  f.push_back(boolean("petiole", "fixed", "true", "the petiole stays where it is"));
  f.push_back(integer("petiole", "step", "0", 0, 1e9, "steps", "when the petiole appears (0 = at the start)"));

  // venation{}
  f.push_back(
      num("venation", "threshold", "40", 0, kInf, true, "auxin per step",
          "flow a cell next to a vein must exceed to become a vein cell (with source 1: about its upstream cells); "
          "sets vein spacing"));
  f.push_back(Field{"venation", "source", Kind::number_or_function, "1", 0, 1e30, false, "", "auxin per step",
                    "auxin every cell produces; or function(cell) returning it"});
  f.push_back(num("venation", "murray_exponent", "3", 1, 4, false, "",
                  "n of Murray's law: radius = radius_scale flow^(1/n), so r_parent^n = sum r_child^n plus the auxin "
                  "that joins between forks"));
  f.push_back(num("venation", "radius_scale", "0.05", 0, 1e30, true, "model units",
                  "radius of a vein carrying unit flow: r = radius_scale * flow^(1/n)"));
  f.push_back(num("venation", "min_radius", "0.05", 0, std::numeric_limits<float>::max(), false, "model units",
                  "no vein is thinner (the files keep radii as 32-bit numbers)"));
  f.push_back(integer("venation", "every", "1", 1, 1e6, "steps",
                      "run canalisation every this many steps (auxin is slower than mechanics); the outputs then "
                      "show the last pass's flows (end a run on a multiple of it for those of the final cells: "
                      "cells born since carry their mother's)"));

  // constraints
  f.push_back(num("ground", "height", "0", -kFar, kFar, false, "model units", "cells stay above the plane z = height"));
  f.push_back(vec("half_space", "point", "{0, 0, 0}", -kFar, kFar, "model units", "a point on the boundary plane"));
  f.push_back(vec("half_space", "normal", "{0, 0, 1}", -kFar, kFar, "direction", "cells stay on this side"));
  f.push_back(
      vec("ball", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "centre of a solid ball cells stay out of"));
  f.push_back(num("ball", "radius", "", 0, kFar, true, "model units", "its radius"));
  f.push_back(vec("box", "min", "", -kFar, kFar, "model units", "lower corner of a solid box cells stay out of"));
  f.push_back(vec("box", "max", "", -kFar, kFar, "model units", "upper corner"));
  f.push_back(text("mesh", "file", "",
                   "STL (ASCII or binary) or OBJ mesh (polygons are split into triangles), read Z-up as cellform "
                   "writes, that cells cannot cross from either side (a wall, not a solid: cells inside a closed mesh "
                   "stay inside, as in a mould; the cells must start off it, all on one side; path relative to the "
                   "script)"));
  f.push_back(num("mesh", "scale", "1", 0, kInf, true, "factor", "scales the mesh's coordinates into model units"));
  f.push_back(vec("mesh", "offset", "{0, 0, 0}", -kFar, kFar, "model units",
                  "added to the scaled coordinates: moves a mesh drawn away from the origin (a site model) to the "
                  "cells"));
  f.push_back(vec("attractor", "position", "", -kFar, kFar, "model units", "point that pulls cells"));
  f.push_back(num("attractor", "strength", "0.1", -kInf, kInf, false, "units/time^2",
                  "acceleration towards it (negative repels)"));
  f.push_back(num("attractor", "radius", "0", 0, kInf, false, "model units", "range of influence; 0 = everywhere"));

  // leaf{} and colonisation{}: space-colonisation venation (Runions et al. 2005)
  f.push_back(choice("leaf", "shape", Kind::choice, "ovate", "ellipse|ovate|cordate|lobed|palmate",
                     "blade outline, petiole at the origin, tip along +y"));
  f.push_back(num("leaf", "width", "0.6", 0.01, 10, false, "leaf lengths", "widest extent across the blade"));
  f.push_back(integer("leaf", "lobes", "5", 1, 100, "", "lobed: lobes per side; palmate: lobes in all (at least 2)"));
  f.push_back(num("leaf", "lobe_depth", "0.35", 0, 0.99, false, "fraction", "cut between lobes, of the radius"));
  f.push_back(integer("leaf", "teeth", "0", 0, 2000, "", "teeth along the margin (0 = entire margin)"));
  f.push_back(num("leaf", "tooth_depth", "0.02", 0, 1, false, "leaf lengths", "height of the teeth"));
  f.push_back(integer("leaf", "fine_teeth", "0", 0, 2000, "",
                      "a second wave of teeth summed with the first (Runions 2005, Section 3.2: waves of different "
                      "amplitudes and frequencies), e.g. finer teeth on the teeth of a doubly serrate margin "
                      "(0 = none)"));
  f.push_back(num("leaf", "fine_tooth_depth", "0.005", 0, 1, false, "leaf lengths", "height of the second wave"));
  f.push_back(
      text("leaf", "file", "(none)",
           "outline file (one 'x y' per line, '#' starts a comment, closed: the first point repeated last; petiole "
           "at (0, 0), any unit: scaled so its tip, the "
           "highest y (at least half the farthest vertex's distance), is one leaf length; relative to "
           "the script) instead of a shape"));
  f.push_back(integer("leaf", "seeds", "1", 1, 10000, "",
                      "initial vein nodes spread along the base (several: grass-like parallel veins)"));
  f.push_back(
      num("leaf", "seed_spread", "0.3", 0, 10, false, "leaf lengths", "width of the base the seeds are spread over"));
  f.push_back(Field{"leaf", "seed_points", Kind::table, "(none)", 0, 0, false, "", "leaf lengths",
                    "initial vein nodes placed by hand, {{x, y}, ...} inside the blade (the petiole at (0, 0), the tip "
                    "at (0, 1)), instead of seeds and seed_spread"});
  // volume{} and surface{}: 3-D source domains instead of a leaf
  f.push_back(Field{"volume", "box", Kind::table, "(none)", 0, 0, false, "", "",
                    "sources fill the box {min = {x, y, z}, max = {x, y, z}} (model units = vein segments)"});
  f.push_back(Field{"volume", "ball", Kind::table, "(none)", 0, 0, false, "", "",
                    "sources fill the ball {centre = {x, y, z}, radius = r}"});
  f.push_back(text("volume", "file", "(none)",
                   "sources fill the inside of this closed STL or OBJ mesh (path relative to the script)"));
  f.push_back(num("volume", "scale", "1", 0, kInf, true, "factor", "file: scales the mesh's coordinates"));
  f.push_back(
      vec("volume", "offset", "{0, 0, 0}", -kFar, kFar, "model units", "file: added to the scaled coordinates"));
  f.push_back(Field{"volume", "seeds", Kind::table, "(auto)", 0, 0, false, "", "model units",
                    "seed vein nodes {{x, y, z}, ...} inside the volume; default: box: centre of its floor, ball: "
                    "its lowest point (file: required)"});
  f.push_back(vec("volume.box", "min", "", -kFar, kFar, "model units", "lowest corner"));
  f.push_back(vec("volume.box", "max", "", -kFar, kFar, "model units", "highest corner"));
  f.push_back(vec("volume.ball", "centre", "{0, 0, 0}", -kFar, kFar, "model units", "centre"));
  f.push_back(num("volume.ball", "radius", "", 0, kFar, true, "model units", "radius"));
  f.push_back(text("surface", "file", "(none)",
                   "sources lie on the triangles of this STL or OBJ mesh (open or closed; relative to the script)"));
  f.push_back(num("surface", "scale", "1", 0, kInf, true, "factor", "file: scales the mesh's coordinates"));
  f.push_back(
      vec("surface", "offset", "{0, 0, 0}", -kFar, kFar, "model units", "file: added to the scaled coordinates"));
  f.push_back(boolean("surface", "cells", "false",
                      "grow the script's cells first (cells{}, division{}, run{}, shapes); veins grow on their sheet"));
  f.push_back(Field{
      "surface", "seeds", Kind::table, "(auto)", 0, 0, false, "", "model units",
      "seed vein nodes {{x, y, z}, ...}; file: required, on the surface (after surface.scale and offset; one within a "
      "vein segment of it, but farther than 1e-6 of its box's diagonal, is moved onto it with a note); cells: "
      "moved to the nearest point of "
      "the grown sheet, from at most half its size or 3 cell spacings away (default: the petiole cells)"});
  f.push_back(choice("colonisation", "type", Kind::choice, "open", "open|closed",
                     "open: trees; closed: veins join into loops"));
  f.push_back(choice(
      "colonisation", "neighbourhood", Kind::choice, "exact", "exact|urquhart",
      "closed: relative neighbourhood (Runions 2005, Eq. 2) or its Urquhart approximation (leaf only; slower "
      "here, up to 25 times in the presets on one core (grass 25, reticulate 14, poplar's default 1.1) and more in "
      "larger leaves, as exact keeps each source's sector bests "
      "from step to step: the paper's speed-up does not apply)"));
  f.push_back(num("colonisation", "kill_distance", "1", 0.5, kInf, false, "vein segments",
                  "d_k: a vein node this close reaches (open: removes) a source"));
  f.push_back(num("colonisation", "birth_distance", "10", 0, kInf, true, "vein segments",
                  "b_s: new sources keep this far from every source"));
  f.push_back(num("colonisation", "vein_birth_distance", "0", 0, kInf, false, "vein segments",
                  "b_v: new sources keep this far from every vein node; 0 = birth_distance"));
  f.push_back(num("colonisation", "darts", "200", 0, kInf, true, "per 10^6 unit^2 (volume: unit^3) per step",
                  "rho x 10^6 of Table 1: darts per unit area (leaf, surface) or volume (volume) per step"));
  f.push_back(choice("colonisation", "growth", Kind::choice, "marginal", "none|marginal|isogonic|nonuniform",
                     "how the blade grows (nonuniform: Appendix A, with growth_x, growth_y, growth_steps; volume "
                     "and surface: none, their default)"));
  f.push_back(
      num("colonisation", "initial_length", "270", 0, kInf, true, "vein segments", "L_i: leaf length at the start"));
  f.push_back(
      num("colonisation", "final_length", "1600", 0, kInf, true, "vein segments", "L_f: growth stops at this length"));
  f.push_back(num("colonisation", "length_step", "8", 0, kInf, false, "vein segments per step",
                  "Delta L: growth per step (marginal and isogonic: > 0, and at most 10^7 steps from initial_length "
                  "to final_length; no effect with none or nonuniform)"));
  f.push_back(integer("colonisation", "max_steps", "100000", 1, 1e9, "steps", "stop after this many steps"));
  f.push_back(integer("colonisation", "max_nodes", "2000000", 1, 1e9, "nodes",
                      "stop after the step that reaches this many vein nodes"));
  f.push_back(integer("colonisation", "max_sources", "2000000", 1, 1e9, "sources",
                      "stop after a step that leaves this many auxin sources waiting (a leaf growing faster than its "
                      "veins fill it), or before a step whose darts would make more wait, which is not taken (a large "
                      "blade that does not grow); each waiting source holds about a kilobyte"));
  f.push_back(
      num("colonisation", "murray_exponent", "2", 1, 4, false, "", "n of r_parent^n = sum r_child^n (Table 1: 2)"));
  f.push_back(num("colonisation", "tip_radius", "0.15", 0, 1000, true, "vein segments", "radius of a free vein end"));
  f.push_back(num("colonisation", "node_flow", "0", 0, 1e6, false, "tip flows per node",
                  "extra flow each vein node but a free end adds to what reaches it (a free end carries 1), so veins "
                  "widen towards the base beyond Murray's law, the more the longer they run: the paper's widening of "
                  "primary and secondary veins for the veinlets not modelled (Section 3.5); a long branch may then "
                  "outweigh a shorter one with more tips and keep the order; 0 = Murray's law alone, r_parent^n = "
                  "sum r_child^n"));
  f.push_back(Field{"colonisation", "growth_x", Kind::table_or_function, "(none)", 0, 0, false, "", "REG per step",
                    "nonuniform: horizontal growth rate REG_x = 1 + g_x (Fig. 5c) of the initial height y0 (leaf "
                    "lengths, 0 = petiole, 1 = tip): {{y0, rate}, ...} with y0 increasing, linear between, or "
                    "function(y0) sampled at 257 heights from -0.5 to 1.5; rates > 0"});
  f.push_back(Field{"colonisation", "growth_y", Kind::table_or_function, "(none)", 0, 0, false, "", "REG per step",
                    "nonuniform: vertical growth rate REG_y = 1 + g_y (Fig. 5d), as growth_x; > 0 keeps the "
                    "mapping y0 -> y_t (Runions 2005, Eq. 4) increasing"});
  f.push_back(integer("colonisation", "growth_steps", "0", 0, 1e9, "steps",
                      "nonuniform: steps of growth; the leaf then keeps its shape (required, >= 1)"));

  // print{}
  f.push_back(boolean("print", "veins", "true", "veins become solid tapered members with their Murray radii"));
  f.push_back(boolean("print", "shell", "false", "the cell sheet becomes a shell of shell_thickness"));
  f.push_back(num("print", "size", "120", 0, 1e5, true, "mm",
                  "largest extent of the printed form when scale = 0 (of its ideal round members; the mesh lies on "
                  "chords of them, up to about two voxels less at thin tips and rims)"));
  f.push_back(num("print", "scale", "0", 0, 1e9, false, "mm per model unit", "0 = automatic from size"));
  // lower bounds far below any printer, but not 1e-320 (refused at the end of a run, "inf mm" said, audit)
  f.push_back(num("print", "min_radius", "0.4", 1e-4, 1e3, false, "mm",
                  "thinner veins are raised to this printable minimum (less than size / 2 when scale is automatic)"));
  f.push_back(num("print", "shell_thickness", "0.6", 1e-4, 1e3, false, "mm",
                  "wall thickness of the shell (less than size when scale is automatic); printed walls are up to "
                  "about a voxel thinner in places (the surface lies on chords): check them with a --min-wall a "
                  "voxel below it"));
  f.push_back(num("print", "voxel_size", "0", 0, 1e3, false, "mm",
                  "level-set resolution, at most min_radius (printing veins) and shell_thickness / 2 (printing "
                  "a shell); 0 = min_radius / 2 (with a shell at most "
                  "shell_thickness / 2: two voxels across the wall), raised if that would need more than "
                  "max_memory, up to the thinnest member printed (a vein's radius, at least min_radius; half the "
                  "shell's wall)"));
  f.back().nonzero_min = 1e-5;  // (1e-320 was refused after the steps, "inf mm" said, audit)
  f.push_back(
      num("print", "adaptivity", "0.2", 0, 1, false, "0..1",
          "mesh simplification (OpenVDB): fewer triangles where the surface is flat; above the default it thins round "
          "veins by more than a voxel in places (at 1, the thinnest by about half; noted); 0 = uniform"));
  f.push_back(num("print", "max_memory", "2000", 1, 1e6, false, "MB",
                  "memory limit of the printable grid: an explicit voxel_size that needs more is refused; the "
                  "automatic one is coarsened to fit, up to the thinnest member printed (a vein's radius, at least "
                  "min_radius; half the shell's wall). A print whose estimate exceeds what the process has left "
                  "(ulimit -v, a container's limit, free memory and swap) is refused, never coarsened"));
  f.push_back(text("print", "formats", "stl", "comma-separated: stl, obj, ply, scad, vdb"));
  f.push_back(boolean("print", "fill_cavities", "false",
                      "fill closed pockets inside the solid (a shell around a closed sheet becomes solid; so do "
                      "pockets between crowded cells, which a run warns of)"));
  f.push_back(num("print", "close_holes", "1", 0, 10, false, "cell spacings",
                  "shell: fill holes in the printed sheet by a closing of radius r = half this many cell spacings; it "
                  "spans gaps up to 2 sqrt(h^2 + 2 h r) across (h = shell_thickness / 2), and joins folds of the "
                  "sheet closer than 2 r; 0 = no closing"));
  f.push_back(num("print", "close_holes_max", "2", 0, 100, false, "mm",
                  "shell: the closing's radius r at most this (0 = no cap): at a large print scale half a cell "
                  "spacing is many millimetres, and a closing that large fills the space between nearby folds"));
  f.push_back(boolean("print", "lay_flat", "false",
                      "raise each vein by its radius as printed, so that a flat form's veins, thick and thin, all rest "
                      "on its lowest plane, the printer's bed (centred on the form's surface, thin veins float above "
                      "the thickest: a colonisation leaf's outer veins up to a few mm); not the shell"));
  f.push_back(num("print", "flat_base", "0", 0, 1e5, false, "mm",
                  "cut this much off the bottom of the form so it stands on a flat face (0 = no cut); the voxels "
                  "within two of the cut are meshed without adaptivity, so that the face stays flat: a wide "
                  "foot costs triangles (a leaf's flat underside made its file 4.4 times larger)"));
  f.push_back(choice("print", "pieces", Kind::choice, "warn", "any|warn|one",
                     "one: a form that falls apart is an error; warn: a warning with the part count"));

  // output{}
  f.push_back(
      boolean("output", "ply", "true", "write cells.ply (cells, triangles, links, per-cell attributes) and veins.ply"));
  f.push_back(boolean("output", "obj", "true", "write cells.obj (the cell surface) and veins.obj"));
  f.push_back(integer("output", "every", "0", 0, 1e9, "steps",
                      "cell runs: also write frames/cells_NNNNNN.ply (the step, in six digits, more from step "
                      "1,000,000) of the cells as placed (step 0) and every this many steps (0 = none); not with "
                      "colonisation{...}, even when surface{cells = true} grows a sheet first"));
  f.push_back(integer("output", "checkpoint_every", "1000", 0, 1e9, "steps",
                      "write checkpoint.cfck every this many steps (0 = only at the end)"));
  f.push_back(num("output", "checkpoint_seconds", "60", 0, 1e9, false, "s",
                  "skip a periodic checkpoint due this soon after the last one (0 = never skip; the first is "
                  "always written); the end of a run and Ctrl-C always write one, a failing step leaves the last"));
  f.push_back(num("output", "checkpoint_minutes", "10", 0, 1e6, false, "min",
                  "also write one after the first step that ends this long after the last one (or the start of the "
                  "steps: of the veins' steps, after a grown sheet), so that a failure loses about this much at most "
                  "(0 = never; --checkpoint-every N sets it to 0: exactly every N steps); not with checkpoint_every "
                  "= 0, nor within checkpoint_seconds of the last"));
  f.push_back(boolean("output", "png", "false",
                      "space colonisation: also write veins.png, a raster preview of veins and outline"));
  f.push_back(integer("output", "png_size", "1024", 16, 20000, "pixels", "longer side of veins.png"));
  f.push_back(num("output", "svg_size", "0", 0, 1e5, false, "mm",
                  "longer side of the leaf (outline and veins, their widths included) in veins.svg, drawn in mm with a "
                  "5 mm margin; 0 = at "
                  "the print's scale with print{...} (the outline fits the printed veins), else 200"));
  f.back().nonzero_min = 1;  // strokes are at least 0.1 mm: a smaller drawing is a blot
  f.push_back(choice("output", "svg_paths", Kind::choice, "widths", "widths|veins",
                     "veins.svg: widths = a path runs between branch points and width changes, each at its width; "
                     "veins = a path per vein, from its parent vein to its tip at its mean width (about half the "
                     "pen lifts for a plotter)"));
  return f;
}

}  // namespace

const std::vector<Field>& schema() {
  static const std::vector<Field> fields = build();
  return fields;
}

std::vector<const Field*> section_fields(const std::string& section) {
  std::vector<const Field*> out;
  for (const Field& f : schema())
    if (f.section == section) out.push_back(&f);
  return out;
}

const Field* find_field(const std::string& section, const std::string& name) {
  for (const Field& f : schema())
    if (f.section == section && f.name == name) return &f;
  return nullptr;
}

std::string allowed_text(const Field& f) {
  std::ostringstream s;
  auto number = [&f](double v) {
    std::ostringstream t;
    t << v;
    // a whole-number limit the short form rounds (2^53 said 9.0072e+15, which is above it) is written out
    if (f.kind == Kind::integer && std::abs(v) <= 0x1p62 && std::stod(t.str()) != v)
      return std::to_string(static_cast<long long>(v));
    return t.str();
  };
  switch (f.kind) {
    case Kind::number:
    case Kind::integer:
    case Kind::vec3: {
      const bool lo = f.min > -1e299, hi = f.max < 1e299;
      const std::string what = f.kind == Kind::integer ? "a whole number"
                               : f.kind == Kind::vec3  ? "{x, y, z} with each"
                                                       : "a number";
      s << (f.nonzero_min > 0 ? "0, or " : "") << what;
      if (f.nonzero_min > 0)
        s << " from " << number(f.nonzero_min) << " to " << number(f.max);
      else if (lo && hi)
        s << " from " << number(f.min) << (f.min_exclusive ? " (exclusive)" : "") << " to " << number(f.max);
      else if (lo)
        s << (f.min_exclusive ? " > " : " >= ") << number(f.min);
      else if (hi)
        s << " <= " << number(f.max);
      else if (f.kind == Kind::vec3)
        s << " finite";
      break;
    }
    case Kind::boolean:
      s << "true or false";
      break;
    case Kind::text:
      s << "a string";
      break;
    case Kind::choice:
      s << "one of " << f.choices;
      break;
    case Kind::choice_or_function:
      s << "one of " << f.choices << ", or a function";
      break;
    case Kind::function:
      s << "a function";
      break;
    case Kind::number_or_function:
      s << "a number";
      if (f.min > -1e299 && f.max < 1e299)
        s << " from " << number(f.min) << " to " << number(f.max);
      else if (f.min > -1e299)
        s << " >= " << number(f.min);
      s << ", or a function";
      break;
    case Kind::table:
      s << "a table";
      break;
    case Kind::table_or_function:
      s << "a table or a function";
      break;
  }
  return s.str();
}

std::string schema_markdown() {
  std::ostringstream s;
  std::string section;
  auto cell = [](const std::string& text) {  // a "|" in a cell ends it: escaped ("one of a|b")
    std::string out;
    for (const char c : text) {
      if (c == '|') out += '\\';
      out += c;
    }
    return out;
  };
  for (const Field& f : schema()) {
    if (f.section != section) {
      section = f.section;
      // a table inside a section ("cells.petiole") is shown as it is written: cells{ petiole = {...} }
      const std::size_t dot = section.find('.');
      const std::string call = dot == std::string::npos
                                   ? section + "{...}"
                                   : section.substr(0, dot) + "{ " + section.substr(dot + 1) + " = {...} }";
      s << "\n### `" << call << "`\n\n| parameter | default | allowed | unit | meaning |\n|---|---|---|---|---|\n";
    }
    s << "| `" << f.name << "` | "
      << (!f.default_text.empty() ? "`" + f.default_text + "`"
          : f.structured()        ? std::string("(none)")
                                  : "required")
      << " | " << cell(allowed_text(f)) << " | " << f.unit << " | " << cell(f.doc) << " |\n";
  }
  return s.str();
}

}  // namespace cellform::app
