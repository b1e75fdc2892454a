// The sections of the growth-script API (cells{}, division{}, disc{}, ground{}, print{}, ...): each
// reads its table against the schema and fills the scene configuration.
#include "app/script_impl.h"
#include "forms/obstacles.h"
#include "forms/shapes.h"
#include "venation/domain.h"

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
  p.max_speed = v["max_speed"].num;
  p.weights[static_cast<int>(cells::CellType::general)] = general;
  const std::pair<const char*, cells::CellType> types[] = {{"petiole", cells::CellType::petiole},
                                                           {"vein", cells::CellType::vein}};
  for (const auto& [name, type] : types) {
    if (lua_type(I.L, 1) == LUA_TTABLE)
      lua_getfield(I.L, 1, name);
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
  } else {
    d.direction = dir.str == "axis"              ? cells::SplitDirection::axis
                  : dir.str == "tangent"         ? cells::SplitDirection::tangent
                  : dir.str == "radial"          ? cells::SplitDirection::radial
                  : dir.str == "circumferential" ? cells::SplitDirection::circumferential
                  : dir.str == "auxin"           ? cells::SplitDirection::rule
                                                 : cells::SplitDirection::random;
    I.cfg->scene.split_along_auxin = dir.str == "auxin";
  }
  if ((d.direction == cells::SplitDirection::axis || d.direction == cells::SplitDirection::circumferential) &&
      d.axis.norm() == 0)
    throw InvalidInput(at + "division.axis must be a non-zero vector for direction = \"" + dir.str + "\"");
  if (v["rule"].ref != LUA_NOREF) I.divides_ref = v["rule"].ref;
}

void section_run(Impl& I, const std::string& at) {
  I.once("run", at);
  Values v = I.read_section("run", 1, at, &I.cfg->resolved["run"]);
  I.cfg->steps = static_cast<std::uint64_t>(v["steps"].num);
  I.cfg->seed = static_cast<std::uint64_t>(v["seed"].num);
}

void section_venation(Impl& I, const std::string& at) {
  I.once("venation", at);
  Values v = I.read_section("venation", 1, at, &I.cfg->resolved["venation"]);
  venation::Params p;
  p.threshold = v["threshold"].num;
  if (v["source"].ref != LUA_NOREF)
    I.source_ref = v["source"].ref;
  else
    p.source = v["source"].num;
  p.murray_exponent = v["murray_exponent"].num;
  p.radius_scale = v["radius_scale"].num;
  p.min_radius = v["min_radius"].num;
  p.every = static_cast<std::uint32_t>(v["every"].num);
  I.cfg->scene.venation = p;
}

namespace {

/// Refuses a second source domain: a script grows veins in one leaf{}, volume{} or surface{}.
void one_domain(Impl& I, const std::string& section, const std::string& at) {
  for (const std::string other : {"leaf", "volume", "surface"})
    if (other != section && I.sections_seen.count(other))
      throw InvalidInput(at + section + "{...}: the veins already grow in " + other + "{...} (at " +
                         I.sections_seen[other] + "); a script has one of leaf{}, volume{} and surface{}");
}

/// The seeds = {{x, y, z}, ...} field of the section table at stack index 1 (also one point {x, y, z}).
std::vector<Vec3> read_points(Impl& I, const std::string& section, const std::string& at) {
  lua_State* L = I.L;
  std::vector<Vec3> out;
  lua_getfield(L, 1, "seeds");
  const int idx = lua_gettop(L);
  auto fail = [&](const std::string& what) {
    lua_settop(L, idx - 1);
    return InvalidInput(at + section + ".seeds must be a list of points {{x, y, z}, ...} in model units; " + what);
  };
  if (lua_type(L, idx) == LUA_TNIL) {
    lua_pop(L, 1);
    return out;
  }
  auto read_point = [&](int t, const std::string& which) {
    if (lua_type(L, t) != LUA_TTABLE || lua_rawlen(L, t) != 3) throw fail(which + " is not {x, y, z}");
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      lua_rawgeti(L, t, k + 1);
      if (lua_type(L, -1) != LUA_TNUMBER) throw fail(which + " has a component that is not a number");
      p[k] = lua_tonumber(L, -1);
      lua_pop(L, 1);
    }
    if (!p.allFinite()) throw fail(which + " is not finite");
    return p;
  };
  lua_rawgeti(L, idx, 1);
  const bool single = lua_type(L, -1) == LUA_TNUMBER;
  lua_pop(L, 1);
  if (single) {
    out.push_back(read_point(idx, "the point"));
  } else {
    const auto n = static_cast<int>(lua_rawlen(L, idx));
    if (n == 0) throw fail("got an empty table");
    for (int i = 1; i <= n; ++i) {
      lua_rawgeti(L, idx, i);
      out.push_back(read_point(lua_gettop(L), "entry " + std::to_string(i)));
      lua_pop(L, 1);
    }
  }
  lua_settop(L, idx - 1);
  return out;
}

venation::Mesh read_domain_mesh(Impl& I, const std::string& section, const Values& v, const std::string& at) {
  std::filesystem::path file = v.at("file").str;
  if (file.is_relative()) file = I.script_dir / file;
  try {
    forms::TriangleMesh m = forms::load_mesh(file);
    venation::Mesh out;
    out.vertices = std::move(m.vertices);
    for (Vec3& p : out.vertices) p *= v.at("scale").num;
    out.triangles = std::move(m.triangles);
    return out;
  } catch (const std::exception& e) {
    throw InvalidInput(at + section + ".file: " + e.what());
  }
}

}  // namespace

std::string script_domain_message(const std::string& message, const std::string& section) {
  std::string m = message;
  const std::pair<std::string, std::string> names[] = {{"domain.initial_nodes", section + ".seeds"},
                                                       {"domain.initial_sources", section + ".sources"},
                                                       {"domain.box", "volume.box"},
                                                       {"domain.ball", "volume.ball"},
                                                       {"domain.volume", "volume.file"},
                                                       {"domain.surface", section + ".file"}};
  for (const auto& [from, to] : names)
    for (std::size_t at = m.find(from); at != std::string::npos; at = m.find(from, at + to.size()))
      m.replace(at, from.size(), to);
  return m;
}

void section_domain(Impl& I, const std::string& section, const std::string& at) {
  I.once(section, at);
  one_domain(I, section, at);
  nlohmann::json& rec = I.cfg->resolved[section];
  Values v = I.read_section(section, 1, at, &rec);
  if (!I.cfg->colonisation) I.cfg->colonisation.emplace();
  ColonisationSpec& spec = *I.cfg->colonisation;
  venation::Domain& d = spec.domain;
  lua_State* L = I.L;
  // a nested table such as volume{box = {min = ..., max = ...}}, read against the schema's "volume.box"
  auto nested = [&](const char* name, Values& out) {
    if (lua_type(L, 1) != LUA_TTABLE) return false;
    lua_getfield(L, 1, name);
    const int idx = lua_gettop(L);
    if (lua_type(L, idx) == LUA_TNIL) {
      lua_pop(L, 1);
      return false;
    }
    try {
      out = I.read_section(section + "." + name, idx, at, &rec[name]);
    } catch (...) {
      lua_settop(L, idx - 1);
      throw;
    }
    lua_settop(L, idx - 1);
    return true;
  };
  std::vector<Vec3> seeds = read_points(I, section, at);
  const bool file = !v["file"].str.empty();
  if (section == "volume") {
    Values box, ball;
    const bool is_box = nested("box", box), is_ball = nested("ball", ball);
    if (int(is_box) + int(is_ball) + int(file) != 1)
      throw InvalidInput(at +
                         "volume{...} needs exactly one of box = {min = {x, y, z}, max = {x, y, z}}, "
                         "ball = {centre = {x, y, z}, radius = r} or file = \"shape.stl\"");
    if (is_box) {
      d.kind = venation::DomainKind::box;
      d.box_min = box["min"].vec;
      d.box_max = box["max"].vec;
      if ((d.box_min.array() >= d.box_max.array()).any())
        throw InvalidInput(at + "volume.box.min must be below volume.box.max in x, y and z");
      if (seeds.empty())
        seeds.push_back(Vec3((d.box_min.x() + d.box_max.x()) / 2, (d.box_min.y() + d.box_max.y()) / 2, d.box_min.z()));
    } else if (is_ball) {
      d.kind = venation::DomainKind::ball;
      d.centre = ball["centre"].vec;
      d.radius = ball["radius"].num;
      if (seeds.empty()) seeds.push_back(d.centre - d.radius * Vec3::UnitZ());
    } else {
      d.kind = venation::DomainKind::volume;
      d.mesh = read_domain_mesh(I, section, v, at);
      if (seeds.empty())
        throw InvalidInput(at + "volume{file = ...} needs seeds = {{x, y, z}, ...}: the seed vein nodes inside it");
    }
  } else {
    d.kind = venation::DomainKind::surface;
    spec.on_cells = v["cells"].flag;
    if (file == spec.on_cells)
      throw InvalidInput(at + "surface{...} needs either file = \"shape.obj\" or cells = true (the grown cell sheet)");
    if (file) {
      d.mesh = read_domain_mesh(I, section, v, at);
      if (seeds.empty())
        throw InvalidInput(at + "surface{file = ...} needs seeds = {{x, y, z}, ...}: the seed vein nodes on it");
    }
  }
  d.initial_nodes = seeds;
  rec["seeds"] = nlohmann::json::array();
  for (const Vec3& p : seeds) rec["seeds"].push_back({p.x(), p.y(), p.z()});
  if (spec.on_cells) return;  // the sheet exists once the cells have grown
  try {
    venation::PreparedDomain check(d);
  } catch (const InvalidInput& e) {
    throw InvalidInput(at + script_domain_message(e.what(), section));
  }
}

void finish_colonisation(Impl& I) {
  ColonisationSpec& spec = *I.cfg->colonisation;
  if (spec.domain.kind == venation::DomainKind::leaf) return;
  const std::string at = I.sections_seen["colonisation"];
  nlohmann::json& rec = I.cfg->resolved["colonisation"];
  venation::ColonisationParams& p = spec.params;
  if (spec.growth_given && p.growth != venation::GrowthMode::none)
    throw InvalidInput(at + "colonisation.growth = \"" + rec.value("growth", std::string()) +
                       "\" grows a leaf blade; a volume{...} or surface{...} does not grow (leave growth out or "
                       "set it to \"none\")");
  p.growth = venation::GrowthMode::none;
  p.initial_scale = p.final_scale = 1;
  p.scale_step = 0;
  rec["growth"] = "none";
  for (const char* unused : {"initial_length", "final_length", "length_step"}) rec.erase(unused);
  try {
    venation::validate(spec.domain, p);
  } catch (const std::exception& e) {
    throw InvalidInput(at + e.what());
  }
}

void section_leaf(Impl& I, const std::string& at) {
  I.once("leaf", at);
  one_domain(I, "leaf", at);
  Values v = I.read_section("leaf", 1, at, &I.cfg->resolved["leaf"]);
  if (!I.cfg->colonisation) I.cfg->colonisation.emplace();
  venation::Leaf& leaf = I.cfg->colonisation->leaf;
  try {
    if (!v["file"].str.empty()) {
      std::filesystem::path file = v["file"].str;
      if (file.is_relative()) file = I.script_dir / file;
      leaf.outline = venation::read_outline(file);
    } else {
      venation::ShapeParams sp;
      const std::string k = v["shape"].str;
      sp.kind = k == "ellipse"   ? venation::ShapeKind::ellipse
                : k == "cordate" ? venation::ShapeKind::cordate
                : k == "lobed"   ? venation::ShapeKind::lobed
                : k == "palmate" ? venation::ShapeKind::palmate
                                 : venation::ShapeKind::ovate;
      sp.length = 1;
      sp.width = v["width"].num;
      sp.lobes = static_cast<int>(v["lobes"].num);
      sp.lobe_depth = v["lobe_depth"].num;
      if (v["teeth"].num > 0) sp.teeth.push_back({v["tooth_depth"].num, static_cast<int>(v["teeth"].num)});
      leaf.outline = venation::make_outline(sp);
    }
    const int seeds = static_cast<int>(v["seeds"].num);
    leaf.initial_nodes.clear();
    for (int i = 0; i < seeds && seeds > 1; ++i) {
      const double spread = v["seed_spread"].num;
      leaf.initial_nodes.push_back(venation::Vec2(-spread / 2 + spread * i / (seeds - 1), 0.001));
    }
    venation::validate(leaf);
  } catch (const std::exception& e) {
    throw InvalidInput(at + "leaf: " + e.what());
  }
}

void section_colonisation(Impl& I, const std::string& at) {
  I.once("colonisation", at);
  Values v = I.read_section("colonisation", 1, at, &I.cfg->resolved["colonisation"]);
  if (!I.cfg->colonisation) I.cfg->colonisation.emplace();
  venation::ColonisationParams& p = I.cfg->colonisation->params;
  p.type = v["type"].str == "closed" ? venation::VenationType::closed : venation::VenationType::open;
  p.neighbourhood =
      v["neighbourhood"].str == "urquhart" ? venation::Neighbourhood::urquhart : venation::Neighbourhood::exact;
  p.kill_distance = v["kill_distance"].num;
  p.source_birth_distance = v["birth_distance"].num;
  p.vein_birth_distance = v["vein_birth_distance"].num > 0 ? v["vein_birth_distance"].num : v["birth_distance"].num;
  p.node_distance = 1;
  p.darts_per_area = v["darts"].num * 1e-6;
  const std::string g = v["growth"].str;
  p.growth = g == "none"       ? venation::GrowthMode::none
             : g == "isogonic" ? venation::GrowthMode::uniform
                               : venation::GrowthMode::marginal;
  p.initial_scale = v["initial_length"].num;
  p.final_scale = g == "none" ? p.initial_scale : v["final_length"].num;
  p.scale_step = g == "none" ? 0 : v["length_step"].num;
  p.max_steps = static_cast<std::size_t>(v["max_steps"].num);
  p.max_nodes = static_cast<std::size_t>(v["max_nodes"].num);
  I.cfg->colonisation->growth_given = v["growth"].present;
  I.cfg->colonisation->widths.exponent = v["murray_exponent"].num;
  I.cfg->colonisation->widths.tip_radius = v["tip_radius"].num;
  try {
    venation::validate(p);
  } catch (const std::exception& e) {
    throw InvalidInput(at + e.what());
  }
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
  p.voxel_size = v["voxel_size"].num;
  p.adaptivity = v["adaptivity"].num;
  p.max_memory_mb = v["max_memory"].num;
  p.pieces = v["pieces"].str;
  p.fill_cavities = v["fill_cavities"].flag;
  p.formats.clear();
  std::stringstream ss(v["formats"].str);
  std::string f;
  const std::vector<std::string> known{"stl", "obj", "ply", "scad", "vdb"};
  while (std::getline(ss, f, ',')) {
    f = trim(f);
    if (f.empty()) continue;
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      const std::string near = core::closest_name(f, known);
      throw InvalidInput(at + "print.formats: unknown format '" + f + "' (allowed: stl, obj, ply, scad, vdb)" +
                         (near.empty() ? "" : "; did you mean '" + near + "'?"));
    }
    p.formats.push_back(f);
  }
  if (p.formats.empty()) throw InvalidInput(at + "print.formats must name at least one of stl, obj, ply, scad, vdb");
  if (!p.veins && !p.shell)
    throw InvalidInput(at + "print{...} with veins = false needs shell = true (nothing to print)");
  I.cfg->print = p;
}

void section_output(Impl& I, const std::string& at) {
  I.once("output", at);
  Values v = I.read_section("output", 1, at, &I.cfg->resolved["output"]);
  I.cfg->output.ply = v["ply"].flag;
  I.cfg->output.obj = v["obj"].flag;
  I.cfg->output.every = static_cast<std::uint64_t>(v["every"].num);
  I.cfg->output.checkpoint_every = static_cast<std::uint64_t>(v["checkpoint_every"].num);
}

void section_shape(Impl& I, const std::string& kind, const std::string& at) {
  ShapeCall call{kind, I.read_section(kind, 1, at, nullptr), at};
  I.shapes.push_back(std::move(call));
}

void section_constraint(Impl& I, const std::string& kind, const std::string& at) {
  nlohmann::json rec;
  Values v = I.read_section(kind, 1, at, &rec);
  rec["kind"] = kind;
  I.cfg->resolved["constraints"].push_back(rec);
  forms::Obstacles& o = I.cfg->scene.obstacles;
  auto unit = [&](const Vec3& n, const char* what) {
    if (n.norm() == 0) throw InvalidInput(at + kind + "." + what + " must be a non-zero vector");
    return Vec3(n.normalized());
  };
  if (kind == "ground") {
    o.half_spaces.push_back({Vec3(0, 0, v["height"].num), Vec3::UnitZ()});
  } else if (kind == "half_space") {
    o.half_spaces.push_back({v["point"].vec, unit(v["normal"].vec, "normal")});
  } else if (kind == "ball") {
    o.spheres.push_back({v["centre"].vec, v["radius"].num});
  } else if (kind == "box") {
    const Vec3 lo = v["min"].vec, hi = v["max"].vec;
    if ((lo.array() >= hi.array()).any()) throw InvalidInput(at + "box.min must be below box.max in x, y and z");
    o.boxes.push_back({lo, hi});
  } else if (kind == "mesh") {
    std::filesystem::path file = v["file"].str;
    if (file.is_relative()) file = I.script_dir / file;
    try {
      forms::TriangleMesh mesh = forms::load_mesh(file);
      for (Vec3& p : mesh.vertices) p *= v["scale"].num;
      o.meshes.push_back(std::move(mesh));
    } catch (const std::exception& e) {
      throw InvalidInput(at + "mesh: " + e.what());
    }
  } else if (kind == "attractor") {
    I.cfg->scene.attractors.push_back({v["position"].vec, v["strength"].num, v["radius"].num});
  }
}

namespace {
Vec3 unit_or(const Vec3& n, const Vec3& fallback) { return n.norm() > 0 ? Vec3(n.normalized()) : fallback; }

}  // namespace

void build_shapes(Impl& I) {
  SceneConfig& cfg = *I.cfg;
  const double rest = cfg.scene.cells.rest_length;
  nlohmann::json& rec = cfg.resolved["shapes"];
  rec = nlohmann::json::array();
  for (ShapeCall& s : I.shapes) {
    Values& v = s.values;
    auto spacing = [&]() { return v["spacing"].present ? v["spacing"].num : rest; };
    nlohmann::json r = {{"kind", s.kind}};
    std::vector<Vec3> points;
    try {
      if (s.kind == "disc") {
        points = forms::hex_disc(v["centre"].vec, unit_or(v["normal"].vec, Vec3::UnitZ()), v["radius"].num, spacing());
        r["radius"] = v["radius"].num;
        r["centre"] = {v["centre"].vec.x(), v["centre"].vec.y(), v["centre"].vec.z()};
      } else if (s.kind == "rectangle") {
        points = forms::hex_rectangle(v["centre"].vec, unit_or(v["normal"].vec, Vec3::UnitZ()), v["width"].num,
                                      v["height"].num, spacing());
        r["width"] = v["width"].num;
        r["height"] = v["height"].num;
      } else if (s.kind == "sphere") {
        points = forms::sphere_points(v["centre"].vec, v["radius"].num, spacing());
        r["radius"] = v["radius"].num;
      } else if (s.kind == "line") {
        points = forms::line_points(v["from"].vec, v["to"].vec, spacing());
      } else if (s.kind == "cell") {
        cfg.initial_cells.push_back({v["at"].vec, v["fixed"].flag});
        r["at"] = {v["at"].vec.x(), v["at"].vec.y(), v["at"].vec.z()};
      } else if (s.kind == "petiole") {
        cfg.scene.petioles.push_back(
            {v["at"].vec, v["fixed"].flag, static_cast<std::uint64_t>(v["step"].num), s.where});
        r["at"] = {v["at"].vec.x(), v["at"].vec.y(), v["at"].vec.z()};
        r["fixed"] = v["fixed"].flag;
        r["step"] = v["step"].num;
      }
    } catch (const std::exception& e) {
      throw InvalidInput(s.where + s.kind + ": " + e.what());
    }
    if (s.kind != "cell" && s.kind != "petiole") r["spacing"] = spacing();
    r["cells"] = points.size();
    for (const Vec3& p : points) cfg.initial_cells.push_back({p, false});
    if (cfg.initial_cells.size() > cfg.scene.cells.division.max_cells)
      throw InvalidInput(
          s.where + s.kind + ": the initial shapes make " + std::to_string(cfg.initial_cells.size()) +
          " cells, more than division.max_cells = " + std::to_string(cfg.scene.cells.division.max_cells));
    rec.push_back(r);
  }
}

}  // namespace cellform::app
