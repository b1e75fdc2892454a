// The Lua 5.4 sandbox: state, limits, the API functions and loading scripts (rule calls: script_rules.cpp).
#include "app/script_host.h"

#include "app/script_impl.h"
#include "app/script_watchdog.h"
#include "core/random.h"

namespace cellform::app {

namespace {

/// Calls the library function `name` kept as upvalue 1 with the arguments on the stack. Its argument
/// errors come back as "bad argument #1 to '?'" with no place (it was not called from the script):
/// they get the function's name and the script's file:line.
int call_library(lua_State* L, const char* name, int nresults) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  if (lua_pcall(L, lua_gettop(L) - 1, nresults, 0) == LUA_OK) return lua_gettop(L);
  if (lua_type(L, -1) != LUA_TSTRING) return lua_error(L);  // not a message (a stop, say): passed on as it is
  // built on the Lua stack: lua_error longjmps, so no C++ object may live in this frame
  lua_pushfstring(L, "to '%s'", name);
  luaL_gsub(L, lua_tostring(L, -2), "to '?'", lua_tostring(L, -1));
  luaL_where(L, 1);
  lua_insert(L, -2);
  lua_concat(L, 2);
  return lua_error(L);
}

/// math.randomseed with a seed only: without one, Lua 5.4 seeds from the clock and an address, and the
/// same script and seed would not give the same form. Upvalue 1 is the library's own function.
int api_randomseed(lua_State* L) {
  if (lua_gettop(L) == 0) {
    luaL_where(L, 1);
    lua_pushstring(L,
                   "math.randomseed() needs a seed (math.randomseed(n)): without one the run would not be "
                   "reproducible; math.random is already seeded from the run's seed and the step");
    lua_concat(L, 2);
    return lua_error(L);
  }
  return call_library(L, "math.randomseed", LUA_MULTRET);
}

/// Every API function is this one C function with its section name as upvalue 1.
int api_section(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string section = lua_tostring(L, lua_upvalueindex(1));
    const std::string at = I.where(1);
    I.require_loading(section, at);
    // a section refused (and caught by pcall) is not given: one given later is its first
    const bool seen = I.sections_seen.count(section) > 0;
    struct Forget {
      Impl& I;
      const std::string& section;
      bool keep = false;
      ~Forget() {
        if (!keep) I.sections_seen.erase(section);
      }
    } forget{I, section, seen};
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
    else if (section == "volume" || section == "surface")
      section_domain(I, section, at);
    else if (section == "disc" || section == "rectangle" || section == "sphere" || section == "line" ||
             section == "cell" || section == "petiole")
      section_shape(I, section, at);
    else
      section_constraint(I, section, at);
    forget.keep = true;
    return 0;
  });
}

/// print("text", ...) writes a line; print{...} (one table) is the print section, named in upvalue 1.
int api_print(lua_State* L) {
  if (lua_gettop(L) == 1 && lua_type(L, 1) == LUA_TTABLE) {
    // print(P), the knobs of params{}: their values, not a print section (P is known by its metatable,
    // which the script cannot reach)
    bool knobs = false;
    if (lua_getmetatable(L, 1)) {
      lua_rawgeti(L, LUA_REGISTRYINDEX, self_of(L)->params_meta_ref);
      knobs = lua_rawequal(L, -1, -2);
      lua_pop(L, 2);
    }
    if (!knobs) return api_section(L);
    return api_print_knobs(L);
  }
  Impl& I = *self_of(L);
  I.wait_if_dying();
  const int n = lua_gettop(L);
  // __tostring may raise: convert every argument (in place: the stack has room for a few more values
  // only) before any C++ object lives in this frame
  for (int i = 1; i <= n; ++i) {
    luaL_tolstring(L, i, nullptr);
    lua_replace(L, i);
  }
  // a stopped script goes no further here: an error raised in the count hook runs xpcall's handler with hooks
  // off, and a handler printing in a loop was stopped by nothing (its prints kept the watchdog waiting)
  if (I.stopping) {
    lua_pushstring(L, I.stop_message.c_str());
    return lua_error(L);
  }
  // the line lives in this block only, and an exception (out of memory) is caught in it: lua_error longjmps,
  // and a C++ exception must not unwind through Lua's C frames
  bool failed = false;
  const bool was_script = I.in_script.exchange(false, std::memory_order_acq_rel);
  try {  // a terminal or pipe that does not read on blocks in print: not the script's time
    std::string line;
    for (int i = 1; i <= n; ++i) {
      if (i > 1) line += "\t";
      line += lua_text(L, i);
    }
    if (I.print) I.print(line);
  } catch (const std::bad_alloc&) {
    I.pending_error = "print: out of memory for the line (print less at once)";
    failed = true;
  } catch (const std::exception& e) {
    I.pending_error = "print: " + core::error_text(e);
    failed = true;
  }
  I.in_script.store(was_script, std::memory_order_release);
  if (failed) {
    lua_pushstring(L, I.pending_error.c_str());
    return lua_error(L);
  }
  return 0;
}

/// The line of `text` that a message "NAME:LINE: ..." names, or "" if it names none.
std::string source_line(const std::string& text, const std::string& message, const std::string& name) {
  if (message.rfind(name + ":", 0) != 0) return {};
  const std::size_t at = name.size() + 1;
  std::size_t line = 0, i = at;
  for (; i < message.size() && i < at + 9 && message[i] >= '0' && message[i] <= '9'; ++i)
    line = line * 10 + static_cast<std::size_t>(message[i] - '0');
  if (i == at || line == 0) return {};
  std::size_t from = 0;
  for (std::size_t k = 1; k < line && from != std::string::npos; ++k) {
    from = text.find('\n', from);
    if (from != std::string::npos) ++from;
  }
  return from == std::string::npos ? std::string() : text.substr(from, text.find('\n', from) - from);
}

const char* const kSections[] = {"run",    "cells",        "division", "output",   "venation", "print",
                                 "leaf",   "colonisation", "volume",   "surface",  "disc",     "rectangle",
                                 "sphere", "line",         "cell",     "petiole",  "ground",   "half_space",
                                 "ball",   "box",          "mesh",     "attractor"};

/// setmetatable without __gc (upvalue 1: the library's setmetatable).
int api_setmetatable(lua_State* L) {
  if (lua_type(L, 2) == LUA_TTABLE && raw_field(L, 2, "__gc") != LUA_TNIL)
    return luaL_error(L,
                      "setmetatable: a metatable with __gc (a finalizer) is not allowed in a script: Lua runs "
                      "finalizers beyond the instruction budget and Ctrl-C");
  lua_settop(L, 2);
  return call_library(L, "setmetatable", 1);
}

/// rawset(t, k, v), except a new field of the cell table (an existing one is overwritten for each cell) or of
/// the knobs (params{}: read-only; a change to one is found after the step).
int api_rawset(lua_State* L) {
  lua_settop(L, 3);
  lua_rawgeti(L, LUA_REGISTRYINDEX, self_of(L)->cell_table_ref);
  const bool cell = lua_rawequal(L, 1, -1);
  lua_pop(L, 1);
  bool knobs = false;
  if (self_of(L)->params_ref != LUA_NOREF) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, self_of(L)->params_ref);
    knobs = lua_rawequal(L, 1, -1);
    lua_pop(L, 1);
  }
  if (knobs && !lua_isnil(L, 2)) {
    lua_pushvalue(L, 2);
    const bool absent = lua_rawget(L, 1) == LUA_TNIL;
    lua_pop(L, 1);
    if (absent)
      return luaL_error(L, "rawset(params, %s, ...): the knobs are read-only; declare it in params{...}",
                        lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_typename(L, 2));
  }
  if (cell && !lua_isnil(L, 2)) {
    lua_pushvalue(L, 2);
    const bool absent = lua_rawget(L, 1) == LUA_TNIL;
    lua_pop(L, 1);
    if (absent) {
      const char* key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : luaL_typename(L, 2);
      return luaL_error(L,
                        "rawset(cell, %s, ...): a rule function cannot add fields to its cell table (one table "
                        "is filled anew for each cell, so a value kept there would reach the next cell)",
                        key);
    }
  }
  return call_library(L, "rawset", 1);
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
  install_fixed_orders(L);  // pairs and table.sort: the same order in every run
  // no finalizers: Lua runs __gc with the hook off, out of reach of the instruction budget and Ctrl-C
  lua_getglobal(L, "setmetatable");
  lua_pushcclosure(L, api_setmetatable, 1);
  lua_setglobal(L, "setmetatable");
  // rawset passes the cell table's __newindex: a field added so would reach the next cell's table
  lua_getglobal(L, "rawset");
  lua_pushcclosure(L, api_rawset, 1);
  lua_setglobal(L, "rawset");
  // math.random is reproducible: Lua 5.4 seeds it randomly; here 0 while a script is read, then the run's
  // seed and the step (set_step). The library's own randomseed is kept for that, whatever a script does.
  lua_getglobal(L, LUA_MATHLIBNAME);
  lua_getfield(L, -1, "randomseed");
  I.randomseed_ref = luaL_ref(L, LUA_REGISTRYINDEX);  // (load() seeds with it)
  lua_getfield(L, -1, "randomseed");
  lua_pushcclosure(L, api_randomseed, 1);
  lua_setfield(L, -2, "randomseed");
  lua_pop(L, 1);
  for (const char* section : kSections) {
    lua_pushstring(L, section);
    lua_pushcclosure(L, std::string_view(section) == "print" ? api_print : api_section, 1);
    lua_setglobal(L, section);
  }
  lua_pushcfunction(L, api_params);
  lua_setglobal(L, "params");
  // the cell table, one for every call: no field may be added (it would reach the next cell)
  lua_newtable(L);
  lua_newtable(L);
  lua_pushcfunction(L, [](lua_State* S) -> int {  // (no C++ object lives here: lua_error longjmps)
    const char* key = lua_type(S, 2) == LUA_TSTRING ? lua_tostring(S, 2) : luaL_typename(S, 2);
    return luaL_error(S,
                      "cell.%s = ...: a rule function cannot add fields to its cell table (one table is filled "
                      "anew for each cell, so a value kept there would reach the next cell; rule functions "
                      "should depend only on the cell)",
                      key);
  });
  lua_setfield(L, -2, "__newindex");
  lua_pushcfunction(L, api_cell_index);  // a misspelt field is an error, not a silent nil
  lua_setfield(L, -2, "__index");
  lua_pushliteral(L, "the cell table is read-only");
  lua_setfield(L, -2, "__metatable");  // setmetatable on it is refused
  lua_setmetatable(L, -2);
  I.cell_table_ref = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_sethook(L, &Impl::hook, kHookMask, kHookEvery);
  watchdog_ = std::make_unique<Watchdog>(I);
}

ScriptHost::~ScriptHost() {
  watchdog_.reset();
  if (impl_ && impl_->L) lua_close(impl_->L);
}

void ScriptHost::set_step(std::uint64_t step) {
  step_ = step;
  lua_State* L = impl_->L;
  lua_rawgeti(L, LUA_REGISTRYINDEX, impl_->randomseed_ref);
  lua_pushinteger(L, static_cast<lua_Integer>(core::mix64(seed_) & 0x7fffffffffffffffull));
  lua_pushinteger(L, static_cast<lua_Integer>(step));
  lua_call(L, 2, 0);
}

void ScriptHost::check_knobs(std::uint64_t step) { check_knobs_unchanged(*impl_, step); }

void ScriptHost::set_print(std::function<void(const std::string&)> print) { impl_->print = std::move(print); }
const std::function<void(const std::string&)>& ScriptHost::print_function() const { return impl_->print; }

void ScriptHost::set_on_stuck(std::function<void(const std::string&)> handler) {
  watchdog_->set_on_stuck(std::move(handler));
}

void ScriptHost::accept_digit_booleans(const std::set<std::string>& keys) { impl_->digit_booleans = keys; }

SceneConfig ScriptHost::load(const std::string& source, const std::filesystem::path& script_path,
                             const Overrides& overrides, const std::set<std::string>& may_go_unused) {
  Impl& I = *impl_;
  unused_.clear();
  lua_State* L = I.L;
  SceneConfig cfg;
  I.cfg = &cfg;
  I.overrides = &overrides;
  I.used_overrides.clear();
  I.sections_seen.clear();
  I.shapes.clear();
  I.placements = 0;
  I.first_constraint.clear();
  I.param_names.clear();
  // the rules of an earlier reading go (a second reading, with a checkpoint's values, sets its own)
  for (int* ref : {&I.divides_ref, &I.direction_ref, &I.source_ref}) {
    luaL_unref(L, LUA_REGISTRYINDEX, *ref);
    *ref = LUA_NOREF;
  }
  I.divides_at.clear();
  I.direction_at.clear();
  I.source_at.clear();
  luaL_unref(L, LUA_REGISTRYINDEX, I.params_ref);
  luaL_unref(L, LUA_REGISTRYINDEX, I.params_meta_ref);
  I.params_ref = I.params_meta_ref = LUA_NOREF;
  I.script_name = script_path.string();
  watchdog_->script_ = I.script_name;  // no script runs now: the watchdog reads it only while one does
  I.script_dir = script_path.has_parent_path() ? script_path.parent_path() : std::filesystem::path(".");
  g_reading_script = true;
  struct Reset {
    Impl& I;
    ~Reset() {
      I.venation_runs = I.cfg && I.cfg->scene.venation.has_value();
      I.cfg = nullptr;
      I.overrides = nullptr;
      g_reading_script = false;
    }
  } reset{I};

  std::string chunk = "@";  // (not "@" + path: GCC 12 warns falsely of overlapping copies there, -Wrestrict)
  chunk += script_path.string();
  I.memory_exceeded = false;
  I.refused = false;
  // as the lua command accepts them: a UTF-8 byte-order mark, and a first line "#!..." (made a comment)
  std::string text = source.rfind("\xEF\xBB\xBF", 0) == 0 ? source.substr(3) : source;
  if (!text.empty() && text[0] == '#') text.insert(0, "--");
  if (luaL_loadbufferx(L, text.data(), text.size(), chunk.c_str(), "t") != LUA_OK) {
    std::string msg = lua_text(L, -1);
    lua_pop(L, 1);
    throw InvalidInput(I.describe(msg));
  }
  // math.random from seed 0 at every reading: a second one (with a checkpoint's values) draws what the first did
  // (protected: the hook of a script stopped before raises at the call until protected_call resets it)
  const int chunk_at = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, I.randomseed_ref);
  lua_pushinteger(L, 0);
  std::string err = I.protected_call(1, 0, I.limits.instructions);
  lua_settop(L, err.empty() ? chunk_at : chunk_at - 1);  // (stopped: the chunk goes too)
  if (err.empty()) err = I.protected_call(0, 0, I.limits.instructions);
  if (err.empty()) check_knobs_unchanged(I);
  if (!err.empty()) {
    // a misspelt function ("dsic{...}") is a call of nil: name the function meant; one the sandbox leaves
    // out (dofile, io.open) is said to be left out
    const std::string nil_call = "attempt to call a nil value (global '",
                      nil_index = "attempt to index a nil value (global '";
    const std::size_t at = err.find(nil_call), at_index = err.find(nil_index);
    const std::size_t from = at != std::string::npos         ? at + nil_call.size()
                             : at_index != std::string::npos ? at_index + nil_index.size()
                                                             : std::string::npos;
    const std::size_t to = from == std::string::npos ? std::string::npos : err.find('\'', from);
    const std::string global = to == std::string::npos ? std::string() : err.substr(from, to - from);
    constexpr const char* kLeftOut[] = {"dofile",   "loadfile", "load", "require", "collectgarbage",
                                        "rawequal", "io",       "os",   "package", "debug"};
    if (!global.empty() && std::find(std::begin(kLeftOut), std::end(kLeftOut), global) != std::end(kLeftOut)) {
      err += "; '" + global +
             "' is left out of cellform scripts, which reach no files, programs or other scripts (the sandbox "
             "keeps Lua's base functions, string, table, math, utf8 and coroutine)";
    } else if (at != std::string::npos) {
      std::vector<std::string> names(std::begin(kSections), std::end(kSections));
      names.push_back("params");
      const std::string near = global.empty() ? std::string() : core::closest_name(global, names);
      // none close in spelling: the functions by what they make (obstacle{} and plane{} were met with no more)
      err += near == global ? "; the script set it to nil before this call"
             : near.empty()
                 ? "; no such function (shapes: disc, rectangle, sphere, line, cell, petiole; obstacles: ground, "
                   "half_space, ball, box, mesh; attractor; settings: run, cells, division, venation, print, output; "
                   "veins by space colonisation: leaf, volume, surface, colonisation; params)"
                 : "; did you mean '" + near + "'?";
    } else if (err.find("attempt to call a nil value (field 'dump')") != std::string::npos &&
               source_line(text, err, I.script_name).find("string.dump") != std::string::npos) {
      err += "; 'string.dump' is left out of cellform scripts, which refuse precompiled chunks";
    }
    throw InvalidInput(err);
  }

  const std::map<std::string, std::string> called = I.sections_seen;  // by the script, before the defaults
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
    if (may_go_unused.count(key)) {
      unused_.push_back(key);
      continue;
    }
    std::vector<std::string> names(I.param_names.begin(), I.param_names.end());
    for (const Field& f : schema())
      if (f.kind != Kind::function && f.kind != Kind::table && f.kind != Kind::table_or_function)
        names.push_back(f.section + "." + f.name);
    const std::string near = core::closest_name(key, names);
    // a real parameter of a section the script does not call (run, cells, division and output are read
    // whether called or not, so theirs are always used)
    const std::string section = key.substr(0, key.find('.'));
    const bool uncalled = key.find('.') != std::string::npos && find_field(section, key.substr(key.find('.') + 1));
    if (near == key && !uncalled) {  // a part of a section the script leaves out (volume.ball of a box volume)
      const std::size_t last = key.rfind('.');
      const std::string part = key.substr(0, last);
      throw InvalidInput("--set " + key + "=" + value + ": the script's " + section + "{...} has no " +
                         part.substr(section.size() + 1) + " = {...}, so there is nothing for " + key + " to change");
    }
    throw InvalidInput("--set " + key + "=" + value + ": " +
                       (uncalled ? "the script does not call " + section + "{...}, so there is nothing for " + key +
                                       " to change; add " + section + "{...} to the script"
                                 : "the script has no parameter '" + key + "'" +
                                       (near.empty() ? "" : "; did you mean '" + near + "'?")));
  }
  build_shapes(I);
  for (const char* domain : {"leaf", "volume", "surface"})
    if (cfg.colonisation && I.sections_seen.count(domain) && !I.sections_seen.count("colonisation"))
      throw InvalidInput(I.sections_seen[domain] + domain + "{...} needs colonisation{...} to grow veins in it");
  const bool in_3d = I.sections_seen.count("volume") || I.sections_seen.count("surface");
  if (cfg.colonisation && !I.sections_seen.count("leaf") && !in_3d) {  // the default blade
    cfg.notes.push_back(I.sections_seen["colonisation"] +
                        "no leaf{...}, volume{...} or surface{...}: the veins grow in leaf{}'s default blade (an "
                        "ovate outline)");
    lua_settop(L, 0);
    section_leaf(I, I.script_name + ": ");
  }
  if (cfg.colonisation) finish_colonisation(I);
  if (!cfg.colonisation || cfg.colonisation->domain.kind != venation::DomainKind::leaf)
    for (const auto& [at, name] :
         {std::pair{cfg.output.svg_size_at, "svg_size"}, {cfg.output.svg_paths_at, "svg_paths"}})
      if (!at.empty())
        cfg.notes.push_back(at + "output." + name + " has no effect: only a space-colonisation run in a " +
                            "leaf{...} writes veins.svg");
  const bool on_cells = cfg.colonisation && cfg.colonisation->on_cells;
  if (cfg.colonisation && ((!cfg.initial_cells.empty() && !on_cells) || I.sections_seen.count("venation")))
    throw InvalidInput(I.sections_seen["colonisation"] +
                       "colonisation{...} grows veins in a leaf{...}, volume{...} or surface{...}; it cannot be "
                       "combined with venation{...}, nor with cells unless surface{cells = true} grows on them");
  if (cfg.colonisation && !on_cells) {  // statements about cells would be silently ignored: say so instead
    if (!cfg.steps_given_at.empty())
      throw InvalidInput(cfg.steps_given_at +
                         "run.steps counts the steps of cells (a cell run, or the sheet surface{cells = true} grows); "
                         "this space-colonisation run stops at colonisation.max_steps, or at --steps N");
    if (cfg.resolved.contains("run")) cfg.resolved["run"].erase("steps");  // not a parameter of this run
    for (const char* section : {"cells", "division"})
      if (called.count(section))
        throw InvalidInput(called.at(section) + section +
                           "{...} sets up the cell system; this space-colonisation run grows no cells (only "
                           "surface{cells = true} does)");
    if (I.overrides)  // a --set of theirs too, which needs no call (but one a checkpoint kept goes unused)
      for (const auto& [key, value] : *I.overrides)
        for (const std::string section : {"cells", "division"})
          if (key.rfind(section + ".", 0) == 0 && !may_go_unused.count(key))
            throw InvalidInput("--set " + key + "=" + value + ": " + section +
                               "{...} sets up the cell system; this space-colonisation run grows no cells (only "
                               "surface{cells = true} does)");
    for (const ShapeCall& s : I.shapes) {
      if (s.kind == "petiole")
        throw InvalidInput(s.where +
                           "petiole{...} places a petiole cell (the sink of venation{...}, or a seed of surface{cells "
                           "= true}); this space-colonisation run grows no cells. A leaf{...} grows its veins from "
                           "the petiole at the outline's start (0, 0), or from leaf{seeds = N}; volume{...} and "
                           "surface{...} take seeds = {{x, y, z}, ...}");
    }
    if (!I.first_constraint.empty())
      throw InvalidInput(I.first_constraint +
                         "{...} acts on cells; this space-colonisation run grows no cells (only surface{cells = "
                         "true} does). The veins stay inside the leaf{...}, volume{...} or surface{...}" +
                         (cfg.colonisation->domain.kind != venation::DomainKind::leaf &&
                                  (I.first_constraint.ends_with(": mesh") || I.first_constraint.ends_with(": ball") ||
                                   I.first_constraint.ends_with(": box"))
                              ? ": for veins round an obstacle, give volume{file = ...} a mesh with the obstacle's "
                                "surface nested inside its own (inside is an odd number of crossings, so nested "
                                "shells make a hollow)"
                              : ""));
  }
  if (on_cells && cfg.initial_cells.empty() && cfg.scene.petioles.empty())
    throw InvalidInput(I.sections_seen["surface"] +
                       "surface{cells = true} grows the cells first: place them with a shape such as disc{radius = 3}");
  if (cfg.print && cfg.print->shell && cfg.colonisation && !on_cells)
    throw InvalidInput(I.sections_seen["print"] +
                       "print{shell = true} thickens a cell sheet; this space-colonisation run grows none (use "
                       "surface{cells = true}, or shell = false)");
  if (cfg.colonisation && cfg.output.every > 0)  // frames are snapshots of a cell run
    throw InvalidInput(I.value_at("output.every", I.sections_seen["output"]) +
                       "output.every writes frames of a cell run; a space-colonisation run (even one whose "
                       "surface{cells = true} grows a sheet first) writes its outputs at the end (and "
                       "output.checkpoint_every sets how often it saves a checkpoint)");
  if (cfg.scene.split_along_auxin && !cfg.scene.venation)  // there would be no flow to split along
    throw InvalidInput(I.value_at("division.direction", I.sections_seen["division"]) +
                       "division.direction = \"auxin\" splits cells along the auxin flow, which needs venation{...}");
  if (cfg.output.png && !cfg.colonisation)
    throw InvalidInput(I.value_at("output.png", I.sections_seen["output"]) +
                       "output{png = true} draws space-colonisation veins; it needs colonisation{...}");
  if (cfg.print && cfg.print->veins && !cfg.print->shell && !cfg.scene.venation && !cfg.colonisation)
    throw InvalidInput(I.sections_seen["print"] +
                       "print{veins = true} needs veins: add venation{...}, or print the sheet with shell = true");
  if (cfg.print) {  // known now: said before the run, not after it
    const PrintSpec& p = *cfg.print;
    const std::string at = I.sections_seen["print"];
    auto named = [&](const char* other) {
      return I.value_at(I.overrides && I.overrides->count("print.voxel_size") ? "print.voxel_size" : other, at);
    };
    if (p.veins && (cfg.scene.venation || cfg.colonisation) && p.voxel_size > p.min_radius)
      throw InvalidInput(named("print.min_radius") + "print.voxel_size (" + core::number_text(p.voxel_size) +
                         " mm) exceeds print.min_radius (" + core::number_text(p.min_radius) +
                         " mm): the thinnest veins would vanish; use a voxel size of at most min_radius");
    if (p.shell && p.voxel_size > p.shell_thickness / 2)
      throw InvalidInput(named("print.shell_thickness") + "print.voxel_size (" + core::number_text(p.voxel_size) +
                         " mm) exceeds half of print.shell_thickness (" + core::number_text(p.shell_thickness) +
                         " mm): with fewer than two voxels across, the wall would break into pieces; use a voxel "
                         "size of at most shell_thickness / 2");
  }
  if (on_cells && cfg.colonisation->domain.initial_nodes.empty() && cfg.scene.petioles.empty())
    throw InvalidInput(I.sections_seen["surface"] +
                       "surface{cells = true} needs seeds = {{x, y, z}, ...} or a petiole{...} cell where the veins "
                       "start");
  if (I.division_radius_derived) {  // as the shapes' spacings, the default follows the cells' size
    cells::DivisionParams& d = cfg.scene.cells.division;
    d.radius = cells::kDivisionRadius * cfg.scene.cells.rest_length;
    nlohmann::json& rec = cfg.resolved["division"];  // run.json: the value used, where it applies
    if (d.trigger == cells::DivisionTrigger::neighbours && I.divides_ref == LUA_NOREF)
      rec["radius"] = d.radius;
    else
      rec.erase("radius");
  }
  cfg.scene.cells.vein_trees = cfg.scene.venation.has_value();  // no canalisation, no straightening to bound
  if (!cfg.colonisation || on_cells) {
    // the checks that need several parameters at once (the stable time step) name the section, or the --set
    try {
      cells::validate(cfg.scene.cells);
    } catch (const InvalidInput& e) {
      std::string m = e.what();
      if (m.rfind("cells.division.", 0) == 0) m.erase(0, 6);  // the script's name: division.radius
      const std::string key = m.substr(0, m.find(' '));
      const std::string section = key.substr(0, key.find('.'));
      const std::string at = I.sections_seen.count(section) ? I.sections_seen[section] : I.script_name + ": ";
      const std::string where = I.value_at(key, at);
      std::string sets;  // the stable time step's other inputs set on the command line
      if (key == "cells.time_step" && I.overrides)
        for (const auto& [k, v] : *I.overrides) {
          const bool weight = k.rfind("cells.vein.", 0) == 0 || k.rfind("cells.petiole.", 0) == 0 ||
                              k == "cells.spring" || k == "cells.planar" || k == "cells.cohesion" ||
                              k == "cells.separation" || k == "cells.rest_length" || k == "cells.integrator" ||
                              k == "cells.vein_cohesion" || k == "cells.vein_separation";
          if (weight) sets += (sets.empty() ? "" : ", ") + ("--set " + k + "=" + v);
        }
      throw InvalidInput(where + m + (sets.empty() ? "" : " (with " + sets + ")"));
    }
  }
  // a Ctrl-C that took the reading (g_reading_script) during the host's own work at the end (a large mesh{}
  // read) stops here, as its message said; one from now on stops the steps instead
  if (!g_reading_script.exchange(false))
    throw InvalidInput(I.script_name + ": interrupted while the script was read; nothing was written");
  return cfg;
}

}  // namespace cellform::app
