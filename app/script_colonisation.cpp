// The sections of the growth-script API that set up space colonisation (leaf{}, volume{}, surface{},
// colonisation{}): each reads its table against the schema and fills the colonisation configuration.
#include <optional>

#include "app/memory.h"
#include "app/script_impl.h"
#include "app/script_placement.h"
#include "venation/domain.h"

namespace cellform::app {
namespace {

/// Refuses a second source domain: a script grows veins in one leaf{}, volume{} or surface{}.
void one_domain(Impl& I, const std::string& section, const std::string& at) {
  for (const std::string other : {"leaf", "volume", "surface"})
    if (other != section && I.sections_seen.count(other))
      throw InvalidInput(at + section + "{...}: the veins already grow in " + other + "{...} (at " + I.seen_at(other) +
                         "); a script has one of leaf{}, volume{} and surface{}");
}

/// The field `name` = {{x, y, z}, ...} of the section table at stack index 1 (also one point {x, y, z}); with
/// `dims` 2, points {x, y} (z = 0), in `unit`.
std::vector<Vec3> read_points(Impl& I, const std::string& section, const std::string& at,
                              const std::string& name = "seeds", int dims = 3,
                              const std::string& unit = "model units") {
  lua_State* L = I.L;
  std::vector<Vec3> out;
  if (lua_type(L, 1) != LUA_TTABLE) return out;  // the default blade: no table was given
  raw_field(L, 1, name.c_str());
  const int idx = lua_gettop(L);
  const std::string point = dims == 3 ? "{x, y, z}" : "{x, y}";
  auto fail = [&](const std::string& what) {
    lua_settop(L, idx - 1);
    return InvalidInput(at + section + "." + name + " must be a list of points {" + point + ", ...} in " + unit + "; " +
                        what);
  };
  if (lua_type(L, idx) == LUA_TNIL) {
    lua_pop(L, 1);
    return out;
  }
  auto read_point = [&](int t, const std::string& which) {
    if (lua_type(L, t) != LUA_TTABLE || lua_rawlen(L, t) != static_cast<lua_Unsigned>(dims))
      throw fail(which + " is not " + point);
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < dims; ++k) {
      lua_rawgeti(L, t, k + 1);
      if (lua_type(L, -1) != LUA_TNUMBER) throw fail(which + " has a component that is not a number");
      p[k] = lua_tonumber(L, -1);
      lua_pop(L, 1);
    }
    if (!p.allFinite()) throw fail(which + " is not finite");
    if (p.cwiseAbs().maxCoeff() > kFarthest)
      throw fail(which + " lies beyond " + core::number_text(kFarthest) + " " + unit);
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
  const std::filesystem::path file = script_file(I, v.at("file").str, section + ".file", at);
  venation::Mesh out;
  try {
    check_file_fits(file, kMeshBytesPerByte, "mesh '" + file.string() + "'");
    forms::TriangleMesh m = forms::load_mesh(file);
    out.vertices = std::move(m.vertices);
    out.triangles = std::move(m.triangles);
  } catch (const std::exception& e) {
    throw InvalidInput(at + section + ".file: " + file_message(e));
  }
  scale_mesh(out.vertices, v.at("scale").num, v.at("offset").vec, v.at("file").str, at + section + ".file: ");
  return out;
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

std::string script_colonisation_message(const std::string& message) {
  std::string m = message;
  const std::pair<std::string, std::string> names[] = {
      {"colonisation.scale_step", "colonisation.length_step"},
      {"colonisation.final_scale", "colonisation.final_length"},
      {"colonisation.initial_scale", "colonisation.initial_length"},
      {"colonisation.darts_per_area", "colonisation.darts"},
      {"colonisation.source_birth_distance", "colonisation.birth_distance"},
      {"colonisation.node_distance", "the vein segment"},
      {"colonisation.max_steps", "the step limit (--steps or colonisation.max_steps)"},
      {"leaf.initial_nodes", "leaf.seeds"},
      {"leaf.petiole at", "the petiole, the point (0, 0) of the outline, at"},
      {"shape.teeth: teeth", "leaf.teeth and leaf.tooth_depth (with any fine_teeth): teeth"},
      {"shape.lobe_depth", "leaf.lobe_depth"},
      {"shape.lobes", "leaf.lobes"},
      {"shape.width", "leaf.width"}};
  for (const auto& [from, to] : names)
    for (std::size_t at = m.find(from); at != std::string::npos; at = m.find(from, at + to.size()))
      m.replace(at, from.size(), to);
  return m;
}

/// Seeds within a vein segment (1 model unit) of a surface file's triangles, but off it by more than the
/// domain's tolerance (a point on a round shape typed where the mesh has facets), moved onto it, with a note.
void snap_seeds(Impl& I, const venation::Domain& d, std::vector<Vec3>& seeds, const std::string& at) {
  if (d.mesh.triangles.empty() || d.mesh.vertices.empty()) return;  // (the domain's check says what is wrong)
  venation::Domain probe = d;                                       // seeded on the mesh itself, to be measured against
  const auto first = static_cast<std::size_t>(d.mesh.triangles.front()[0]);
  if (first >= d.mesh.vertices.size() || !d.mesh.vertices[first].allFinite()) return;
  probe.initial_nodes = {d.mesh.vertices[first]};
  probe.initial_sources.clear();
  std::optional<venation::PreparedDomain> prepared;
  try {
    prepared.emplace(probe);
  } catch (const InvalidInput&) {
    return;  // the domain's own check says what is wrong with the mesh
  }
  const double tol = 1e-6 * (prepared->hi() - prepared->lo()).norm();  // the domain's own tolerance
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    if (!seeds[i].allFinite()) continue;
    const Vec3 on = prepared->project(seeds[i]);
    const double off = (on - seeds[i]).norm();
    if (!(off > tol && off <= 1)) continue;
    I.cfg->notes.push_back(at + "surface.seeds[" + std::to_string(i + 1) + "] " +
                           core::point_text(seeds[i].x(), seeds[i].y(), seeds[i].z()) + " is " +
                           core::number_text(off) + " model units off the surface: moved onto it, to " +
                           core::point_text(on.x(), on.y(), on.z()));
    seeds[i] = on;
  }
}

void section_domain(Impl& I, const std::string& section, const std::string& at) {
  I.once(section, at);
  one_domain(I, section, at);
  nlohmann::json& rec = I.cfg->resolved[section];
  Values v = I.read_section(section, 1, at, &rec);
  if (!I.cfg->colonisation) I.cfg->colonisation.emplace();
  ColonisationSpec& spec = *I.cfg->colonisation;
  spec.domain_where = at;
  venation::Domain& d = spec.domain;
  lua_State* L = I.L;
  // a nested table such as volume{box = {min = ..., max = ...}}, read against the schema's "volume.box"
  auto nested = [&](const char* name, Values& out) {
    if (lua_type(L, 1) != LUA_TTABLE) return false;
    raw_field(L, 1, name);
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
  // scale is for a mesh file's coordinates (a mesh drawn in mm, say): elsewhere it would do nothing unsaid
  auto no_scale = [&](const std::string& instead) {
    if (v["scale"].present && v["scale"].num != 1 && !file)  // (1 changes nothing: accepted)
      throw InvalidInput(I.value_at(section + ".scale", at) + section +
                         ".scale scales the coordinates of a mesh file (" + section + "{file = ...}); " + instead);
    if (v["offset"].present && !v["offset"].vec.isZero() && !file)
      throw InvalidInput(I.value_at(section + ".offset", at) + section +
                         ".offset moves the coordinates of a mesh file (" + section +
                         "{file = ...}), and there is "
                         "none here");
  };
  if (section == "volume") {
    Values box, ball;
    const bool is_box = nested("box", box), is_ball = nested("ball", ball);
    if (int(is_box) + int(is_ball) + int(file) != 1)
      throw InvalidInput(at +
                         "volume{...} needs exactly one of box = {min = {x, y, z}, max = {x, y, z}}, "
                         "ball = {centre = {x, y, z}, radius = r} or file = \"shape.stl\"");
    no_scale("a box or ball is given in model units (vein segments)");
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
      throw InvalidInput(at + "surface{...} needs either file = \"shape.obj\" or cells = true (the grown cell sheet)" +
                         (file ? ", not both" : ""));
    no_scale(
        "the grown cell sheet is in model units (vein segments): for veins finer against it, grow it larger "
        "(cells.rest_length)");
    if (file) {
      d.mesh = read_domain_mesh(I, section, v, at);
      if (seeds.empty())
        throw InvalidInput(at + "surface{file = ...} needs seeds = {{x, y, z}, ...}: the seed vein nodes on it");
      snap_seeds(I, d, seeds, at);
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
  const std::string at = I.sections_seen["colonisation"];
  if (spec.domain.kind == venation::DomainKind::leaf) {
    try {
      venation::validate(spec.leaf, spec.params);  // a closed pattern's seeds (only leaf.seed_points can repeat)
    } catch (const InvalidInput& e) {
      std::string m = core::error_text(e);
      for (std::size_t k = m.find("leaf.initial_nodes"); k != std::string::npos; k = m.find("leaf.initial_nodes", k))
        m.replace(k, 18, "leaf.seed_points");
      const auto leaf = I.sections_seen.find("leaf");
      throw InvalidInput((leaf != I.sections_seen.end() ? leaf->second : at) + m);
    }
    return;
  }
  nlohmann::json& rec = I.cfg->resolved["colonisation"];
  venation::ColonisationParams& p = spec.params;
  if (spec.growth_given && p.growth != venation::GrowthMode::none)
    throw InvalidInput(at + "colonisation.growth = \"" + rec.value("growth", std::string()) +
                       "\" grows a leaf blade; a volume{...} or surface{...} does not grow (leave growth out or "
                       "set it to \"none\")");
  if (!spec.length_given.empty())
    throw InvalidInput(I.value_at("colonisation." + spec.length_given, at) + "colonisation." + spec.length_given +
                       " sizes a growing leaf blade; a volume{...} or surface{...} keeps its own size (leave it out)");
  p.growth = venation::GrowthMode::none;
  p.initial_scale = p.final_scale = 1;
  p.scale_step = 0;
  rec["growth"] = "none";
  for (const char* unused : {"initial_length", "final_length", "length_step"}) rec.erase(unused);
  try {
    venation::validate(spec.domain, p);
  } catch (const std::exception& e) {
    const char* section = spec.domain.kind == venation::DomainKind::surface ? "surface" : "volume";
    throw InvalidInput(at + script_domain_message(script_colonisation_message(core::error_text(e)), section));
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
      // the built-in outlines' values do not shape a drawn one: said if given (a note: a run that gave them
      // once, when they went unsaid, still resumes), and not recorded as used
      for (const char* k :
           {"shape", "width", "lobes", "lobe_depth", "teeth", "tooth_depth", "fine_teeth", "fine_tooth_depth"}) {
        if (v[k].present)
          I.cfg->notes.push_back(I.value_at(std::string("leaf.") + k, at) + "leaf." + k +
                                 " has no effect beside leaf.file: it shapes the built-in outlines, and an outline "
                                 "file is used as drawn");
        I.cfg->resolved["leaf"].erase(k);
      }
      const std::filesystem::path file = script_file(I, v["file"].str, "leaf.file", at);
      check_file_fits(file, kOutlineBytesPerByte, "leaf.file '" + file.string() + "'");
      leaf.outline = venation::read_outline(file);
      // any drawing unit: the tip (the highest y; the petiole is (0, 0)) is one leaf length, as the built-in
      // shapes' is; an outline not drawn upwards from its petiole by at least half its farthest vertex's
      // distance is measured by that half (so the scale never jumps with a vertex nudged across y = 0)
      double reach = 0, far = 0;
      venation::Vec2 farthest = venation::Vec2::Zero();
      for (const venation::Vec2& q : leaf.outline.points) {
        reach = std::max(reach, q.y());
        if (q.norm() > far) farthest = q;
        far = std::max(far, q.norm());
      }
      if (reach < 0.5 * far && std::isfinite(far))  // drawn pointing down or sideways (a walkthrough's was)
        I.cfg->notes.push_back(
            I.value_at("leaf.file", at) + "leaf.file's outline does not point along +y from its petiole (0, 0): its " +
            "highest y is " + core::number_text(reach) + ", its farthest vertex " + "(" +
            core::number_text(farthest.x()) + ", " + core::number_text(farthest.y()) + ")" +
            ", so one leaf length is half that vertex's distance and " +
            "the blade reaches twice as far as colonisation.initial_length and final_length say; draw the tip as "
            "the highest point");
      reach = std::max(reach, 0.5 * far);
      if (!(reach > 0) || !std::isfinite(1 / reach))
        throw InvalidInput("leaf.file: every vertex of the outline is at the petiole (0, 0)");
      for (venation::Vec2& q : leaf.outline.points) q /= reach;
    } else {
      venation::ShapeParams sp;
      const std::string k = v["shape"].str;
      sp.kind = k == "ellipse"   ? venation::ShapeKind::ellipse
                : k == "cordate" ? venation::ShapeKind::cordate
                : k == "lobed"   ? venation::ShapeKind::lobed
                : k == "palmate" ? venation::ShapeKind::palmate
                                 : venation::ShapeKind::ovate;
      // values of the other outlines are said, as beside a file, and not recorded as used
      auto unused = [&](const char* name, const std::string& why) {
        if (!v[name].present) return;
        I.cfg->notes.push_back(I.value_at(std::string("leaf.") + name, at) + "leaf." + name + " has no effect " + why);
        I.cfg->resolved["leaf"].erase(name);
      };
      if (sp.kind != venation::ShapeKind::lobed && sp.kind != venation::ShapeKind::palmate)
        for (const char* name : {"lobes", "lobe_depth"})
          unused(name, "with shape = \"" + k + "\": it shapes the lobed and palmate outlines");
      if (v["teeth"].num == 0) unused("tooth_depth", "without teeth (leaf.teeth = 0: an entire margin)");
      if (v["fine_teeth"].num == 0) unused("fine_tooth_depth", "without fine teeth (leaf.fine_teeth = 0)");
      sp.length = 1;
      sp.width = v["width"].num;
      sp.lobes = static_cast<int>(v["lobes"].num);
      sp.lobe_depth = v["lobe_depth"].num;
      if (v["teeth"].num > 0) sp.teeth.push_back({v["tooth_depth"].num, static_cast<int>(v["teeth"].num)});
      if (v["fine_teeth"].num > 0)
        sp.teeth.push_back({v["fine_tooth_depth"].num, static_cast<int>(v["fine_teeth"].num)});
      leaf.outline = venation::make_outline(sp);
    }
    // seed nodes placed by hand (Runions 2005: "positions of the initial points are specified by the user")
    const std::vector<Vec3> placed = read_points(I, "leaf", "", "seed_points", 2, "leaf lengths");
    if (!placed.empty() && (v["seeds"].present || v["seed_spread"].present))
      throw InvalidInput(std::string("leaf.seed_points places the seed vein nodes by hand: leave out leaf.") +
                         (v["seeds"].present ? "seeds" : "seed_spread") + ", which spreads them along the base");
    const int seeds = placed.empty() ? static_cast<int>(v["seeds"].num) : static_cast<int>(placed.size());
    if (placed.empty() && seeds > 1 && v["seed_spread"].num == 0)
      throw InvalidInput("leaf.seed_spread = 0 puts the " + std::to_string(seeds) +
                         " seeds on one point, where they cannot grow apart; give a seed_spread > 0 (leaf lengths), "
                         "or seeds = 1");
    leaf.initial_nodes.clear();
    for (int i = 0; i < seeds && seeds > 1 && placed.empty(); ++i) {
      const double spread = v["seed_spread"].num;
      leaf.initial_nodes.push_back(venation::Vec2(-spread / 2 + spread * i / (seeds - 1), 0.001));
    }
    if (!placed.empty()) {
      auto& rec = I.cfg->resolved["leaf"];
      rec.erase("seeds");
      rec.erase("seed_spread");
      rec["seed_points"] = nlohmann::json::array();
      for (const Vec3& q : placed) {
        leaf.initial_nodes.push_back(venation::Vec2(q.x(), q.y()));
        rec["seed_points"].push_back({q.x(), q.y()});
      }
    }
    try {
      venation::validate(leaf);
    } catch (const InvalidInput& e) {
      const std::string m = e.what();
      if (!v["file"].str.empty() && m.rfind("leaf.petiole at", 0) == 0)
        throw InvalidInput("leaf.file: the point (0, 0) of " + v["file"].str +
                           ", where the blade attaches to its petiole, lies outside the outline; the outline must "
                           "have (0, 0) inside it or on it");
      if (!placed.empty() && m.rfind("leaf.initial_nodes[", 0) == 0)
        throw InvalidInput("leaf.seed_points[" + m.substr(19) + " (the petiole at (0, 0), the tip at (0, 1))");
      if (seeds <= 1 || m.rfind("leaf.initial_nodes[", 0) != 0 || m.find("outside") == std::string::npos) throw;
      const std::string nth = m.substr(19, m.find(']') - 19);
      throw InvalidInput(
          "leaf.seeds: seed " + nth + " of " + std::to_string(seeds) +
          " lies outside the blade: the seeds span leaf.seed_spread = " + core::number_text(v["seed_spread"].num) +
          " leaf lengths along the base, wider than the blade there; use a smaller seed_spread");
    }
  } catch (const std::exception& e) {
    throw InvalidInput(at + "leaf: " + script_colonisation_message(core::error_text(e)));
  }
}

namespace {

using core::number_text;

/// One growth function of colonisation{growth = "nonuniform"} (Appendix A): a table {{y0, rate}, ...} or
/// a function of y0, both in leaf lengths, into a GrowthFunction in model units of the initial leaf.
venation::GrowthFunction read_growth_function(Impl& I, const Value& given, const char* name, const std::string& at,
                                              double initial_length, nlohmann::json& record) {
  lua_State* L = I.L;
  const std::string field = std::string("colonisation.") + name;
  venation::GrowthFunction f;
  record = nlohmann::json::array();
  // a function's values are its own: named at its line, as its wrong return types are
  const std::string fn_at = given.ref != LUA_NOREF ? I.function_at(given.ref, at) : at;
  const bool along_x = std::string_view(name) == "growth_x";
  auto add = [&](double y0, double rate, const std::string& which) {
    if (!std::isfinite(y0) || !(std::isfinite(rate) && rate > 0))
      throw InvalidInput(fn_at + field + which +
                         ": the height y0 must be finite and the rate (REG per step) a finite number > 0 (Appendix A " +
                         (along_x ? "needs REG_x > 0 for x_t = x_0 REG_x^t to keep its side of the midrib"
                                  : "needs REG_y > 0 for y0 -> y_t to be increasing") +
                         "), got {" + number_text(y0) + ", " + number_text(rate) + "}");
    if (!f.y.empty() && !(y0 * initial_length > f.y.back()))
      throw InvalidInput(at + field + which + ": heights y0 must increase strictly from one entry to the next, got " +
                         number_text(y0) + " after " + number_text(f.y.back() / initial_length));
    f.y.push_back(y0 * initial_length);
    f.rate.push_back(rate);
    record.push_back({y0, rate});
  };
  if (given.ref != LUA_NOREF) {
    constexpr int kSamples = 257;  // y0 from -0.5 to 1.5 leaf lengths, every 1/128
    for (int k = 0; k < kSamples; ++k) {
      const double y0 = -0.5 + 2.0 * k / (kSamples - 1);
      // error(42), error({}), a yield: the message handler gives each its text and the script's line
      lua_pushcfunction(L, &Impl::error_object_text);
      const int handler = lua_gettop(L);
      lua_rawgeti(L, LUA_REGISTRYINDEX, given.ref);
      lua_pushnumber(L, y0);
      const LuaRunsHere lua_runs(I);               // the function's allocations count against the memory limit
      I.sampling = "the function " + field;        // it must not describe the scene
      const int rc = lua_pcall(L, 1, 1, handler);  // counts against the script's own instruction budget
      lua_remove(L, handler);
      I.sampling.clear();
      I.wait_if_dying();
      if (rc != LUA_OK) {
        const std::string msg = lua_type(L, -1) == LUA_TSTRING ? lua_text(L, -1) : "error object is not a string";
        lua_pop(L, 1);
        throw InvalidInput(at + field + " failed at y0 = " + number_text(y0) + ": " + I.describe(msg));
      }
      if (lua_type(L, -1) != LUA_TNUMBER) {
        const std::string got = luaL_typename(L, -1);
        lua_pop(L, 1);
        throw InvalidInput(I.function_at(given.ref, at) + field + " must return a number (REG per step), got " + got +
                           " at y0 = " + number_text(y0));
      }
      const double rate = lua_tonumber(L, -1);
      lua_pop(L, 1);
      std::string where = number_text(y0);  // built in place: GCC 12 warns falsely on "(" + string
      where.insert(0, 1, '(');
      where.push_back(')');
      add(y0, rate, where);
    }
    return f;
  }
  raw_field(L, 1, name);
  const int t = lua_gettop(L);
  const auto n = static_cast<int>(lua_rawlen(L, t));
  try {
    if (n == 0) throw InvalidInput(at + field + " must list at least one {y0, rate} pair");
    for (int i = 1; i <= n; ++i) {
      lua_rawgeti(L, t, i);
      const int e = lua_gettop(L);
      std::string which = "[";  // (not "[" + ...: GCC 12 warns falsely of overlapping copies there, -Wrestrict)
      which += std::to_string(i);
      which += "]";
      bool ok = lua_type(L, e) == LUA_TTABLE && lua_rawlen(L, e) == 2;
      double pair[2] = {0, 0};
      for (int k = 0; k < 2 && ok; ++k) {
        lua_rawgeti(L, e, k + 1);
        ok = lua_type(L, -1) == LUA_TNUMBER;
        pair[k] = lua_tonumber(L, -1);
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
      if (!ok)
        throw InvalidInput(at + field + which +
                           " must be a pair {y0, rate} of numbers (y0 in leaf lengths from the "
                           "petiole, rate = REG per step)");
      add(pair[0], pair[1], which);
    }
  } catch (...) {
    lua_settop(L, t - 1);
    throw;
  }
  lua_settop(L, t - 1);
  return f;
}

/// growth = "nonuniform": growth_x, growth_y, growth_steps; refuses them for the other growth types.
void read_nonuniform_growth(Impl& I, Values& v, const std::string& at, venation::ColonisationParams& p) {
  nlohmann::json& rec = I.cfg->resolved["colonisation"];
  if (p.growth != venation::GrowthMode::nonuniform) {
    const std::string now = v["growth"].present ? "growth is \"" + v["growth"].str + "\""
                                                : "growth is not given; a leaf{...} grows \"marginal\" by default, "
                                                  "and a volume{...} or surface{...} does not grow";
    for (const char* name : {"growth_x", "growth_y"})
      if (v[name].present)
        throw InvalidInput(at + "colonisation." + name + " applies only to growth = \"nonuniform\" (" + now + ")");
    if (v["growth_steps"].present && v["growth_steps"].num > 0)
      throw InvalidInput(at + "colonisation.growth_steps applies only to growth = \"nonuniform\" (" + now + ")");
    rec.erase("growth_x");
    rec.erase("growth_y");
    return;
  }
  for (const char* name : {"growth_x", "growth_y"})
    if (!v[name].present)
      throw InvalidInput(at + "colonisation{growth = \"nonuniform\"} needs " + name +
                         ": {{y0, rate}, ...} or function(y0) returning the growth rate per step (REG = 1 + g, "
                         "Fig. 5), y0 in leaf lengths from the petiole");
  if (v["growth_steps"].num < 1)
    throw InvalidInput(at + "colonisation{growth = \"nonuniform\"} needs growth_steps >= 1 (steps of growth)");
  p.growth_x = read_growth_function(I, v["growth_x"], "growth_x", at, p.initial_scale, rec["growth_x"]);
  p.growth_y = read_growth_function(I, v["growth_y"], "growth_y", at, p.initial_scale, rec["growth_y"]);
  p.growth_steps = static_cast<std::size_t>(v["growth_steps"].num);
}

}  // namespace

void section_colonisation(Impl& I, const std::string& at) {
  I.once("colonisation", at);
  Values v = I.read_section("colonisation", 1, at, &I.cfg->resolved["colonisation"]);
  if (!I.cfg->colonisation) I.cfg->colonisation.emplace();
  I.cfg->colonisation->where = at;
  venation::ColonisationParams& p = I.cfg->colonisation->params;
  p.type = v["type"].str == "closed" ? venation::VenationType::closed : venation::VenationType::open;
  p.neighbourhood =
      v["neighbourhood"].str == "urquhart" ? venation::Neighbourhood::urquhart : venation::Neighbourhood::exact;
  if (p.type == venation::VenationType::open && v["neighbourhood"].present)  // it would be ignored
    throw InvalidInput(at +
                       "colonisation.neighbourhood chooses the relative neighbourhood of closed patterns; an open "
                       "pattern pulls each source's nearest node (leave it out, or set type = \"closed\")");
  p.kill_distance = v["kill_distance"].num;
  p.source_birth_distance = v["birth_distance"].num;
  p.vein_birth_distance = v["vein_birth_distance"].num > 0 ? v["vein_birth_distance"].num : v["birth_distance"].num;
  I.cfg->resolved["colonisation"]["vein_birth_distance"] = p.vein_birth_distance;  // run.json: the value used
  p.node_distance = 1;
  p.darts_per_area = v["darts"].num * 1e-6;
  const std::string g = v["growth"].str;
  p.growth = g == "none"         ? venation::GrowthMode::none
             : g == "isogonic"   ? venation::GrowthMode::uniform
             : g == "nonuniform" ? venation::GrowthMode::nonuniform
                                 : venation::GrowthMode::marginal;
  p.initial_scale = v["initial_length"].num;
  const bool fixed_size = g == "none" || g == "nonuniform";
  p.final_scale = fixed_size ? p.initial_scale : v["final_length"].num;
  p.scale_step = fixed_size ? 0 : v["length_step"].num;
  if (fixed_size)  // noted, as other settings without effect: the blade keeps initial_length (nonuniform: scaled)
    for (const char* name : {"final_length", "length_step"})
      if (v[name].present) {
        I.cfg->notes.push_back(I.value_at(std::string("colonisation.") + name, at) + "colonisation." + name +
                               " has no effect with growth = \"" + g +
                               "\" (it belongs to \"marginal\" and \"isogonic\")");
      }
  if (fixed_size)  // run.json: they do not apply, given or not
    for (const char* name : {"final_length", "length_step"}) I.cfg->resolved["colonisation"].erase(name);
  read_nonuniform_growth(I, v, at, p);
  p.max_steps = static_cast<std::size_t>(v["max_steps"].num);
  p.max_nodes = static_cast<std::size_t>(v["max_nodes"].num);
  p.max_sources = static_cast<std::size_t>(v["max_sources"].num);
  I.cfg->colonisation->growth_given = v["growth"].present;
  for (const char* name : {"initial_length", "final_length", "length_step"})
    if (v[name].present && I.cfg->colonisation->length_given.empty()) I.cfg->colonisation->length_given = name;
  I.cfg->colonisation->widths.exponent = v["murray_exponent"].num;
  I.cfg->colonisation->widths.tip_radius = v["tip_radius"].num;
  I.cfg->colonisation->widths.per_node_flow = v["node_flow"].num;
  try {
    venation::validate(p);
  } catch (const std::exception& e) {
    throw InvalidInput(at + script_colonisation_message(core::error_text(e)));
  }
}

}  // namespace cellform::app
