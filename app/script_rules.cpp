// Calling the script's rule functions (division.rule, division.direction, venation.source) on a cell.
#include <algorithm>
#include <cmath>
#include <string>

#include "app/script_host.h"
#include "app/script_impl.h"
#include "core/errors.h"
#include "venation/canalisation.h"

namespace cellform::app {

namespace {

/// (api_cell_index's kCellFields in script_values.cpp lists these fields for the error on a misspelt one.)
void fill_cell_table(Impl& I, const cells::Cells& c, core::Index i, std::uint64_t step) {
  lua_State* L = I.L;
  // outside any protected call a Lua memory error would abort: the limit waits for the rule's allocations
  const bool was_host = I.in_host;
  I.in_host = true;
  lua_rawgeti(L, LUA_REGISTRYINDEX, I.cell_table_ref);
  // raw sets: a metatable the script gave the table (__newindex raising an error) must not run here,
  // outside any protected call
  auto set_top = [&](const char* k) {  // table[k] = the value on top
    lua_pushstring(L, k);
    lua_insert(L, -2);
    lua_rawset(L, -3);
  };
  auto set_num = [&](const char* k, double v) {
    lua_pushnumber(L, v);
    set_top(k);
  };
  auto set_int = [&](const char* k, long long v) {
    lua_pushinteger(L, v);
    set_top(k);
  };
  set_int("id", static_cast<long long>(c.id[i]));
  set_int("index", static_cast<long long>(i) + 1);
  set_int("age", c.age[i]);
  set_int("generation", c.generation[i]);
  set_int("step", static_cast<long long>(step));
  static const char* const type_names[] = {"general", "petiole", "vein"};
  lua_pushstring(L, type_names[static_cast<int>(c.type[i])]);
  set_top("type");
  lua_pushboolean(L, c.fixed[i]);
  set_top("fixed");
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
  for (const auto& [name, values] : c.attributes)
    if (name == venation::kOrder && std::isfinite(values[i]))  // a whole number, as in cells.ply and veins.ply
      set_int(name.c_str(), static_cast<long long>(values[i]));
    else
      set_num(name.c_str(), values[i]);
  I.in_host = was_host;
}

}  // namespace

namespace {

/// Marks a rule call in progress for the watchdog (ScriptHost::Watchdog), which names it if the call is stuck.
class RuleCall {
 public:
  RuleCall(Impl& I, const char* rule, std::uint64_t step, std::uint64_t cell) : I_(I) {
    I.call_step.store(step, std::memory_order_relaxed);
    I.call_cell.store(cell, std::memory_order_relaxed);
    I.call_rule.store(rule, std::memory_order_release);
  }
  ~RuleCall() { I_.call_rule.store(nullptr, std::memory_order_release); }
  RuleCall(const RuleCall&) = delete;
  RuleCall& operator=(const RuleCall&) = delete;

 private:
  Impl& I_;
};

/// A rule's error that names no line (error(msg, 0), the memory limit passed inside a library call) gets the
/// rule function's: "file: msg" becomes "file:line: msg", `rule_at` being where the function is defined.
/// Also says why a venation attribute was nil (before the first canalisation pass), and that os and io are left
/// out of the sandbox, where Lua's message only says "a nil value".
std::string with_rule_line(const Impl& I, const std::string& err, const std::string& rule_at) {
  const std::string bare = I.script_name + ": ";
  std::string m = err.rfind(bare, 0) == 0 && rule_at != bare ? rule_at + err.substr(bare.size()) : err;
  for (const char* f :
       {venation::kFlow, venation::kRadius, venation::kOrder, venation::kFlowX, venation::kFlowY, venation::kFlowZ})
    if (m.find("a nil value (field '" + std::string(f) + "')") != std::string::npos)
      return m + "; if that is cell." + f +
             ", it is nil until the first canalisation pass (at step venation.every): " + "write (cell." + f + " or 0)";
  for (const char* g : {"os", "io", "debug", "package"})
    if (m.find("a nil value (global '" + std::string(g) + "')") != std::string::npos)
      return m + "; '" + g +
             "' is left out of cellform scripts (the sandbox keeps Lua's base functions, string, "
             "table, math, utf8 and coroutine)";
  return m;
}

/// What a division.direction rule returned, for its message: "{1, 0}", "nil", "string", "1, 0, nil".
std::string returned_direction(lua_State* L) {  // its three results on top (nothing here raises a Lua error)
  auto one = [L](int idx) {
    return lua_type(L, idx) == LUA_TNUMBER ? core::number_text(lua_tonumber(L, idx))
                                           : std::string(luaL_typename(L, idx));
  };
  if (lua_type(L, -3) == LUA_TTABLE) {
    const auto n = lua_rawlen(L, -3);
    if (n == 0) return "a table without items 1 to 3 ({x = ...} fields are not read)";
    std::string t = "{";
    for (lua_Integer k = 1; k <= static_cast<lua_Integer>(std::min<std::size_t>(n, 4)); ++k) {
      lua_rawgeti(L, -3, k);
      t += (k > 1 ? ", " : "") + one(-1);
      lua_pop(L, 1);
    }
    return t + (n > 4 ? ", ...}" : "}");
  }
  if (lua_type(L, -3) != LUA_TNUMBER) return one(-3);
  return one(-3) + ", " + one(-2) + ", " + one(-1);
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
      std::string err;
      {
        const RuleCall call(*I, "division.rule", step_, c.id[i]);
        err = I->protected_call(1, 1, I->limits.rule_instructions, true);
      }
      if (!err.empty()) throw fail("division.rule", with_rule_line(*I, err, I->divides_at), c, i);
      if (lua_type(L, -1) != LUA_TBOOLEAN) {
        const std::string got = luaL_typename(L, -1);
        lua_pop(L, 1);
        throw fail("division.rule", I->divides_at + "division.rule must return true or false, got " + got, c, i);
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
      std::string err;
      {
        const RuleCall call(*I, "division.direction", step_, c.id[i]);
        err = I->protected_call(1, 3, I->limits.rule_instructions, true);
      }
      if (!err.empty()) throw fail("division.direction", with_rule_line(*I, err, I->direction_at), c, i);
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
      const std::string got = ok && d.allFinite() ? std::string() : returned_direction(L);
      lua_pop(L, 3);
      if (!got.empty())
        throw fail(
            "division.direction",
            I->direction_at + "division.direction must return {x, y, z} (or x, y, z) of finite numbers, got " + got, c,
            i);
      // the split plane needs a length to normalise: a vector whose square underflows or overflows ({0, 0,
      // 1e-300}, {1e300, 1e300, 0}) is scaled first (its direction is all that counts); only zero is refused
      if (const double n = d.norm(); !(n > 0) || !std::isfinite(n)) d /= d.cwiseAbs().maxCoeff();
      if (!(d.norm() > 0)) {
        const auto flow = c.attributes.find(venation::kFlowX);
        const bool no_flow = flow != c.attributes.end() && flow->second[i] == 0 &&
                             c.attributes.at(venation::kFlowY)[i] == 0 && c.attributes.at(venation::kFlowZ)[i] == 0;
        throw fail("division.direction",
                   I->direction_at + "division.direction returned a zero vector" +
                       (no_flow ? std::string(" (this cell's flow_dx, flow_dy, flow_dz are all 0: a petiole, or a "
                                              "cell no flow reaches, has no flow direction; return another one there)")
                                : std::string()),
                   c, i);
      }
      return d;
    };
  }
  return r;
}

venation::SourceRule ScriptHost::source_rule() {
  constexpr double kMaxSource = 1e30;  // venation.source's range as a constant (schema.cpp)
  Impl* I = impl_.get();
  if (I->source_ref == LUA_NOREF) return {};
  return [this, I](const cells::Cells& c, core::Index i) {
    lua_State* L = I->L;
    lua_rawgeti(L, LUA_REGISTRYINDEX, I->source_ref);
    fill_cell_table(*I, c, i, step_);
    std::string err;
    {
      const RuleCall call(*I, "venation.source", step_, c.id[i]);
      err = I->protected_call(1, 1, I->limits.rule_instructions, true);
    }
    auto where = [&] {
      return " (in venation.source at step " + std::to_string(step_) + " for cell " + std::to_string(c.id[i]) + ")";
    };
    if (!err.empty()) throw InvalidInput(with_rule_line(*I, err, I->source_at) + where());
    if (lua_type(L, -1) != LUA_TNUMBER) {
      const std::string got = luaL_typename(L, -1);
      lua_pop(L, 1);
      throw InvalidInput(I->source_at + "venation.source must return a number from 0 to 1e30, got " + got + where());
    }
    const double v = lua_tonumber(L, -1);
    lua_pop(L, 1);
    if (!std::isfinite(v) || v < 0 || v > kMaxSource)
      throw InvalidInput(I->source_at +
                         "venation.source must return a number from 0 to 1e30 (as a constant source), got " +
                         core::number_text(v) + where());
    return v;
  };
}

}  // namespace cellform::app
