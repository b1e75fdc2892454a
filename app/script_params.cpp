// params{}: the script's knobs, --set on them, their table's guards (a new or misspelt knob, a change by
// a rule), print(P); and the cell table's missing fields (ScriptHost::Impl, declared in app/script_impl.h).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <string_view>

#include "app/script_impl.h"
#include "venation/canalisation.h"

namespace cellform::app {

namespace {

/// __index of the table params{} returns: a knob it does not declare is a script error (a misspelled
/// P.vein_spacin would be nil, and the section given it would fall back to its default unannounced).
int params_missing(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string at = I.where(1);
    if (lua_type(L, 2) != LUA_TSTRING)
      throw InvalidInput(at + "params has no knob at a " + luaL_typename(L, 2) + " key (knobs are named: P.name)");
    const std::string key = lua_tostring(L, 2);
    bool unnamed = false;
    const std::vector<std::string> names = sorted_names(L, 1, unnamed);  // the same suggestion every run
    const std::string near = core::closest_name(key, names);
    throw InvalidInput(at + "params has no knob '" + core::printable(key) + "'" +
                       (near.empty() ? "" : "; did you mean '" + near + "'?") + " (params{...} declares the knobs)");
    return 0;
  });
}

/// run.json's record of the value on top of the stack (a knob's default, or its --set).
nlohmann::json knob_record(lua_State* L) {
  const int t = lua_type(L, -1);
  if (t == LUA_TNUMBER)
    return lua_isinteger(L, -1) ? nlohmann::json(lua_tointeger(L, -1)) : nlohmann::json(lua_tonumber(L, -1));
  if (t == LUA_TBOOLEAN) return lua_toboolean(L, -1) != 0;
  if (t == LUA_TSTRING) {
    std::size_t len = 0;
    const char* text = lua_tolstring(L, -1, &len);
    return std::string(text, len);  // whole, NULs included (JSON writes them \u0000)
  }
  return luaL_typename(L, -1);
}

/// Whether the value on top of the stack is, type and bits, the knob `was` records: without copying it (a knob of
/// a megabyte of text, copied and written as JSON twice after every step, made a run 90 times slower). False
/// where it cannot tell: the caller compares their records.
bool knob_same(lua_State* L, const nlohmann::json& was) {
  const int t = lua_type(L, -1);
  if (t == LUA_TSTRING && was.is_string()) {
    std::size_t len = 0;
    const char* text = lua_tolstring(L, -1, &len);
    const std::string& w = was.get_ref<const std::string&>();
    return w.size() == len && std::memcmp(w.data(), text, len) == 0;
  }
  if (t == LUA_TBOOLEAN && was.is_boolean()) return was.get<bool>() == (lua_toboolean(L, -1) != 0);
  if (t == LUA_TNUMBER && lua_isinteger(L, -1) && was.is_number_integer() && !was.is_number_unsigned())
    return was.get<std::int64_t>() == lua_tointeger(L, -1);
  if (t == LUA_TNUMBER && !lua_isinteger(L, -1) && was.is_number_float()) {
    const double now = lua_tonumber(L, -1), then = was.get<double>();
    return std::memcmp(&now, &then, sizeof now) == 0;  // (-0.0 is not 0.0 in run.json)
  }
  return false;
}

/// "params { name = value, ... }" of the knobs of the table at `index`.
std::string knob_line(lua_State* L, const Impl& I, int index) {
  index = lua_absindex(L, index);
  std::string line = "params {";
  std::size_t k = 0;
  for (const std::string& name : I.param_names) {  // sorted
    lua_pushlstring(L, name.data(), name.size());
    lua_rawget(L, index);  // raw: no metamethod may raise here, past this frame's strings
    const nlohmann::json value = knob_record(L);
    lua_pop(L, 1);
    line += (k++ ? ", " : " ") + name + " = " + value.dump();
  }
  return line + (k ? " }" : "}");
}

/// __tostring of the table params{} returns: tostring(P), print("knobs:", P).
/// P.name = value for a name params{...} did not declare (a declared one is checked after the step).
int params_assign_new(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    if (lua_type(L, 2) == LUA_TSTRING && I.knobs.contains(lua_tostring(L, 2))) {
      lua_settop(L, 3);  // a declared knob set to nil before: set again (a change is found after the step)
      lua_rawset(L, 1);
      return 0;
    }
    const std::string at = I.where(1);
    std::string key = lua_type(L, 2) == LUA_TSTRING ? "'" : "at a ";  // appended: GCC 12 warns falsely of
    key += lua_type(L, 2) == LUA_TSTRING ? core::printable(lua_tostring(L, 2)) + "'"  // "'" + string&&
                                         : std::string(luaL_typename(L, 2)) + " key";
    throw InvalidInput(at + "params: the knobs are read-only, and a new one " + key +
                       " cannot be added: declare it in params{...} (a value computed from the knobs goes in a local "
                       "variable; a rule function should keep nothing between calls, which a resume does not "
                       "restore)");
    return 0;
  });
}

int params_tostring(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string line = knob_line(L, I, 1);
    lua_pushlstring(L, line.data(), line.size());
    return 1;
  });
}

}  // namespace

/// params{name = default, ...}: script-level knobs; returns the table with --set overrides applied.
int api_params(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    const std::string at = I.where(1);
    I.require_loading("params", at);
    I.once("params", at);
    if (lua_type(L, 1) != LUA_TTABLE || lua_gettop(L) != 1)
      throw InvalidInput(at + "params{...} takes one table of name = default");
    nlohmann::json& rec = I.cfg->resolved["params"];
    rec = nlohmann::json::object();
    lua_newtable(L);
    // the knobs in byte order of their names: Lua's own order changes from run to run, and so would the
    // message of a script with two bad knobs
    bool unnamed = false;
    const std::vector<std::string> keys = sorted_names(L, 1, unnamed);
    if (unnamed) throw InvalidInput(at + "params{...}: every parameter needs a name (name = default)");
    for (const std::string& key : keys) {
      lua_pushlstring(L, key.data(), key.size());
      lua_pushvalue(L, -1);
      lua_rawget(L, 1);  // key value, as lua_next left them
      // a name --set can give, and only one thing: "cells.spring" would be set with the section's parameter,
      // and "" or "a b" never (a dotted name of no parameter stays: older scripts)
      bool a_parameter = false;  // at any dot: cells.vein.cohesion is section cells.vein's cohesion
      for (std::size_t dot = key.find('.'); dot != std::string::npos && !a_parameter; dot = key.find('.', dot + 1))
        a_parameter = find_field(key.substr(0, dot), key.substr(dot + 1)) != nullptr;
      const bool settable = !key.empty() && std::none_of(key.begin(), key.end(), [](char c) {
        return c == '=' || std::isspace(static_cast<unsigned char>(c)) || std::iscntrl(static_cast<unsigned char>(c));
      });
      if (!settable || a_parameter) {
        lua_pop(L, 2);
        throw InvalidInput(at + "params{...}: the knob name " + core::printable("'" + key + "'") +
                           (a_parameter
                                ? " is a section's parameter too: --set " + key + "=... would set both"
                                : std::string(" cannot be given to --set NAME=VALUE (empty, or with spaces or =)")) +
                           "; name it otherwise");
      }
      I.param_names.insert(key);
      auto it = I.overrides->find(key);
      const int t = lua_type(L, -1);
      if (t != LUA_TNUMBER && t != LUA_TBOOLEAN && t != LUA_TSTRING) {
        const std::string type = luaL_typename(L, -1);
        lua_pop(L, 2);
        throw InvalidInput(at + "params{...}: the knob " + core::printable(key) + " is a " + type +
                           "; a knob is a number, a boolean or a string (what --set can give and run.json "
                           "records); keep a " +
                           type + " in a local variable, or give its parts as knobs of their own");
      }
      std::size_t length = 0;
      const char* given = t == LUA_TSTRING ? lua_tolstring(L, -1, &length) : nullptr;  // whole, NULs included
      if (!core::is_utf8(key) || (given && !core::is_utf8(std::string_view(given, length)))) {
        lua_pop(L, 2);
        throw InvalidInput(at + "params{...}: the knob " + core::printable(key) +
                           (core::is_utf8(key) ? "'s default" : "") +
                           " is not UTF-8 text, which run.json and the checkpoint record; write it in UTF-8");
      }
      const bool integer = t == LUA_TNUMBER && lua_isinteger(L, -1);
      if (t == LUA_TNUMBER && !integer && !std::isfinite(lua_tonumber(L, -1))) {
        const double x = lua_tonumber(L, -1);
        lua_pop(L, 2);
        throw InvalidInput(at + "params{...}: the knob " + core::printable(key) + " is " + core::number_text(x) +
                           "; a knob is a finite number (run.json records it, and --set gives only those)");
      }
      if (it != I.overrides->end()) {
        I.used_overrides.insert(key);
        const std::string& text = it->second;
        double x;
        lua_pop(L, 1);
        long long whole = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), whole);
        if (integer && ec == std::errc() && end == text.data() + text.size()) {  // exactly, beyond 2^53 too
          lua_pushinteger(L, static_cast<lua_Integer>(whole));
          rec[key] = static_cast<std::int64_t>(whole);
        } else if (t == LUA_TNUMBER) {
          if (!parse_double(text, x) || !std::isfinite(x))
            throw InvalidInput("--set " + key + ": expected a finite number, got \"" + text + "\"");
          // a whole default stays whole (a count such as 3 given as --set n=5 is 5, not 5.0)
          if (integer && x == std::floor(x) && std::abs(x) < 0x1p63) {
            lua_pushinteger(L, static_cast<lua_Integer>(x));
            rec[key] = static_cast<std::int64_t>(x);
          } else {
            lua_pushnumber(L, x);
            rec[key] = x;
          }
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
        rec[key] = knob_record(L);
      }
      lua_pushvalue(L, -2);  // key
      lua_insert(L, -2);     // key value
      lua_rawset(L, 2);      // result table at index 2
      lua_pop(L, 1);         // the key
    }
    lua_newtable(L);  // its metatable
    lua_pushcfunction(L, params_missing);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, params_tostring);
    lua_setfield(L, -2, "__tostring");
    lua_pushcfunction(L, params_assign_new);
    lua_setfield(L, -2, "__newindex");
    lua_pushliteral(L, "params are read-only");
    lua_setfield(L, -2, "__metatable");  // setmetatable(P, ...) is refused
    lua_pushvalue(L, -1);
    I.params_meta_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    lua_setmetatable(L, 2);
    lua_pushvalue(L, 2);
    I.params_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    I.params_at = at;
    I.knobs = rec;
    lua_settop(L, 2);
    return 1;
  });
}

/// The fields of the cell table (fill_cell_table), then the attributes canalisation adds to it.
constexpr std::size_t kFixedCellFields = 14;
constexpr const char* kCellFields[] = {"id",
                                       "index",
                                       "age",
                                       "generation",
                                       "step",
                                       "type",
                                       "fixed",
                                       "x",
                                       "y",
                                       "z",
                                       "vx",
                                       "vy",
                                       "vz",
                                       "neighbours",
                                       venation::kFlow,
                                       venation::kRadius,
                                       venation::kOrder,
                                       venation::kFlowX,
                                       venation::kFlowY,
                                       venation::kFlowZ};

/// cell.k for a k the table does not hold: nil for an attribute not computed yet (flow before the first
/// canalisation); an error for an attribute in a script without venation{} (it would be nil for good), and for any
/// other field, naming the closest one.
int api_cell_index(lua_State* L) {
  if (lua_type(L, 2) != LUA_TSTRING) return 0;
  const char* key = lua_tostring(L, 2);
  const bool attribute =
      std::find_if(std::begin(kCellFields) + kFixedCellFields, std::end(kCellFields),
                   [key](const char* f) { return std::string_view(key) == f; }) != std::end(kCellFields);
  if (attribute && self_of(L)->venation_runs) return 0;
  return guarded(L, [key, attribute](Impl& I) {  // (guarded: no Lua error while the message's strings live)
    if (attribute)  // (a walkthrough's rule read cell.flow for good in a script without venation{}: always nil)
      throw InvalidInput(I.where(1) + "cell." + key +
                         " is an attribute canalisation computes, and this script has no venation{...}: it would "
                         "be nil for good; add venation{...} (with a petiole{...}), or read another field");
    const std::string near = core::closest_name(std::string(key), kCellFields);
    if (near == key)  // a field of every cell, set to nil by the rule itself (c.x = nil)
      throw InvalidInput(I.where(1) + "cell." + near + " is nil: the rule set it to nil before reading it");
    throw InvalidInput(I.where(1) + "cell." + core::printable(key) + ": the cell table has no such field" +
                       (near.empty() ? "" : "; did you mean '" + near + "'?") +
                       " (its fields: id, index, x, y, z, vx, vy, vz, age, generation, type, fixed, neighbours, step, "
                       "and flow, vein_radius, vein_order, flow_dx/dy/dz once venation runs)");
    return 0;
  });
}

/// print(P), P on top of the stack: one line "params { name = value, ... }" of its knobs.
int api_print_knobs(lua_State* L) {
  return guarded(L, [L](Impl& I) {
    if (I.print) I.print(knob_line(L, I, -1));
    return 0;
  });
}

void check_knobs_unchanged(Impl& I, std::uint64_t step) {
  if (I.params_ref == LUA_NOREF) return;
  lua_State* L = I.L;
  // outside any protected call a Lua memory error would abort: the limit waits (as in fill_cell_table)
  struct Host {
    Impl& I;
    bool was;
    ~Host() { I.in_host = was; }
  } host{I, I.in_host};
  I.in_host = true;
  const nlohmann::json& rec = I.knobs;
  lua_rawgeti(L, LUA_REGISTRYINDEX, I.params_ref);
  for (const auto& [name, was] : rec.items()) {
    lua_pushlstring(L, name.data(), name.size());
    lua_rawget(L, -2);
    if (knob_same(L, was)) {
      lua_pop(L, 1);
      continue;
    }
    const nlohmann::json now = knob_record(L);
    lua_pop(L, 1);
    // (as text: a NaN knob equals itself; a string that is not UTF-8 is written with replacements)
    auto text = [](const nlohmann::json& j) {
      return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    };
    if (text(now) != text(was)) {
      lua_pop(L, 1);
      throw InvalidInput(
          I.params_at + "params: " + (step ? "a rule function" : "the script") + " changed the knob " +
          core::printable(name) + " from " + text(was) + " to " + text(now) +
          (step ? " by the end of step " + std::to_string(step) : std::string(" after params{...} made it")) +
          ", but run.json records it as made: the knobs are read-only; give "
          "its value in params{...}, or --set " +
          core::printable(name) +
          "=VALUE for one run (a value computed from the knobs goes in a local "
          "variable)");
    }
  }
  lua_pop(L, 1);
}

}  // namespace cellform::app
