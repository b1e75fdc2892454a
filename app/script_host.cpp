// Lua 5.4 sandbox and the growth-script API (sections such as cells{}, division{}, disc{}).
#include "app/script_host.h"

#include <lua.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <set>
#include <sstream>

#include "app/schema.h"
#include "core/errors.h"
#include "forms/obstacles.h"
#include "forms/shapes.h"

namespace cellform::app {

using core::InvalidInput;
using core::Vec3;

namespace {

constexpr int kHookEvery = 1000;  // instructions between budget checks

/// A parameter value after conversion from Lua or from a --set string.
struct Value {
  bool present = false;  // given by the script or --set (false: the schema default applies, if any)
  double num = 0;
  Vec3 vec = Vec3::Zero();
  bool flag = false;
  std::string str;
  int ref = LUA_NOREF;  // a function in the registry
};

using Values = std::map<std::string, Value>;

/// A call of a shape function, evaluated after the script has run (when rest_length is known).
struct ShapeCall {
  std::string kind;
  Values values;
  std::string where;
};

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  const auto b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

bool parse_double(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size();
}

bool parse_vec(std::string text, Vec3& out) {
  text = trim(text);
  if (text.size() >= 2 && text.front() == '{' && text.back() == '}') text = text.substr(1, text.size() - 2);
  std::stringstream ss(text);
  std::string part;
  int n = 0;
  while (std::getline(ss, part, ',')) {
    if (n == 3 || !parse_double(part, out[n])) return false;
    ++n;
  }
  return n == 3;
}

std::string choices_list(const std::string& choices) {
  std::string s = choices;
  for (char& c : s)
    if (c == '|') c = ',';
  return s;
}

bool is_choice(const std::string& choices, const std::string& v) {
  std::stringstream ss(choices);
  std::string part;
  while (std::getline(ss, part, '|'))
    if (part == v) return true;
  return false;
}

nlohmann::json to_json(const Field& f, const Value& v) {
  switch (f.kind) {
    case Kind::number:
      return v.num;
    case Kind::integer:
      return static_cast<long long>(v.num);
    case Kind::boolean:
      return v.flag;
    case Kind::vec3:
      return nlohmann::json::array({v.vec.x(), v.vec.y(), v.vec.z()});
    case Kind::text:
    case Kind::choice:
      return v.str;
    case Kind::choice_or_function:
      return v.ref != LUA_NOREF ? std::string("<function>") : v.str;
    case Kind::function:
      return v.ref != LUA_NOREF ? nlohmann::json("<function>") : nlohmann::json();
    case Kind::number_or_function:
      return v.ref != LUA_NOREF ? nlohmann::json("<function>") : nlohmann::json(v.num);
    case Kind::table:
      return nlohmann::json::object();
  }
  return {};
}

}  // namespace

struct ScriptHost::Impl {
  lua_State* L = nullptr;
  ScriptLimits limits;
  std::size_t used = 0;
  bool memory_exceeded = false;
  std::uint64_t executed = 0;
  std::uint64_t budget = 0;
  std::string script_name;
  std::filesystem::path script_dir;
  std::function<void(const std::string&)> print;

  // state while a script loads
  SceneConfig* cfg = nullptr;
  const Overrides* overrides = nullptr;
  std::set<std::string> used_overrides;
  std::map<std::string, std::string> sections_seen;  // section -> where
  std::vector<ShapeCall> shapes;
  std::set<std::string> param_names;
  std::string pending_error;

  // rule functions
  int divides_ref = LUA_NOREF;
  int direction_ref = LUA_NOREF;
  int source_ref = LUA_NOREF;
  int cell_table_ref = LUA_NOREF;

  static void* alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize) {
    auto* self = static_cast<Impl*>(ud);
    const std::size_t old = ptr ? osize : 0;
    if (nsize == 0) {
      self->used -= old;
      std::free(ptr);
      return nullptr;
    }
    if (nsize > old && self->used - old + nsize > self->limits.memory_bytes) {
      self->memory_exceeded = true;
      return nullptr;
    }
    void* p = std::realloc(ptr, nsize);
    if (p) self->used = self->used - old + nsize;
    return p;
  }

  static void hook(lua_State* L, lua_Debug*) {
    Impl* self = *static_cast<Impl**>(lua_getextraspace(L));
    self->executed += kHookEvery;
    if (self->executed > self->budget)
      luaL_error(L,
                 "instruction budget of %I instructions exceeded (an endless loop?); raise it with --lua-instructions",
                 static_cast<lua_Integer>(self->budget));
  }

  /// Turns a Lua error message into one line that names the script; adds the memory-limit hint.
  std::string describe(const std::string& lua_message) const {
    if (memory_exceeded || lua_message == "not enough memory")
      return script_name + ": the script exceeded its memory limit of " + std::to_string(limits.memory_bytes >> 20) +
             " MiB; raise it with --lua-memory";
    if (lua_message.find("attempt to load a binary chunk") != std::string::npos)
      return script_name + ": precompiled (binary) Lua chunks are not allowed; give the script as source text";
    return lua_message;
  }

  /// pcall with the instruction budget reset to `budget`; returns "" or the error message.
  std::string protected_call(int nargs, int nresults, std::uint64_t call_budget) {
    executed = 0;
    budget = call_budget;
    memory_exceeded = false;
    const int rc = lua_pcall(L, nargs, nresults, 0);
    if (rc == LUA_OK) return {};
    std::string msg = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "error object is not a string";
    lua_pop(L, 1);
    return describe(msg);
  }

  std::string where(int level = 1) {
    luaL_where(L, level);
    std::string w = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (w.empty()) w = script_name + ": ";
    return w;
  }

  /// Converts the Lua value at `idx` for field f; throws InvalidInput with `at` prefix.
  Value from_lua(const Field& f, int idx, const std::string& at) {
    Value v;
    v.present = true;
    const std::string name = f.section + "." + f.name;
    auto fail = [&](const std::string& got) -> InvalidInput {
      return InvalidInput(at + name + " must be " + allowed_text(f) + ", got " + got);
    };
    const int t = lua_type(L, idx);
    const std::string got = t == LUA_TSTRING ? std::string("\"") + lua_tostring(L, idx) + "\"" : luaL_typename(L, idx);
    switch (f.kind) {
      case Kind::number:
      case Kind::integer:
        if (t != LUA_TNUMBER) throw fail(got);
        v.num = lua_tonumber(L, idx);
        break;
      case Kind::boolean:
        if (t != LUA_TBOOLEAN) throw fail(got);
        v.flag = lua_toboolean(L, idx) != 0;
        break;
      case Kind::vec3: {
        if (t != LUA_TTABLE || lua_rawlen(L, idx) != 3) throw fail(t == LUA_TTABLE ? "a table without 3 numbers" : got);
        for (int i = 0; i < 3; ++i) {
          lua_rawgeti(L, idx, i + 1);
          if (lua_type(L, -1) != LUA_TNUMBER) {
            lua_pop(L, 1);
            throw fail("a non-number component");
          }
          v.vec[i] = lua_tonumber(L, -1);
          lua_pop(L, 1);
        }
        break;
      }
      case Kind::text:
        if (t != LUA_TSTRING) throw fail(got);
        v.str = lua_tostring(L, idx);
        break;
      case Kind::choice:
      case Kind::choice_or_function:
        if (f.kind == Kind::choice_or_function && t == LUA_TFUNCTION) {
          lua_pushvalue(L, idx);
          v.ref = luaL_ref(L, LUA_REGISTRYINDEX);
          break;
        }
        if (t != LUA_TSTRING) throw fail(got);
        v.str = lua_tostring(L, idx);
        break;
      case Kind::number_or_function:
        if (t == LUA_TFUNCTION) {
          lua_pushvalue(L, idx);
          v.ref = luaL_ref(L, LUA_REGISTRYINDEX);
        } else if (t == LUA_TNUMBER) {
          v.num = lua_tonumber(L, idx);
        } else {
          throw fail(got);
        }
        break;
      case Kind::function:
        if (t != LUA_TFUNCTION) throw fail(got);
        lua_pushvalue(L, idx);
        v.ref = luaL_ref(L, LUA_REGISTRYINDEX);
        break;
      case Kind::table:
        if (t != LUA_TTABLE) throw fail(got);
        break;
    }
    return v;
  }

  Value from_text(const Field& f, const std::string& text, const std::string& at) {
    Value v;
    v.present = true;
    const std::string name = f.section + "." + f.name;
    auto fail = [&]() { return InvalidInput(at + name + " must be " + allowed_text(f) + ", got \"" + text + "\""); };
    switch (f.kind) {
      case Kind::number:
      case Kind::integer:
      case Kind::number_or_function:
        if (!parse_double(text, v.num)) throw fail();
        break;
      case Kind::boolean:
        if (text == "true" || text == "1")
          v.flag = true;
        else if (text == "false" || text == "0")
          v.flag = false;
        else
          throw fail();
        break;
      case Kind::vec3:
        if (!parse_vec(text, v.vec)) throw fail();
        break;
      case Kind::text:
        v.str = text == "(none)" ? std::string() : text;
        break;  // an optional text
      case Kind::choice:
      case Kind::choice_or_function:
        v.str = text;
        break;
      case Kind::function:
      case Kind::table:
        throw InvalidInput(at + name + " cannot be set from the command line");
    }
    return v;
  }

  void check_range(const Field& f, Value& v, const std::string& at) {
    if (!v.present) return;
    const std::string name = f.section + "." + f.name;
    auto bad = [&](double x) { return !std::isfinite(x) || x < f.min || x > f.max || (f.min_exclusive && x <= f.min); };
    auto fail = [&](const std::string& got) {
      return InvalidInput(at + name + " must be " + allowed_text(f) + ", got " + got);
    };
    if (f.kind == Kind::number || f.kind == Kind::integer ||
        (f.kind == Kind::number_or_function && v.ref == LUA_NOREF)) {
      std::ostringstream g;
      g << v.num;
      if (bad(v.num)) throw fail(g.str());
      if (f.kind == Kind::integer && v.num != std::floor(v.num)) throw fail(g.str());
    } else if (f.kind == Kind::vec3) {
      for (int i = 0; i < 3; ++i) {
        std::ostringstream g;
        g << "{" << v.vec.x() << ", " << v.vec.y() << ", " << v.vec.z() << "}";
        if (bad(v.vec[i])) throw fail(g.str());
      }
    } else if ((f.kind == Kind::choice || f.kind == Kind::choice_or_function) && v.ref == LUA_NOREF) {
      if (!is_choice(f.choices, v.str)) {
        std::vector<std::string> options;
        std::stringstream ss(f.choices);
        std::string part;
        while (std::getline(ss, part, '|')) options.push_back(part);
        const std::string near = core::closest_name(v.str, options);
        throw InvalidInput(at + name + " must be one of " + choices_list(f.choices) + ", got \"" + v.str + "\"" +
                           (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
      }
    }
  }

  /// Reads the table argument of a section function at stack index `idx` against the schema.
  Values read_section(const std::string& section, int idx, const std::string& at, nlohmann::json* record) {
    const auto fields = section_fields(section);
    const int t = lua_type(L, idx);
    if (t != LUA_TTABLE && t != LUA_TNONE && t != LUA_TNIL)
      throw InvalidInput(at + section + "{...} takes a table of named parameters, got " + luaL_typename(L, idx));
    Values values;
    if (t == LUA_TTABLE) {
      lua_pushnil(L);
      while (lua_next(L, idx) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING) {
          lua_pop(L, 2);
          throw InvalidInput(at + section + "{...}: parameters are named (name = value); got a value without a name");
        }
        const std::string key = lua_tostring(L, -2);
        const Field* f = find_field(section, key);
        if (!f) {
          lua_pop(L, 2);
          std::vector<std::string> names;
          for (const Field* g : fields) names.push_back(g->name);
          const std::string near = core::closest_name(key, names);
          std::string all;
          for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
          throw InvalidInput(at + section + "{...} has no parameter '" + key + "'" +
                             (near.empty() ? "" : "; did you mean '" + near + "'?") + " (valid: " + all + ")");
        }
        try {
          values[key] = from_lua(*f, lua_gettop(L), at);
        } catch (...) {
          lua_pop(L, 2);
          throw;
        }
        lua_pop(L, 1);
      }
    }
    for (const Field* f : fields) {
      const std::string key = f->section + "." + f->name;
      std::string value_at = at;  // where a bad value is reported: the script line, or the --set option
      if (overrides) {
        auto it = overrides->find(key);
        if (it != overrides->end()) {
          value_at = "--set " + key + "=" + it->second + ": ";
          values[f->name] = from_text(*f, it->second, value_at);
          used_overrides.insert(key);
        }
      }
      Value& v = values[f->name];
      if (!v.present && f->kind != Kind::function && f->kind != Kind::table) {
        if (f->default_text.empty())
          throw InvalidInput(at + section + "{...} needs '" + f->name + "' (" + allowed_text(*f) + ")");
        if (f->default_text.find("cells.") == std::string::npos) {
          Value d = from_text(*f, f->default_text, "schema default: ");
          d.present = false;
          v.num = d.num, v.vec = d.vec, v.flag = d.flag, v.str = d.str;
        }
      }
      check_range(*f, v, value_at);
      if (record && f->kind != Kind::table && (v.present || f->default_text.find("cells.") == std::string::npos))
        (*record)[f->name] = to_json(*f, v);
    }
    return values;
  }

  void once(const std::string& section, const std::string& at) {
    auto [it, fresh] = sections_seen.emplace(section, at);
    if (!fresh) throw InvalidInput(at + section + "{...} is given twice (first at " + it->second + ")");
  }
};

namespace {

using Impl = ScriptHost::Impl;

Impl* self_of(lua_State* L) { return *static_cast<Impl**>(lua_getextraspace(L)); }

cells::ForceWeights weights_from(const Values& v) {
  cells::ForceWeights w;
  w.spring = v.at("spring").num;
  w.planar = v.at("planar").num;
  w.cohesion = v.at("cohesion").num;
  w.separation = v.at("separation").num;
  return w;
}

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

void section_leaf(Impl& I, const std::string& at) {
  I.once("leaf", at);
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

/// Runs `body` (which returns the number of Lua results) and turns a C++ exception into a Lua error.
/// lua_error longjmps, so it is raised only after every C++ object of the body is destroyed.
template <class Body>
int guarded(lua_State* L, Body&& body) {
  Impl& I = *self_of(L);
  int results = 0;
  bool failed = false;
  try {
    results = body(I);
  } catch (const std::exception& e) {
    I.pending_error = e.what();
    failed = true;
  }
  if (failed) {
    lua_pushstring(L, I.pending_error.c_str());
    return lua_error(L);
  }
  return results;
}

/// Every API function is this one C function with its section name as upvalue 1.
int api_section(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string section = lua_tostring(L, lua_upvalueindex(1));
    const std::string at = I.where(1);
    if (lua_gettop(L) > 1) throw InvalidInput(at + section + "{...} takes one table of named parameters");
    if (section == "cells")
      section_cells(I, at);
    else if (section == "division")
      section_division(I, at);
    else if (section == "run")
      section_run(I, at);
    else if (section == "output")
      section_output(I, at);
    else if (section == "venation")
      section_venation(I, at);
    else if (section == "print")
      section_print(I, at);
    else if (section == "leaf")
      section_leaf(I, at);
    else if (section == "colonisation")
      section_colonisation(I, at);
    else if (section == "disc" || section == "rectangle" || section == "sphere" || section == "line" ||
             section == "cell" || section == "petiole")
      section_shape(I, section, at);
    else
      section_constraint(I, section, at);
    return 0;
  });
}

/// params{name = default, ...}: script-level knobs; returns the table with --set overrides applied.
int api_params(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string at = I.where(1);
    I.once("params", at);
    if (lua_type(L, 1) != LUA_TTABLE || lua_gettop(L) != 1)
      throw InvalidInput(at + "params{...} takes one table of name = default");
    nlohmann::json& rec = I.cfg->resolved["params"];
    rec = nlohmann::json::object();
    lua_newtable(L);
    lua_pushnil(L);
    while (lua_next(L, 1) != 0) {
      if (lua_type(L, -2) != LUA_TSTRING) {
        lua_pop(L, 2);
        throw InvalidInput(at + "params{...}: every parameter needs a name (name = default)");
      }
      const std::string key = lua_tostring(L, -2);
      I.param_names.insert(key);
      auto it = I.overrides->find(key);
      const int t = lua_type(L, -1);
      if (it != I.overrides->end()) {
        I.used_overrides.insert(key);
        const std::string& text = it->second;
        double x;
        lua_pop(L, 1);
        if (t == LUA_TNUMBER) {
          if (!parse_double(text, x)) throw InvalidInput("--set " + key + ": expected a number, got \"" + text + "\"");
          lua_pushnumber(L, x);
          rec[key] = x;
        } else if (t == LUA_TBOOLEAN) {
          if (text != "true" && text != "false")
            throw InvalidInput("--set " + key + ": expected true or false, got \"" + text + "\"");
          lua_pushboolean(L, text == "true");
          rec[key] = text == "true";
        } else if (t == LUA_TSTRING) {
          lua_pushstring(L, text.c_str());
          rec[key] = text;
        } else {
          throw InvalidInput("--set " + key + ": only number, boolean and string params can be set");
        }
      } else {
        if (t == LUA_TNUMBER)
          rec[key] = lua_tonumber(L, -1);
        else if (t == LUA_TBOOLEAN)
          rec[key] = lua_toboolean(L, -1) != 0;
        else if (t == LUA_TSTRING)
          rec[key] = lua_tostring(L, -1);
        else
          rec[key] = luaL_typename(L, -1);
      }
      lua_pushvalue(L, -2);  // key
      lua_insert(L, -2);     // key value
      lua_rawset(L, 2);      // result table at index 2
    }
    return 1;
  });
}

int api_print(lua_State* L) {
  Impl& I = *self_of(L);
  const int n = lua_gettop(L);
  std::string line;
  for (int i = 1; i <= n; ++i) {
    if (i > 1) line += "\t";
    line += luaL_tolstring(L, i, nullptr);
    lua_pop(L, 1);
  }
  if (I.print) I.print(line);
  return 0;
}

}  // namespace

}  // namespace cellform::app

namespace cellform::app {

namespace {

const char* const kSections[] = {"run",          "cells",      "division",  "output", "venation", "print",    "leaf",
                                 "colonisation", "disc",       "rectangle", "sphere", "line",     "cell",     "petiole",
                                 "ground",       "half_space", "ball",      "box",    "mesh",     "attractor"};

Vec3 unit_or(const Vec3& n, const Vec3& fallback) { return n.norm() > 0 ? Vec3(n.normalized()) : fallback; }

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
        cfg.scene.petioles.push_back({v["at"].vec, v["fixed"].flag, static_cast<std::uint64_t>(v["step"].num)});
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

}  // namespace

ScriptHost::ScriptHost(ScriptLimits limits) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  I.limits = limits;
  I.L = lua_newstate(&Impl::alloc, &I);
  if (!I.L) throw std::runtime_error("cannot create the Lua interpreter");
  *static_cast<Impl**>(lua_getextraspace(I.L)) = &I;
  lua_State* L = I.L;
  const std::pair<const char*, lua_CFunction> libs[] = {
      {LUA_GNAME, luaopen_base},       {LUA_TABLIBNAME, luaopen_table}, {LUA_STRLIBNAME, luaopen_string},
      {LUA_MATHLIBNAME, luaopen_math}, {LUA_UTF8LIBNAME, luaopen_utf8}, {LUA_COLIBNAME, luaopen_coroutine}};
  for (const auto& [name, open] : libs) {
    luaL_requiref(L, name, open, 1);
    lua_pop(L, 1);
  }
  // the sandbox: nothing that reaches files, the OS, other code or the collector
  for (const char* name : {"dofile", "loadfile", "load", "require", "collectgarbage", "rawequal"}) {
    lua_pushnil(L);
    lua_setglobal(L, name);
  }
  lua_getglobal(L, LUA_STRLIBNAME);
  lua_pushnil(L);
  lua_setfield(L, -2, "dump");
  lua_pop(L, 1);
  lua_pushcfunction(L, api_print);
  lua_setglobal(L, "print");
  for (const char* section : kSections) {
    lua_pushstring(L, section);
    lua_pushcclosure(L, api_section, 1);
    lua_setglobal(L, section);
  }
  lua_pushcfunction(L, api_params);
  lua_setglobal(L, "params");
  lua_newtable(L);
  I.cell_table_ref = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_sethook(L, &Impl::hook, LUA_MASKCOUNT, kHookEvery);
}

ScriptHost::~ScriptHost() {
  if (impl_ && impl_->L) lua_close(impl_->L);
}

void ScriptHost::set_print(std::function<void(const std::string&)> print) { impl_->print = std::move(print); }

SceneConfig ScriptHost::load(const std::string& source, const std::filesystem::path& script_path,
                             const Overrides& overrides) {
  Impl& I = *impl_;
  lua_State* L = I.L;
  SceneConfig cfg;
  I.cfg = &cfg;
  I.overrides = &overrides;
  I.used_overrides.clear();
  I.sections_seen.clear();
  I.shapes.clear();
  I.param_names.clear();
  I.script_name = script_path.string();
  I.script_dir = script_path.has_parent_path() ? script_path.parent_path() : std::filesystem::path(".");
  struct Reset {
    Impl& I;
    ~Reset() {
      I.cfg = nullptr;
      I.overrides = nullptr;
    }
  } reset{I};

  const std::string chunk = "@" + script_path.string();
  I.memory_exceeded = false;
  if (luaL_loadbufferx(L, source.data(), source.size(), chunk.c_str(), "t") != LUA_OK) {
    std::string msg = lua_tostring(L, -1);
    lua_pop(L, 1);
    throw InvalidInput(I.describe(msg));
  }
  const std::string err = I.protected_call(0, 0, I.limits.instructions);
  if (!err.empty()) throw InvalidInput(err);

  // defaults for sections the script did not call
  for (const char* section : {"cells", "division", "run", "output"}) {
    if (I.sections_seen.count(section)) continue;
    lua_settop(L, 0);
    const std::string at = I.script_name + ": ";
    if (std::string(section) == "cells")
      section_cells(I, at);
    else if (std::string(section) == "division")
      section_division(I, at);
    else if (std::string(section) == "run")
      section_run(I, at);
    else
      section_output(I, at);
  }
  lua_settop(L, 0);

  for (const auto& [key, value] : overrides) {
    if (I.used_overrides.count(key)) continue;
    std::vector<std::string> names(I.param_names.begin(), I.param_names.end());
    for (const Field& f : schema())
      if (f.kind != Kind::function && f.kind != Kind::table) names.push_back(f.section + "." + f.name);
    const std::string near = core::closest_name(key, names);
    const bool is_shape =
        key.find('.') != std::string::npos && find_field(key.substr(0, key.find('.')), key.substr(key.find('.') + 1));
    throw InvalidInput("--set " + key + "=" + value + ": " +
                       (is_shape ? "shapes and constraints may be called several times, so they cannot be set by name; "
                                   "declare a knob with params{...} in the script and use it"
                                 : "the script has no parameter '" + key + "'" +
                                       (near.empty() ? "" : "; did you mean '" + near + "'?")));
  }
  build_shapes(I);
  if (cfg.colonisation && !I.sections_seen.count("colonisation"))
    throw InvalidInput(I.sections_seen["leaf"] + "leaf{...} needs colonisation{...} to grow veins in it");
  if (cfg.colonisation && !I.sections_seen.count("leaf")) {  // the default blade
    lua_settop(L, 0);
    section_leaf(I, I.script_name + ": ");
  }
  if (cfg.colonisation && (!cfg.initial_cells.empty() || I.sections_seen.count("venation")))
    throw InvalidInput(
        I.sections_seen["colonisation"] +
        "colonisation{...} grows veins in a leaf{...} outline; it cannot be combined with cells or venation{...}");
  if (cfg.print && cfg.print->veins && !cfg.print->shell && !cfg.scene.venation && !cfg.colonisation)
    throw InvalidInput(I.sections_seen["print"] +
                       "print{veins = true} needs veins: add venation{...}, or print the sheet with shell = true");
  return cfg;
}

namespace {

void fill_cell_table(Impl& I, const cells::Cells& c, core::Index i, std::uint64_t step) {
  lua_State* L = I.L;
  lua_rawgeti(L, LUA_REGISTRYINDEX, I.cell_table_ref);
  auto set_num = [&](const char* k, double v) {
    lua_pushnumber(L, v);
    lua_setfield(L, -2, k);
  };
  auto set_int = [&](const char* k, long long v) {
    lua_pushinteger(L, v);
    lua_setfield(L, -2, k);
  };
  set_int("id", static_cast<long long>(c.id[i]));
  set_int("index", static_cast<long long>(i) + 1);
  set_int("age", c.age[i]);
  set_int("generation", c.generation[i]);
  set_int("step", static_cast<long long>(step));
  static const char* const type_names[] = {"general", "petiole", "vein"};
  lua_pushstring(L, type_names[static_cast<int>(c.type[i])]);
  lua_setfield(L, -2, "type");
  lua_pushboolean(L, c.fixed[i]);
  lua_setfield(L, -2, "fixed");
  set_num("x", c.position[i].x());
  set_num("y", c.position[i].y());
  set_num("z", c.position[i].z());
  set_num("vx", c.velocity[i].x());
  set_num("vy", c.velocity[i].y());
  set_num("vz", c.velocity[i].z());
  int links = 0;
  for (int k = 0; k < c.link_stride; ++k)
    if (c.links[static_cast<std::size_t>(i) * c.link_stride + k] != core::kNoIndex) ++links;
  set_int("neighbours", links);
  for (const auto& [name, values] : c.attributes) set_num(name.c_str(), values[i]);
}

}  // namespace

cells::Rules ScriptHost::rules() {
  cells::Rules r;
  Impl* I = impl_.get();
  auto fail = [this, I](const char* rule, const std::string& msg, const cells::Cells& c, core::Index i) {
    return InvalidInput(msg + " (in " + rule + " at step " + std::to_string(step_) + " for cell " +
                        std::to_string(c.id[i]) + ")");
  };
  if (I->divides_ref != LUA_NOREF) {
    r.divides = [this, I, fail](const cells::Cells& c, core::Index i) {
      lua_State* L = I->L;
      lua_rawgeti(L, LUA_REGISTRYINDEX, I->divides_ref);
      fill_cell_table(*I, c, i, step_);
      const std::string err = I->protected_call(1, 1, I->limits.rule_instructions);
      if (!err.empty()) throw fail("division.rule", err, c, i);
      if (lua_type(L, -1) != LUA_TBOOLEAN) {
        const std::string got = luaL_typename(L, -1);
        lua_pop(L, 1);
        throw fail("division.rule", I->script_name + ": division.rule must return true or false, got " + got, c, i);
      }
      const bool yes = lua_toboolean(L, -1) != 0;
      lua_pop(L, 1);
      return yes;
    };
  }
  if (I->direction_ref != LUA_NOREF) {
    r.split_direction = [this, I, fail](const cells::Cells& c, core::Index i) {
      lua_State* L = I->L;
      lua_rawgeti(L, LUA_REGISTRYINDEX, I->direction_ref);
      fill_cell_table(*I, c, i, step_);
      const std::string err = I->protected_call(1, 3, I->limits.rule_instructions);
      if (!err.empty()) throw fail("division.direction", err, c, i);
      Vec3 d;
      bool ok = true;
      if (lua_type(L, -3) == LUA_TTABLE && lua_rawlen(L, -3) == 3) {
        for (int k = 0; k < 3; ++k) {
          lua_rawgeti(L, -3, k + 1);
          ok = ok && lua_type(L, -1) == LUA_TNUMBER;
          d[k] = lua_tonumber(L, -1);
          lua_pop(L, 1);
        }
      } else {
        for (int k = 0; k < 3; ++k) {
          ok = ok && lua_type(L, -3 + k) == LUA_TNUMBER;
          d[k] = lua_tonumber(L, -3 + k);
        }
      }
      lua_pop(L, 3);
      if (!ok || !d.allFinite())
        throw fail("division.direction",
                   I->script_name + ": division.direction must return {x, y, z} (or x, y, z) of finite numbers", c, i);
      return d;
    };
  }
  return r;
}

venation::SourceRule ScriptHost::source_rule() {
  Impl* I = impl_.get();
  if (I->source_ref == LUA_NOREF) return {};
  return [this, I](const cells::Cells& c, core::Index i) {
    lua_State* L = I->L;
    lua_rawgeti(L, LUA_REGISTRYINDEX, I->source_ref);
    fill_cell_table(*I, c, i, step_);
    const std::string err = I->protected_call(1, 1, I->limits.rule_instructions);
    auto where = [&] {
      return " (in venation.source at step " + std::to_string(step_) + " for cell " + std::to_string(c.id[i]) + ")";
    };
    if (!err.empty()) throw InvalidInput(err + where());
    if (lua_type(L, -1) != LUA_TNUMBER) {
      const std::string got = luaL_typename(L, -1);
      lua_pop(L, 1);
      throw InvalidInput(I->script_name + ": venation.source must return a number >= 0, got " + got + where());
    }
    const double v = lua_tonumber(L, -1);
    lua_pop(L, 1);
    if (!std::isfinite(v) || v < 0)
      throw InvalidInput(I->script_name + ": venation.source must return a finite number >= 0, got " +
                         std::to_string(v) + where());
    return v;
  };
}

}  // namespace cellform::app
