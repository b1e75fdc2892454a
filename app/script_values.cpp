// The script host's parameter values: a Lua value or a --set text converted for a field of the schema, its
// range checked, and a whole section read (ScriptHost::Impl, declared in app/script_impl.h; params{} is in
// app/script_params.cpp).
#include "app/script_impl.h"

#include <charconv>
#include <iterator>
#include <string_view>

#include "venation/canalisation.h"

namespace cellform::app {

std::string lua_text(lua_State* L, int idx) {
  std::size_t n = 0;
  const char* s = lua_tolstring(L, idx, &n);
  return s ? std::string(s, n) : std::string();
}

namespace {

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

/// "a|b|c" as "a, b or c", each quoted as a script writes it.
std::string choices_list(const std::string& choices) {
  std::vector<std::string> parts;
  std::stringstream ss(choices);
  for (std::string part; std::getline(ss, part, '|');) parts.push_back("\"" + part + "\"");
  std::string s;
  for (std::size_t i = 0; i < parts.size(); ++i) s += (i == 0 ? "" : i + 1 == parts.size() ? " or " : ", ") + parts[i];
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
    case Kind::table_or_function:
      return v.ref != LUA_NOREF ? nlohmann::json("<function>") : nlohmann::json::object();
  }
  return {};
}

}  // namespace

Value ScriptHost::Impl::from_lua(const Field& f, int idx, const std::string& at) {
  Value v;
  v.present = true;
  const std::string name = f.section + "." + f.name;
  auto fail = [&](const std::string& got) -> InvalidInput {
    return InvalidInput(at + name + " must be " + allowed_text(f) + ", got " + got);
  };
  const int t = lua_type(L, idx);
  const std::string got = t == LUA_TSTRING ? std::string("\"") + lua_tostring(L, idx) + "\"" : luaL_typename(L, idx);
  if (t == LUA_TSTRING) {  // C strings end at a NUL: file = "a.stl\0x" would read a.stl
    std::size_t len = 0;
    const char* text = lua_tolstring(L, idx, &len);
    if (std::string_view(text, len).find('\0') != std::string_view::npos) {
      std::string shown;
      for (std::size_t k = 0; k < len && k < 200; ++k) shown += text[k] ? std::string(1, text[k]) : "\\0";
      throw InvalidInput(at + name + " must not contain a NUL byte, got \"" + shown + "\"");
    }
  }
  switch (f.kind) {
    case Kind::number:
    case Kind::integer:
      if (t != LUA_TNUMBER) throw fail(got);
      v.num = lua_tonumber(L, idx);
      // a Lua integer beyond 2^53 is no double: it would be taken rounded (9007199254740993 as ...992)
      if (f.kind == Kind::integer && lua_isinteger(L, idx) &&
          (!(std::abs(v.num) < 0x1p63) || static_cast<lua_Integer>(v.num) != lua_tointeger(L, idx)))
        throw InvalidInput(at + name + " must be a whole number of at most 2^53 (9007199254740992) in size, got " +
                           std::to_string(lua_tointeger(L, idx)));
      break;
    case Kind::boolean:
      if (t != LUA_TBOOLEAN) throw fail(got);
      v.flag = lua_toboolean(L, idx) != 0;
      break;
    case Kind::vec3: {
      if (t != LUA_TTABLE || lua_rawlen(L, idx) != 3) throw fail(t == LUA_TTABLE ? "a table without 3 numbers" : got);
      {  // {x, y, z} and nothing else: {0.5, 0.5, 0.5, [10] = 1} dropped its extra entry unseen
        const int table = lua_absindex(L, idx);
        // the key beside 1, 2, 3 ('n' of table.pack(x, y, z), say); of several, the first in byte order of
        // their texts, as Lua's own order changes from run to run
        std::string extra;
        lua_pushnil(L);
        while (lua_next(L, table) != 0) {
          lua_pop(L, 1);
          if (lua_isinteger(L, -1) && lua_tointeger(L, -1) >= 1 && lua_tointeger(L, -1) <= 3) continue;
          // by its raw value: a __tostring would run the script in here, and an error it raised would
          // longjmp past this frame's objects and the host's restores
          const int kt = lua_type(L, -1);
          std::string text;
          if (kt == LUA_TSTRING)
            text = "'" + core::printable(lua_tostring(L, -1)) + "'";
          else if (kt == LUA_TNUMBER)
            text =
                "[" +
                (lua_isinteger(L, -1) ? std::to_string(lua_tointeger(L, -1)) : core::number_text(lua_tonumber(L, -1))) +
                "]";
          else if (kt == LUA_TBOOLEAN)
            text = lua_toboolean(L, -1) ? "[true]" : "[false]";
          else
            text = "[a " + std::string(lua_typename(L, kt)) + "]";
          if (extra.empty() || text < extra) extra = text;
        }
        if (!extra.empty()) throw fail("a table with an entry beside x, y and z (key " + extra + ")");
      }
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
    case Kind::table_or_function:  // a table is read by the section itself
      if (t == LUA_TFUNCTION) {
        lua_pushvalue(L, idx);
        v.ref = luaL_ref(L, LUA_REGISTRYINDEX);
      } else if (t != LUA_TTABLE) {
        throw fail(got);
      }
      break;
  }
  return v;
}

Value ScriptHost::Impl::from_text(const Field& f, const std::string& text, const std::string& at) {
  Value v;
  v.present = true;
  const std::string name = f.section + "." + f.name;
  auto fail = [&]() { return InvalidInput(at + name + " must be " + allowed_text(f) + ", got \"" + text + "\""); };
  switch (f.kind) {
    case Kind::number:
    case Kind::integer:
    case Kind::number_or_function: {
      if (!parse_double(text, v.num)) throw fail();
      long long whole = 0;  // a whole number the double would round (9007199254740993 as ...992): refused
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), whole);
      if (f.kind == Kind::integer && ec == std::errc() && end == text.data() + text.size() &&
          (!(std::abs(v.num) < 0x1p63) || static_cast<long long>(v.num) != whole))
        throw InvalidInput(at + name + " must be a whole number of at most 2^53 (9007199254740992) in size, got " +
                           text);
      break;
    }
    case Kind::boolean:
      // only these, as in a script and for a params{} knob (and 1 or 0 from an older checkpoint's --set)
      if (text == "true" || (text == "1" && digit_booleans.count(name)))
        v.flag = true;
      else if (text == "false" || (text == "0" && digit_booleans.count(name)))
        v.flag = false;
      else
        throw fail();
      break;
    case Kind::vec3:
      if (!parse_vec(text, v.vec))
        throw InvalidInput(at + name + " must be " + allowed_text(f) + ", got \"" + text +
                           "\"; on the command line three numbers: --set " + name + "=X,Y,Z");
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
    case Kind::table_or_function:
      throw InvalidInput(at + name + " cannot be set from the command line");
  }
  return v;
}

namespace {
/// A number as a refusal quotes it: 15 digits, enough to show why 3.0000000001 is not whole or why
/// 1.0000001 is above 1; NaN as "NaN" (the stream writes "-nan" for 0/0).
std::string got_text(double x) {
  if (std::isnan(x)) return "NaN";
  std::ostringstream g;
  // a whole number beyond 15 digits in full (2^53 + 2 read as 9.00719925474099e+15 looked like the limit)
  if (x == std::floor(x) && std::abs(x) >= 1e15 && std::abs(x) < 0x1p63)
    g << static_cast<long long>(x);
  else
    g << std::setprecision(15) << x;
  return g.str();
}
}  // namespace

void ScriptHost::Impl::check_range(const Field& f, Value& v, const std::string& at) {
  if (!v.present) return;
  const std::string name = f.section + "." + f.name;
  // (nonzero_min: besides 0, an automatic value, nothing below it)
  auto bad = [&](double x) {
    return !std::isfinite(x) || x < f.min || x > f.max || (f.min_exclusive && x <= f.min) ||
           (f.nonzero_min > 0 && x != 0 && x < f.nonzero_min);
  };
  auto fail = [&](const std::string& got) {
    // allowed_text leaves out the far limit that every number has (1e300): say it when it is the one passed
    const bool far = f.max >= 1e299 && (v.num > f.max || v.vec.cwiseAbs().maxCoeff() > f.max);
    std::ostringstream limit;
    limit << f.max;
    return InvalidInput(at + name + " must be " + allowed_text(f) + (far ? " and at most " + limit.str() : "") +
                        ", got " + got);
  };
  if (f.kind == Kind::number || f.kind == Kind::integer || (f.kind == Kind::number_or_function && v.ref == LUA_NOREF)) {
    if (bad(v.num)) throw fail(got_text(v.num));
    if (f.kind == Kind::integer && v.num != std::floor(v.num)) throw fail(got_text(v.num));
  } else if (f.kind == Kind::vec3) {
    for (int i = 0; i < 3; ++i)
      if (bad(v.vec[i]))
        throw fail("{" + got_text(v.vec.x()) + ", " + got_text(v.vec.y()) + ", " + got_text(v.vec.z()) + "}");
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

std::vector<std::string> sorted_names(lua_State* L, int idx, bool& unnamed) {
  idx = lua_absindex(L, idx);
  std::vector<std::string> names;
  unnamed = false;
  lua_pushnil(L);
  while (lua_next(L, idx) != 0) {
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING) {
      unnamed = true;
      continue;
    }
    std::size_t len = 0;
    const char* text = lua_tolstring(L, -1, &len);  // a string key: read, not converted
    names.emplace_back(text, len);
  }
  std::sort(names.begin(), names.end());
  return names;
}

Values ScriptHost::Impl::read_section(const std::string& section, int idx, const std::string& at,
                                      nlohmann::json* record) {
  const auto fields = section_fields(section);
  const int t = lua_type(L, idx);
  if (t != LUA_TTABLE && t != LUA_TNONE && t != LUA_TNIL)
    throw InvalidInput(at + section + "{...} takes a table of named parameters, got " + luaL_typename(L, idx));
  Values values;
  if (t == LUA_TTABLE) {
    // the names in byte order, so that the same script is refused with the same message every time
    idx = lua_absindex(L, idx);
    bool unnamed = false;
    const std::vector<std::string> keys = sorted_names(L, idx, unnamed);
    if (unnamed)
      throw InvalidInput(at + section + "{...}: parameters are named (name = value); got a value without a name" +
                         (section == "print" ? kPrintTableHint : ""));
    for (const std::string& key : keys) {
      const Field* f = find_field(section, key);
      if (!f) {
        std::vector<std::string> names;
        for (const Field* g : fields) names.push_back(g->name);
        const std::string near = core::closest_name(key, names);
        std::string all;
        for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
        throw InvalidInput(at + section + "{...} has no parameter '" + core::printable(key) + "'" +
                           (near.empty() ? "" : "; did you mean '" + near + "'?") + " (valid: " + all + ")" +
                           (section == "print" && near.empty() ? kPrintTableHint : ""));
      }
      lua_pushlstring(L, key.data(), key.size());
      lua_rawget(L, idx);  // raw: no metamethod runs inside the host
      try {
        values[key] = from_lua(*f, lua_gettop(L), at);
      } catch (...) {
        lua_pop(L, 1);
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
        values[f->name].set_by = "--set " + key + "=" + it->second;
        used_overrides.insert(key);
      }
    }
    Value& v = values[f->name];
    if (!v.present && !f->structured()) {
      if (f->default_text.empty())
        throw InvalidInput(at + section + "{...} needs '" + f->name + "' (" + allowed_text(*f) + ")");
      if (f->default_text.find("cells.") == std::string::npos) {
        Value d = from_text(*f, f->default_text, "schema default: ");
        d.present = false;
        v.num = d.num, v.vec = d.vec, v.flag = d.flag, v.str = d.str;
      }
    }
    check_range(*f, v, value_at);
    if (record && f->kind != Kind::table && f->kind != Kind::table_or_function &&
        (v.present || f->default_text.find("cells.") == std::string::npos))
      (*record)[f->name] = to_json(*f, v);
  }
  return values;
}

}  // namespace cellform::app
