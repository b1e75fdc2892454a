// The sections of the growth-script API for the cell system and its outputs (cells{}, division{}, disc{},
// ground{}, print{}, ...): each reads its table against the schema and fills the scene configuration.
// The colonisation sections are in script_colonisation.cpp.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <vector>

#include "app/memory.h"
#include "app/script_impl.h"
#include "app/script_placement.h"
#include "core/chunk_file.h"
#include "forms/obstacles.h"
#include "forms/shapes.h"

namespace cellform::app {

namespace {

cells::ForceWeights weights_from(const Values& v) {
  cells::ForceWeights w;
  w.spring = v.at("spring").num;
  w.planar = v.at("planar").num;
  w.cohesion = v.at("cohesion").num;
  w.separation = v.at("separation").num;
  return w;
}

}  // namespace

void section_cells(Impl& I, const std::string& at) {
  I.once("cells", at);
  nlohmann::json& rec = I.cfg->resolved["cells"];
  Values v = I.read_section("cells", 1, at, &rec);
  cells::Params& p = I.cfg->scene.cells;
  p.rest_length = v["rest_length"].num;
  p.neighbours = static_cast<int>(v["neighbours"].num);
  p.link_range = v["link_range"].num;
  p.integrator =
      v["integrator"].str == "velocity" ? cells::Integrator::velocity : cells::Integrator::velocity_acceleration;
  p.time_step = v["time_step"].num;
  const cells::ForceWeights general = weights_from(v);
  p.unary = v["unary"].vec;
  p.drag = v["drag"].vec;
  p.vein_cohesion_factor = v["vein_cohesion"].num;
  p.vein_separation_factor = v["vein_separation"].num;
  // a million rest lengths per time unit by default: a form modelled in millimetres or in metres alike (not
  // recorded then: an edited rest length re-derives it)
  p.max_speed = v["max_speed"].present ? v["max_speed"].num : 1e6 * p.rest_length;
  p.weights[static_cast<int>(cells::CellType::general)] = general;
  const std::pair<const char*, cells::CellType> types[] = {{"petiole", cells::CellType::petiole},
                                                           {"vein", cells::CellType::vein}};
  for (const auto& [name, type] : types) {
    if (lua_type(I.L, 1) == LUA_TTABLE)
      raw_field(I.L, 1, name);
    else
      lua_pushnil(I.L);
    const int idx = lua_gettop(I.L);
    Values w = I.read_section(std::string("cells.") + name, idx, at, &rec[name]);
    lua_pop(I.L, 1);
    cells::ForceWeights tw = general;
    if (type == cells::CellType::vein) {  // vein cells straighten by default (schema defaults 0.05)
      tw.cohesion = w["cohesion"].num;
      tw.separation = w["separation"].num;
    }
    if (w["spring"].present) tw.spring = w["spring"].num;
    if (w["planar"].present) tw.planar = w["planar"].num;
    if (w["cohesion"].present) tw.cohesion = w["cohesion"].num;
    if (w["separation"].present) tw.separation = w["separation"].num;
    rec[name] = {
        {"spring", tw.spring}, {"planar", tw.planar}, {"cohesion", tw.cohesion}, {"separation", tw.separation}};
    p.weights[static_cast<int>(type)] = tw;
  }
}

void section_division(Impl& I, const std::string& at) {
  I.once("division", at);
  Values v = I.read_section("division", 1, at, &I.cfg->resolved["division"]);
  cells::DivisionParams& d = I.cfg->scene.cells.division;
  const std::string trig = v["trigger"].str;
  d.trigger = trig == "none"         ? cells::DivisionTrigger::none
              : trig == "neighbours" ? cells::DivisionTrigger::neighbours
                                     : cells::DivisionTrigger::age;
  d.division_age = static_cast<std::uint32_t>(v["age"].num);
  d.radius = v["radius"].num;
  I.division_radius_derived = !v["radius"].present;
  d.min_neighbours = static_cast<int>(v["min_neighbours"].num);
  d.min_age = static_cast<std::uint32_t>(v["min_age"].num);
  d.probability = v["probability"].num;
  d.axis = v["axis"].vec;
  d.centre = v["centre"].vec;
  d.max_cells = static_cast<std::uint64_t>(v["max_cells"].num);
  const Value& dir = v["direction"];
  if (dir.ref != LUA_NOREF) {
    d.direction = cells::SplitDirection::rule;
    I.direction_ref = dir.ref;
    I.direction_at = I.function_at(dir.ref, at);
  } else {
    d.direction = dir.str == "axis"              ? cells::SplitDirection::axis
                  : dir.str == "tangent"         ? cells::SplitDirection::tangent
                  : dir.str == "radial"          ? cells::SplitDirection::radial
                  : dir.str == "circumferential" ? cells::SplitDirection::circumferential
                  : dir.str == "auxin"           ? cells::SplitDirection::rule
                                                 : cells::SplitDirection::random;
    I.cfg->scene.split_along_auxin = dir.str == "auxin";
  }
  // the field of the other directions would be dropped unseen: refused when the script gives both; noted
  // when a --set chose the direction or the field (a --set cannot remove the script's field)
  const std::string named = dir.ref != LUA_NOREF ? std::string("a function") : "\"" + dir.str + "\"";
  const auto unused_field = [&](const char* field, const char* belongs) {
    const std::string text = "division." + std::string(field) + " has no effect with direction = " + named +
                             " (it belongs to " + belongs + ")";
    if (dir.set_by.empty() && v[field].set_by.empty())
      throw InvalidInput(at + text + "; remove it, or choose one of those");
    I.cfg->notes.push_back((dir.set_by.empty() ? v[field].set_by : dir.set_by) + ": " + text);
  };
  if (v["axis"].present && d.direction != cells::SplitDirection::axis &&
      d.direction != cells::SplitDirection::circumferential)
    unused_field("axis", "\"axis\" and \"circumferential\"");
  if (v["centre"].present && d.direction != cells::SplitDirection::radial &&
      d.direction != cells::SplitDirection::circumferential)
    unused_field("centre", "\"radial\" and \"circumferential\"");
  if ((d.direction == cells::SplitDirection::axis || d.direction == cells::SplitDirection::circumferential) &&
      d.axis.norm() == 0)
    throw InvalidInput(at + "division.axis must be a non-zero vector for direction = \"" + dir.str + "\"");
  if (v["rule"].ref != LUA_NOREF) {
    // the rule replaces the trigger and its settings: refuse them rather than drop them unseen
    for (const char* f : {"trigger", "age", "radius", "min_neighbours"}) {
      if (!v[f].present) continue;
      const std::string text =
          "division." + std::string(f) + " has no effect with division.rule, which decides alone when a cell divides";
      if (v[f].set_by.empty()) throw InvalidInput(at + text + "; remove one of them");
      I.cfg->notes.push_back(v[f].set_by + ": " + text);  // a --set: said, and the run goes on
    }
    I.divides_ref = v["rule"].ref;
    I.divides_at = I.function_at(v["rule"].ref, at);
    // run.json: the trigger settings did not apply
    for (const char* f : {"trigger", "age", "radius", "min_neighbours"}) I.cfg->resolved["division"].erase(f);
  } else {
    // a setting of the other trigger would be dropped unseen
    const std::string trigger = v["trigger"].str;
    for (const char* f : {"age", "radius", "min_neighbours"}) {
      const bool used = std::string(f) == "age" ? trigger == "age" : trigger == "neighbours";
      if (!v[f].present || used) continue;
      const std::string text = "division." + std::string(f) + " has no effect with trigger = \"" + trigger +
                               "\" (it belongs to " +
                               (std::string(f) == "age" ? "trigger = \"age\"" : "trigger = \"neighbours\"") + ")";
      // as for the direction: a --set that chose the trigger (or gave the field) is noted, not refused, since
      // it cannot remove the script's field
      if (v["trigger"].set_by.empty() && v[f].set_by.empty())
        throw InvalidInput(at + text + "; remove it, or choose that trigger");
      I.cfg->notes.push_back((v["trigger"].set_by.empty() ? v[f].set_by : v["trigger"].set_by) + ": " + text);
      I.cfg->resolved["division"].erase(f);  // run.json: it did not apply
    }
  }
}

void section_run(Impl& I, const std::string& at) {
  I.once("run", at);
  Values v = I.read_section("run", 1, at, &I.cfg->resolved["run"]);
  I.cfg->steps = static_cast<std::uint64_t>(v["steps"].num);
  if (v["steps"].present) {  // where, for a run that has no use for it
    I.cfg->steps_given_at = at;
    if (I.overrides && I.overrides->count("run.steps"))
      I.cfg->steps_given_at = "--set run.steps=" + I.overrides->at("run.steps") + ": ";
  }
  I.cfg->seed = static_cast<std::uint64_t>(v["seed"].num);
  I.cfg->max_memory_mb = v["max_memory"].num;
}

void section_venation(Impl& I, const std::string& at) {
  I.once("venation", at);
  Values v = I.read_section("venation", 1, at, &I.cfg->resolved["venation"]);
  venation::Params p;
  p.threshold = v["threshold"].num;
  if (v["source"].ref != LUA_NOREF) {
    I.source_ref = v["source"].ref;
    I.source_at = I.function_at(v["source"].ref, at);
  } else {
    p.source = v["source"].num;
  }
  p.murray_exponent = v["murray_exponent"].num;
  p.radius_scale = v["radius_scale"].num;
  p.min_radius = v["min_radius"].num;
  p.every = static_cast<std::uint32_t>(v["every"].num);
  I.cfg->scene.venation = p;
  I.cfg->scene.venation_origin = at;
}

void section_print(Impl& I, const std::string& at) {
  I.once("print", at);
  Values v = I.read_section("print", 1, at, &I.cfg->resolved["print"]);
  PrintSpec p;
  p.veins = v["veins"].flag;
  p.shell = v["shell"].flag;
  p.size = v["size"].num;
  p.scale = v["scale"].num;
  p.min_radius = v["min_radius"].num;
  p.shell_thickness = v["shell_thickness"].num;
  p.voxel_size = v["voxel_size"].num;  // (checked against min_radius and the shell once the veins are known)
  p.adaptivity = v["adaptivity"].num;
  p.max_memory_mb = v["max_memory"].num;
  p.pieces = v["pieces"].str;
  p.fill_cavities = v["fill_cavities"].flag;
  p.flat_base = v["flat_base"].num;
  p.lay_flat = v["lay_flat"].flag;
  p.close_holes = v["close_holes"].num;
  p.close_holes_max = v["close_holes_max"].num;
  if (p.shell && p.scale == 0 && p.shell_thickness >= p.size)  // the auto scale fits the form, not its walls
    throw InvalidInput(
        I.value_at(I.overrides && I.overrides->count("print.size") ? "print.size" : "print.shell_thickness", at) +
        "print.shell_thickness (" + core::number_text(p.shell_thickness) + " mm) is not less than print.size (" +
        core::number_text(p.size) +
        " mm, the whole print across): the walls would be thicker than the form; use a thinner shell "
        "or a larger size");
  if (p.scale == 0 && p.flat_base > 0 && p.flat_base >= p.size)  // the height is at most the largest extent
    throw InvalidInput(
        I.value_at(I.overrides && I.overrides->count("print.size") ? "print.size" : "print.flat_base", at) +
        "print.flat_base (" + core::number_text(p.flat_base) + " mm) is not less than print.size (" +
        core::number_text(p.size) +
        " mm, the largest extent of the print): it would cut the whole form away; use a smaller flat_base");
  if (p.veins && p.scale == 0 && 2 * p.min_radius >= p.size)
    throw InvalidInput(
        I.value_at(I.overrides && I.overrides->count("print.size") ? "print.size" : "print.min_radius", at) +
        "print.min_radius (" + core::number_text(p.min_radius) + " mm) makes every vein at least " +
        core::number_text(2 * p.min_radius) + " mm thick, not less than print.size (" + core::number_text(p.size) +
        " mm, the whole print across): the veins would be larger than the form; use a smaller "
        "min_radius or a larger size");
  if (p.adaptivity > 0.2)  // the default keeps the round members within a voxel of their radius
    I.cfg->notes.push_back(I.value_at("print.adaptivity", at) +
                           "print.adaptivity = " + core::number_text(p.adaptivity) +
                           " simplifies curved surfaces too, not only flat areas: veins and walls come out thinner "
                           "by more than a voxel in places (at 1, the thinnest by about half); the default 0.2 keeps "
                           "them within a voxel");
  if (p.scale > 0 && v["size"].present)  // noted, as below: a --set print.scale may override a script's size
    I.cfg->notes.push_back(I.value_at("print.size", at) +
                           "print.size has no effect: print.scale is set (size sets the scale when scale = 0)");
  if (!p.shell)  // noted, not refused: --set print.shell=false may turn off a shell the script sets up
    for (const char* f : {"shell_thickness", "close_holes", "close_holes_max"})
      if (v[f].present)
        I.cfg->notes.push_back(I.value_at(std::string("print.") + f, at) + "print." + f +
                               " has no effect: print.shell is false (the printed shell's setting)");
  p.formats.clear();
  std::stringstream ss(v["formats"].str);
  std::string f;
  const std::vector<std::string> known{"stl", "obj", "ply", "scad", "vdb"};
  while (std::getline(ss, f, ',')) {
    f = trim(f);
    std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (f.empty()) continue;
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      const std::string near = core::closest_name(f, known);
      throw InvalidInput(I.value_at("print.formats", at) + "print.formats: unknown format '" + f +
                         "' (allowed: stl, obj, ply, scad, vdb)" +
                         (near.empty() ? "" : "; did you mean '" + near + "'?"));
    }
    if (std::find(p.formats.begin(), p.formats.end(), f) == p.formats.end()) p.formats.push_back(f);  // once each
  }
  if (p.formats.empty())
    throw InvalidInput(I.value_at("print.formats", at) +
                       "print.formats must name at least one of stl, obj, ply, scad, vdb");
  if (!p.veins && !p.shell) {  // named where it was given: the script's line or a --set
    const std::string veins_at = I.value_at("print.veins", ""), shell_at = I.value_at("print.shell", "");
    throw InvalidInput((veins_at.empty() && shell_at.empty() ? at
                        : veins_at.empty()                   ? shell_at
                                                             : veins_at) +
                       "print{...} with veins = false needs shell = true (nothing to print)");
  }
  I.cfg->print = p;
}

void section_output(Impl& I, const std::string& at) {
  I.once("output", at);
  Values v = I.read_section("output", 1, at, &I.cfg->resolved["output"]);
  I.cfg->output.ply = v["ply"].flag;
  I.cfg->output.obj = v["obj"].flag;
  I.cfg->output.every = static_cast<std::uint64_t>(v["every"].num);
  I.cfg->output.checkpoint_every = static_cast<std::uint64_t>(v["checkpoint_every"].num);
  I.cfg->output.checkpoint_seconds = v["checkpoint_seconds"].num;
  I.cfg->output.checkpoint_minutes = v["checkpoint_minutes"].num;
  I.cfg->output.png = v["png"].flag;
  I.cfg->output.png_size = static_cast<int>(v["png_size"].num);
  I.cfg->output.svg_size = v["svg_size"].num;
  if (v["svg_size"].present) I.cfg->output.svg_size_at = I.value_at("output.svg_size", at);
  I.cfg->output.svg_join_veins = v["svg_paths"].str == "veins";
  if (v["svg_paths"].present) I.cfg->output.svg_paths_at = I.value_at("output.svg_paths", at);
}

namespace {
// Shapes and constraints a script may place: each keeps C++ state the Lua memory limit does not see (a
// loop of a million disc{} calls took 770 MB)
constexpr std::size_t kMaxPlacements = 250000;

void count_placement(Impl& I, const std::string& kind, const std::string& at) {
  if (++I.placements > kMaxPlacements)
    throw InvalidInput(at + kind + "{...}: a script may place at most " + std::to_string(kMaxPlacements) +
                       " shapes and constraints (cell{...} in a loop? a disc{} or rectangle{} places many cells "
                       "in one call)");
}
}  // namespace

void section_shape(Impl& I, const std::string& kind, const std::string& at) {
  count_placement(I, kind, at);
  ShapeCall call{kind, I.read_section(kind, 1, at, nullptr), at};
  I.shapes.push_back(std::move(call));
}

namespace {

/// "fnv1a64:<hex>" of a file's bytes, read in blocks; "" if it cannot be read (load_mesh says why).
std::string file_fingerprint(const std::filesystem::path& path) {
  // a pipe would block and a device such as /dev/zero never ends: only a regular file is read
  if (std::error_code ec; !std::filesystem::is_regular_file(path, ec)) return "";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::uint64_t h = core::fnv1a64(nullptr, 0);
  std::vector<char> block(1 << 20);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    h = core::fnv1a64(block.data(), static_cast<std::size_t>(in.gcount()), h);
  }
  return in.bad() ? "" : "fnv1a64:" + core::hex64(h);
}

/// The unit vector along `n`; a zero vector has no direction and is refused naming the parameter.
Vec3 unit_vector(const Vec3& n, const std::string& name) {
  const double m = n.cwiseAbs().maxCoeff();
  if (!(m > 0)) throw InvalidInput(name + " must be a non-zero vector (a direction), got {0, 0, 0}");
  // a vector whose square underflows ({0, 0, 1e-300}) or overflows is scaled first: its direction counts
  return n.norm() > 0 && std::isfinite(n.norm()) ? n.normalized() : Vec3(n / m).normalized();
}

}  // namespace

void section_constraint(Impl& I, const std::string& kind, const std::string& at) {
  count_placement(I, kind, at);
  nlohmann::json rec;
  Values v = I.read_section(kind, 1, at, &rec);
  rec["kind"] = kind;
  // run.json lists the first 1,000, as the shapes: 100,000 ball{} calls made a 14 MB run.json (review)
  nlohmann::json& listed = I.cfg->resolved["constraints"];
  nlohmann::json* kept = nullptr;  // (a mesh adds what its file held)
  if (listed.size() < 1000)
    kept = &listed.emplace_back(rec);
  else
    I.cfg->resolved["constraints_not_listed"] = I.cfg->resolved.value("constraints_not_listed", std::size_t{0}) + 1;
  if (I.first_constraint.empty()) I.first_constraint = at + kind;
  forms::Obstacles& o = I.cfg->scene.obstacles;
  forms::ObstacleNames& names = I.cfg->scene.obstacle_names;  // the scene's messages say the script line
  const std::string name = at + kind + "{...}";
  if (kind == "ground") {
    o.half_spaces.push_back({Vec3(0, 0, v["height"].num), Vec3::UnitZ()});
    names.half_spaces.push_back(name);
  } else if (kind == "half_space") {
    o.half_spaces.push_back({v["point"].vec, unit_vector(v["normal"].vec, at + kind + ".normal")});
    names.half_spaces.push_back(name);
  } else if (kind == "ball") {
    o.spheres.push_back({v["centre"].vec, v["radius"].num});
    names.spheres.push_back(name);
  } else if (kind == "box") {
    const Vec3 lo = v["min"].vec, hi = v["max"].vec;
    if ((lo.array() >= hi.array()).any()) throw InvalidInput(at + "box.min must be below box.max in x, y and z");
    o.boxes.push_back({lo, hi});
    names.boxes.push_back(name);
  } else if (kind == "mesh") {
    const std::filesystem::path file = script_file(I, v["file"].str, "mesh.file", at);
    forms::TriangleMesh mesh;
    try {
      // refused before its fingerprint reads it through; that, for a resume to compare, is the same before and
      // after reading it, or it changed meanwhile
      check_file_fits(file, kMeshBytesPerByte, "mesh '" + file.string() + "'");
      const std::string before = file_fingerprint(file);
      mesh = forms::load_mesh(file);
      if (file_fingerprint(file) != before)
        throw core::FileError(file.string() + " changed while it was read; run again once it is written");
      I.cfg->mesh_files.emplace_back(file, before);
    } catch (const std::exception& e) {
      throw InvalidInput(at + "mesh.file: " + file_message(e));
    }
    scale_mesh(mesh.vertices, v["scale"].num, v["offset"].vec, v["file"].str, at + "mesh: ");
    double area = 0;  // as volume{file} and surface{file}: a wall of no area stops nothing
    for (const auto& t : mesh.triangles)
      area += (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
    if (!(area > 0))
      throw InvalidInput(at + "mesh: every triangle of " + v["file"].str +
                         " is degenerate (zero area), so cells would cross it as if it were not there");
    if (kept) {  // what was read, in model units: a file in other units shows here (and a changed file)
      Vec3 lo = mesh.vertices.front(), hi = lo;
      for (const Vec3& p : mesh.vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      (*kept)["triangles"] = mesh.triangles.size();
      (*kept)["bounds"] = {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}};
      (*kept)["fingerprint"] = I.cfg->mesh_files.back().second;
    }
    o.meshes.push_back(std::move(mesh));
    names.meshes.push_back(name);
  } else if (kind == "attractor") {
    I.cfg->scene.attractors.push_back({v["position"].vec, v["strength"].num, v["radius"].num});
  }
}

/// Memory the cells take at the peak of a step, bytes a cell (links, grid, forces and the step's scratch:
/// 685 measured with 2 million cells, December 2026).
constexpr double kBytesPerCell = 700;

/// `mb` megabytes, in GB from 1 GB on.
std::string megabytes_text(double mb) {
  return mb < 1000 ? core::number_text(std::round(mb)) + " MB" : core::number_text(std::round(mb / 100) / 10) + " GB";
}

/// The memory `cells` take at the peak.
std::string memory_of(double cells) { return megabytes_text(cells * kBytesPerCell / 1e6); }

/// The cells run.max_memory (else the machine's memory) holds, and how that budget is named in a message.
std::pair<double, std::string> cell_budget(const SceneConfig& cfg) {
  double mb = cfg.max_memory_mb;
  std::string name = "run.max_memory = " + core::number_text(mb) + " MB";
  if (!(mb > 0)) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return {std::numeric_limits<double>::infinity(), ""};
    double machine = static_cast<double>(pages) * static_cast<double>(page) / 1e6;
    std::string what = "this machine's ";
    // in a container or a job's control group, the lowest limit on its way up to the root, where lower
    std::ifstream groups("/proc/self/cgroup");
    const double limit = control_group_memory_limit(groups, "/sys/fs/cgroup") / 1e6;
    if (limit < machine) {
      machine = limit;
      what = "this container's memory limit, ";
    }
    mb = 0.75 * machine;  // the rest for the outputs' buffers, the system and whatever else runs
    name = "three quarters of " + what + megabytes_text(machine);
  }
  return {mb * 1e6 / kBytesPerCell, name};
}

void build_shapes(Impl& I) {
  SceneConfig& cfg = *I.cfg;
  std::vector<std::size_t> shape_first;  // where each shape call's cells begin, for check_coincident_cells
  std::vector<std::string> shape_where;
  const double rest = cfg.scene.cells.rest_length;
  nlohmann::json& rec = cfg.resolved["shapes"];
  rec = nlohmann::json::array();
  const auto [budget, budget_name] = cell_budget(cfg);
  if (!cfg.colonisation || cfg.colonisation->on_cells) {
    const double max_cells = static_cast<double>(cfg.scene.cells.division.max_cells);
    if (max_cells > budget)  // (the budget is checked here, at the start, and not while the cells grow)
      cfg.notes.push_back("division.max_cells = " + std::to_string(cfg.scene.cells.division.max_cells) +
                          " cells would take about " + memory_of(max_cells) + " at the peak, more than " + budget_name +
                          (cfg.max_memory_mb > 0
                               ? " (lower division.max_cells, or raise run.max_memory)"
                               : ": a run that grows that far runs out of memory (lower division.max_cells)"));
  }
  for (ShapeCall& s : I.shapes) {
    Values& v = s.values;
    auto spacing = [&]() { return v["spacing"].present ? v["spacing"].num : rest; };
    nlohmann::json r = {{"kind", s.kind}};
    std::vector<Vec3> points;
    try {
      // a shape far beyond division.max_cells is refused before it is built (gigabytes and seconds for
      // nothing); the estimate is close, not exact, so a shape near the limit is built and counted below
      const double estimate = s.kind == "disc" ? forms::hex_disc_cells(v["radius"].num, spacing())
                              : s.kind == "rectangle"
                                  ? forms::hex_rectangle_cells(v["width"].num, v["height"].num, spacing())
                              : s.kind == "sphere" ? forms::sphere_cells(v["radius"].num, spacing())
                              : s.kind == "line"   ? forms::line_cells(v["from"].vec, v["to"].vec, spacing())
                                                   : 0.0;
      const double max_cells = static_cast<double>(cfg.scene.cells.division.max_cells);
      const double placed = static_cast<double>(cfg.initial_cells.size());
      if (estimate <= 5e7 && placed + estimate > 1.1 * max_cells + 100)
        throw InvalidInput(
            "the initial shapes would make about " + core::number_text(std::round(placed + estimate)) +
            " cells, more than division.max_cells = " + std::to_string(cfg.scene.cells.division.max_cells) +
            ", which also caps the cells placed (raise it, or place fewer)");
      if (estimate <= 5e7 && placed + estimate > budget)
        throw InvalidInput("the initial shapes would make about " +
                           std::to_string(static_cast<std::uint64_t>(placed + estimate)) + " cells, which take about " +
                           memory_of(placed + estimate) + " at the peak, more than " + budget_name +
                           "; place fewer (a larger spacing or a smaller shape)" +
                           (cfg.max_memory_mb > 0 ? "" : ", or set run.max_memory (MB) if there is more to use"));
      auto xyz = [](const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
      if (s.kind == "disc") {
        points = forms::hex_disc(v["centre"].vec, unit_vector(v["normal"].vec, "normal"), v["radius"].num, spacing());
        r["radius"] = v["radius"].num;
        r["centre"] = xyz(v["centre"].vec);
        r["normal"] = xyz(v["normal"].vec);
      } else if (s.kind == "rectangle") {
        points = forms::hex_rectangle(v["centre"].vec, unit_vector(v["normal"].vec, "normal"), v["width"].num,
                                      v["height"].num, spacing());
        r["width"] = v["width"].num;
        r["height"] = v["height"].num;
        r["centre"] = xyz(v["centre"].vec);
        r["normal"] = xyz(v["normal"].vec);
      } else if (s.kind == "sphere") {
        points = forms::sphere_points(v["centre"].vec, v["radius"].num, spacing());
        r["radius"] = v["radius"].num;
        r["centre"] = xyz(v["centre"].vec);
      } else if (s.kind == "line") {
        points = forms::line_points(v["from"].vec, v["to"].vec, spacing());
        r["from"] = xyz(v["from"].vec);
        r["to"] = xyz(v["to"].vec);
      } else if (s.kind == "cell") {
        cfg.initial_cells.push_back({v["at"].vec, v["fixed"].flag});
        r["at"] = xyz(v["at"].vec);
        r["fixed"] = v["fixed"].flag;
      } else if (s.kind == "petiole") {
        cfg.scene.petioles.push_back(
            {v["at"].vec, v["fixed"].flag, static_cast<std::uint64_t>(v["step"].num), s.where});
        r["at"] = {v["at"].vec.x(), v["at"].vec.y(), v["at"].vec.z()};
        r["fixed"] = v["fixed"].flag;
        r["step"] = static_cast<std::uint64_t>(v["step"].num);
      }
    } catch (const std::exception& e) {
      std::string given;  // values of this call that came from the command line, not the script's line
      for (const auto& [name, value] : v)
        if (!value.set_by.empty()) given += (given.empty() ? " (given by " : ", ") + value.set_by;
      throw InvalidInput(s.where + s.kind + ": " + core::error_text(e) + (given.empty() ? "" : given + ")"));
    }
    if (s.kind != "cell" && s.kind != "petiole") r["spacing"] = spacing();
    // a petiole turns the nearest cell into one or adds a cell, at its step: not known here
    if (s.kind != "petiole") r["cells"] = s.kind == "cell" ? std::size_t{1} : points.size();
    if (s.kind != "petiole" && (shape_where.empty() || shape_where.back() != s.where + s.kind)) {
      shape_first.push_back(cfg.initial_cells.size() - (s.kind == "cell" ? 1 : 0));
      shape_where.push_back(s.where + s.kind);
    }
    for (const Vec3& p : points) cfg.initial_cells.push_back({p, false});
    if (cfg.initial_cells.size() > cfg.scene.cells.division.max_cells)
      throw InvalidInput(
          s.where + s.kind + ": the initial shapes make " + std::to_string(cfg.initial_cells.size()) +
          " cells, more than division.max_cells = " + std::to_string(cfg.scene.cells.division.max_cells) +
          ", which also caps the cells placed (raise it, or place fewer)");
    // run.json lists the first shape calls; a script placing a point cloud cell by cell (250,000 cell{} calls)
    // made a 40 MB run.json: the rest are counted (the script, whose hash run.json keeps, makes them again)
    constexpr std::size_t kListed = 1000;
    if (rec.size() < kListed) {
      rec.push_back(r);
    } else {
      nlohmann::json& more = cfg.resolved["shapes_not_listed"];
      if (more.is_null()) more = {{"calls", 0}, {"cells", 0}};
      more["calls"] = more["calls"].get<std::size_t>() + 1;
      more["cells"] = more["cells"].get<std::size_t>() + (s.kind == "cell" ? 1 : points.size());
    }
  }
  check_coincident_cells(cfg, shape_first, shape_where);
  note_lost_meshes(cfg);
}

}  // namespace cellform::app
