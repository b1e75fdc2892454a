// Private to app/: the script host's state, parameter values, and the sections of the script API.
#pragma once

#include <unistd.h>

#include <atomic>

#include <lua.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/run.h"
#include "app/schema.h"
#include "app/script_host.h"
#include "core/errors.h"

namespace cellform::app {

using core::InvalidInput;
using core::Vec3;

inline constexpr int kHookEvery = 1000;  // instructions between budget checks

/// The string (or number) at `idx`, whole: a Lua string may hold zero bytes, where a C string ends.
std::string lua_text(lua_State* L, int idx);
// the hook counts instructions (budget, Ctrl-C) and sees every call begin (the watchdog's beats)
inline constexpr int kHookMask = LUA_MASKCOUNT | LUA_MASKCALL;

/// A parameter value after conversion from Lua or from a --set string.
struct Value {
  bool present = false;  // given by the script or --set (false: the schema default applies, if any)
  double num = 0;
  Vec3 vec = Vec3::Zero();
  bool flag = false;
  std::string str;
  int ref = LUA_NOREF;  // a function in the registry
  std::string set_by;   // "--set section.name=value" when an override gave it
};

using Values = std::map<std::string, Value>;

/// A call of a shape function, evaluated after the script has run (when rest_length is known).
struct ShapeCall {
  std::string kind;
  Values values;
  std::string where;
};

struct ScriptHost::Impl {
  lua_State* L = nullptr;
  ScriptLimits limits;
  std::size_t used = 0;
  bool memory_exceeded = false;
  // alloc refused this allocation over the limit and waits for Lua to ask again, after a collection
  bool refused = false;
  void* refused_ptr = nullptr;
  std::size_t refused_osize = 0, refused_nsize = 0;
  std::size_t placements = 0;  // shape and constraint calls of the script being read
  bool in_host = false;        // an API function's C++ body runs: no Lua error may be raised (see alloc)
  // for the watchdog (ScriptHost::Watchdog): hook calls so far, and whether Lua code runs now
  std::atomic<std::uint64_t> beats{0};
  std::atomic<bool> ask_caller{false};    // set by the watchdog: the next call from the script's code beats
  std::atomic<bool> stop_pending{false};  // `stopping`, for the watchdog (a stop Lua code escapes is its)
  // set by the watchdog when a Ctrl-C has waited 0.5 s: calls check it too (a loop of library calls may
  // run few instructions of its own)
  std::atomic<bool> interrupt_at_calls{false};
  std::atomic<bool> in_script{false};
  // set by the watchdog before it ends the process: the script's thread, should the stuck call end after
  // all, waits here for the end instead of going on beside the watchdog's handler
  std::atomic<bool> dying{false};
  // the rule call in progress (none: nullptr), for the watchdog's message: the step and cell id are stored
  // before the rule's name (release), read after it (acquire)
  std::atomic<const char*> call_rule{nullptr};
  std::atomic<std::uint64_t> call_step{0}, call_cell{0};
  void wait_if_dying() const {
    while (dying.load(std::memory_order_acquire)) ::pause();
  }
  std::uint64_t executed = 0;
  std::uint64_t budget = 0;
  int hook_every = kHookEvery;  // instructions between the hook's budget checks (fewer for a tiny budget)
  bool rule_call = false;       // the budget is a rule function's per-call one, which no option raises
  // the call ran out of budget or was interrupted: every instruction from then on raises the error again,
  // so a script's pcall cannot catch it and go on (the hook runs each instruction then)
  bool stopping = false;
  std::string stop_message;
  std::string script_name;
  std::filesystem::path script_dir;
  std::function<void(const std::string&)> print;

  // state while a script loads
  SceneConfig* cfg = nullptr;
  const Overrides* overrides = nullptr;
  std::set<std::string> digit_booleans;  // see ScriptHost::accept_digit_booleans
  std::set<std::string> used_overrides;
  std::map<std::string, std::string> sections_seen;  // section -> where
  std::string first_constraint;                      // where and which: the first obstacle or attractor
  std::vector<ShapeCall> shapes;
  std::set<std::string> param_names;
  std::string pending_error;

  // rule functions
  int divides_ref = LUA_NOREF;
  int direction_ref = LUA_NOREF;
  bool division_radius_derived = true;  // division.radius not given: 1.25 rest lengths, set once cells{} is read
  int source_ref = LUA_NOREF;
  // "file:line: " of the section that set each rule, for the messages of its calls during the run
  std::string divides_at, direction_at, source_at;
  int cell_table_ref = LUA_NOREF;
  bool venation_runs = false;      // the script loaded last has venation{}: its attributes come (else they never do)
  int randomseed_ref = LUA_NOREF;  // math.randomseed as the library made it (ScriptHost::set_step)
  int params_ref = LUA_NOREF;      // the table params{} returned (P), and its metatable
  int params_meta_ref = LUA_NOREF;
  std::string params_at;  // "file:line: " of the params{} call
  nlohmann::json knobs;   // the knobs as params{} made them (run.json's record), for the checks after steps

  static void* alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize) {
    auto* self = static_cast<Impl*>(ud);
    const std::size_t old = ptr ? osize : 0;
    if (nsize == 0) {
      self->used -= old;
      std::free(ptr);
      return nullptr;
    }
    // host code (an API function's C++ body) may pass the limit: a Lua memory error there would longjmp
    // past its C++ objects; the script's next allocation fails instead
    if (nsize > old && !self->in_host) {
      // An allocation over the limit that collecting all garbage could make room for is refused once:
      // Lua then collects and asks again. Asked again, the script really holds that much: allocations
      // pass, up to twice the limit and 256 MiB more, and the hook's next instruction stops the script
      // with the line it is at (a Lua memory error names none). Not asked again (a library's buffer, which
      // raises "not enough memory" at once, as a pcall may catch), the refusal stands as a memory error.
      // One allocation beyond twice the limit and 256 MiB fails, with no line.
      const bool retry =
          self->refused && ptr == self->refused_ptr && osize == self->refused_osize && nsize == self->refused_nsize;
      self->refused = false;
      const std::size_t want = self->used - old + nsize;
      if (want > self->limits.memory_bytes) {
        if (!self->memory_exceeded && !retry && nsize - old <= self->limits.memory_bytes) {  // garbage may make room
          self->refused = true;
          self->refused_ptr = ptr;
          self->refused_osize = osize;
          self->refused_nsize = nsize;
          return nullptr;
        }
        self->exceeded();
        if (want > 2 * self->limits.memory_bytes + (std::size_t{256} << 20)) return nullptr;
      }
    }
    void* p = std::realloc(ptr, nsize);
    if (p) self->used = self->used - old + nsize;
    return p;
  }

  /// The script is over its memory limit: the hook's next instruction says so (see alloc).
  void exceeded() {
    if (memory_exceeded) return;
    memory_exceeded = true;
    lua_sethook(L, &Impl::hook, kHookMask, 1);
  }

  /// "the script exceeded its memory limit of N MiB; ..." (the line in front, where it is known).
  std::string memory_message() const {
    return "the script exceeded its memory limit of " + std::to_string(limits.memory_bytes >> 20) +
           " MiB; raise it with --lua-memory";
  }

  /// Pushes "file:line: " of the line running now, or "" when there is none (luaL_error would name the
  /// caller's line, which for the main chunk is none).
  static void push_where(lua_State* L, lua_Debug* ar) {
    lua_getinfo(L, "Sl", ar);
    if (ar->currentline > 0)
      lua_pushfstring(L, "%s:%d: ", ar->short_src, ar->currentline);
    else
      lua_pushliteral(L, "");
  }

  static void hook(lua_State* L, lua_Debug* ar) {
    Impl* self = *static_cast<Impl**>(lua_getextraspace(L));
    self->wait_if_dying();
    if (ar->event != LUA_HOOKCOUNT) {
      // A call made by Lua code beats: the watchdog then times one library call. A function a library call
      // calls back (gsub's replacement, sort's comparator) does not: it runs inside that call.
      // Asking who called costs about 25 ns a call, so it is asked only once the watchdog has seen no beat
      // for a while: then the next call the script's code makes beats, and callbacks never do.
      if (self->ask_caller.load(std::memory_order_relaxed)) {
        lua_Debug caller;
        bool from_library = false;
        if (lua_getstack(L, 1, &caller) && lua_getinfo(L, "f", &caller)) {
          from_library = lua_iscfunction(L, -1) != 0;
          lua_pop(L, 1);
        }
        if (!from_library) {
          self->ask_caller.store(false, std::memory_order_relaxed);
          self->beats.fetch_add(1, std::memory_order_relaxed);
        }
      }
      // a library call that calls back may run no instruction of the script's own for a long time: a stop
      // acts at its calls too, and a Ctrl-C the count has not seen for 0.5 s
      if (!self->stopping && !self->rule_call && self->interrupt_at_calls.load(std::memory_order_relaxed) &&
          g_interrupt.load(std::memory_order_relaxed))
        self->stop("interrupted while the script was read; nothing was written");
      if (self->stopping) {
        lua_pushstring(L, self->stop_message.c_str());
        lua_error(L);
      }
      return;
    }
    self->beats.fetch_add(1, std::memory_order_relaxed);
    if (self->stopping) {
      // every thread the script runs (a coroutine has its own hook count) raises at each instruction
      if (lua_gethookcount(L) != 1) lua_sethook(L, &Impl::hook, kHookMask, 1);
      lua_pushstring(L, self->stop_message.c_str());
      lua_error(L);
    }
    if (self->memory_exceeded) {  // set by alloc, which can raise no error with a line
      push_where(L, ar);
      lua_pushstring(L, self->memory_message().c_str());
      lua_concat(L, 2);
      self->stop(lua_tostring(L, -1));
      lua_error(L);
    }
    if (lua_gethookcount(L) != self->hook_every) {  // a coroutine kept from a call that was stopped
      lua_sethook(L, &Impl::hook, kHookMask, self->hook_every);
      return;
    }
    self->executed += static_cast<std::uint64_t>(self->hook_every);
    // Ctrl-C while a script is read (a rule's step ends first: the run then stops after it)
    if (!self->rule_call && g_interrupt.load(std::memory_order_relaxed)) {
      self->stop("interrupted while the script was read; nothing was written");
      lua_sethook(L, &Impl::hook, kHookMask, 1);
      lua_pushstring(L, self->stop_message.c_str());
      lua_error(L);
    }
    if (self->executed > self->budget) {
      push_where(L, ar);
      if (self->rule_call)
        lua_pushfstring(L,
                        "a rule function ran more than %I instructions in one call (an endless loop?); it is called "
                        "for every cell, so it must be short",
                        static_cast<lua_Integer>(self->budget));
      else
        lua_pushfstring(
            L, "instruction budget of %I instructions exceeded (an endless loop?); raise it with --lua-instructions",
            static_cast<lua_Integer>(self->budget));
      lua_concat(L, 2);
      self->stop(lua_tostring(L, -1));
      lua_sethook(L, &Impl::hook, kHookMask, 1);  // this thread too: a coroutine has its own count
      lua_error(L);
    }
  }

  /// From now until the call ends, every instruction raises `message` (see `stopping`).
  void stop(const std::string& message) {
    stopping = true;
    stop_pending.store(true, std::memory_order_release);
    stop_message = message;
    lua_sethook(L, &Impl::hook, kHookMask, 1);
  }

  /// `text` with the script's path whole where Lua shortened it ("..." and its last 56 bytes: LUA_IDSIZE),
  /// so that a long path in a message can be copied.
  std::string whole_path(std::string text) const {
    for (std::size_t at = text.find("..."); at != std::string::npos; at = text.find("...", at + 3)) {
      const std::size_t colon = text.find(':', at + 3);
      if (colon == std::string::npos) break;
      const std::size_t tail = colon - at - 3;
      if (tail >= 20 && script_name.size() > tail &&
          script_name.compare(script_name.size() - tail, tail, text, at + 3, tail) == 0) {
        text.replace(at, colon - at, script_name);
        at += script_name.size() - 3;
      }
    }
    return text;
  }

  /// Turns a Lua error message into one line that names the script; adds the memory-limit hint. A message
  /// longer than 4,000 bytes keeps its first 3,000 and its last 1,000 (error(string.rep("x", 1e8)) wrote 100 MB
  /// to the terminal; the end of an error passed up through nested coroutines says what went wrong).
  std::string describe(const std::string& message) const {
    std::string lua_message = whole_path(message);
    // a zero byte (error("a\0b")) would end the message in an exception's what(): as the terminal shows it
    for (std::size_t at = lua_message.find('\0'); at != std::string::npos; at = lua_message.find('\0', at + 4))
      lua_message.replace(at, 1, "\\x00");
    constexpr std::size_t kLongest = 4000, kHead = 3000;
    if (lua_message.size() > kLongest) {
      const auto inside = [&](std::size_t at) {  // inside a UTF-8 sequence
        return (static_cast<unsigned char>(lua_message[at]) & 0xc0) == 0x80;
      };
      std::size_t cut = kHead, tail = lua_message.size() - (kLongest - kHead);
      while (cut > 0 && inside(cut)) --cut;
      while (tail < lua_message.size() && inside(tail)) ++tail;
      return describe(lua_message.substr(0, cut)) + "... (" + std::to_string(tail - cut) +
             " bytes of the message left out) ..." + lua_message.substr(tail);
    }
    {
      // the hook's stop, with its place; Lua's own memory error, without (another error, such as a syntax
      // error found while the limit was passed, is itself)
      const std::string text = memory_message();
      if (lua_message.size() > text.size() &&
          lua_message.compare(lua_message.size() - text.size(), text.size(), text) == 0)
        return lua_message;
      if (lua_message == "not enough memory") return script_name + ": " + text;
    }
    if (lua_message == "C stack overflow")  // Lua's parser says it with no place
      return script_name +
             ": C stack overflow: the script nests deeper than Lua allows (about 200 levels of brackets, table "
             "constructors, blocks or calls within calls); split the deepest expression";
    if (lua_message.find("attempt to load a binary chunk") != std::string::npos)
      return script_name + ": precompiled (binary) Lua chunks are not allowed; give the script as source text";
    // coroutine.wrap passes an error on with its own "file:line: " in front of the one it has
    std::string msg = lua_message;
    const std::size_t colon = msg.find(": ");
    const std::size_t line = colon == std::string::npos ? colon : msg.rfind(':', colon - 1);
    if (line != std::string::npos && line + 1 < colon && msg.find_first_not_of("0123456789", line + 1) == colon) {
      const std::string where = msg.substr(0, colon + 2);
      while (msg.compare(where.size(), where.size(), where) == 0) msg.erase(0, where.size());
      return msg;
    }
    // no place (error("...", 0)): the script's name at least
    if (msg.rfind(script_name + ":", 0) == 0 || msg.rfind("--set ", 0) == 0) return msg;
    return script_name + ": " + msg;
  }

  /// pcall with the instruction budget reset to `budget`; returns "" or the error message.
  std::string protected_call(int nargs, int nresults, std::uint64_t call_budget, bool rule = false) {
    executed = 0;
    budget = call_budget;
    rule_call = rule;
    memory_exceeded = false;
    refused = false;
    // a budget under kHookEvery instructions is checked as often as it is small
    const int every = static_cast<int>(std::clamp<std::uint64_t>(call_budget, 1, kHookEvery));
    if (stopping || every != hook_every) {
      stopping = false;
      stop_pending.store(false, std::memory_order_release);
      hook_every = every;
      lua_sethook(L, &Impl::hook, kHookMask, hook_every);
    }
    const int base = lua_gettop(L) - nargs;  // the function; the handler goes below it
    lua_pushcfunction(L, &Impl::error_object_text);
    lua_insert(L, base);
    in_script.store(true, std::memory_order_release);
    const int rc = lua_pcall(L, nargs, nresults, base);
    wait_if_dying();
    in_script.store(false, std::memory_order_release);
    lua_remove(L, base);
    if (rc == LUA_OK && !stopping) return {};
    std::string msg = rc != LUA_OK && lua_type(L, -1) == LUA_TSTRING ? lua_text(L, -1) : "error object is not a string";
    lua_pop(L, rc != LUA_OK ? 1 : nresults);
    if (stopping && g_interrupt.load()) return stop_message;  // a Ctrl-C, whatever else happened
    if (stopping) msg = stop_message;                         // whatever the script made of it
    return describe(msg);
  }

  /// Message handler: error(x) with x not a string gets the script line, with x as the message if it is a
  /// number and a note of its type otherwise (Lua adds the line only to string messages).
  static int error_object_text(lua_State* L) {
    if (lua_type(L, 1) == LUA_TSTRING) {
      // Lua says a C stack overflow (a recursion through string.gsub, say), a yield outside a coroutine, a
      // comparison a library function made (table.sort of a number and a string), or next() given a key its
      // table does not hold, without a line: the line of the innermost script function running is added
      const char* text = lua_tostring(L, 1);
      const bool overflow = std::strcmp(text, "C stack overflow") == 0;
      if (!overflow && std::strcmp(text, "attempt to yield from outside a coroutine") != 0 &&
          std::strncmp(text, "attempt to compare ", 19) != 0 && std::strcmp(text, "invalid key to 'next'") != 0)
        return 1;
      for (int level = 1; level <= 32; ++level) {
        luaL_where(L, level);
        if (lua_rawlen(L, -1) > 0) {
          if (overflow)
            lua_pushliteral(L, "C stack overflow (a recursion too deep)");
          else
            lua_pushvalue(L, 1);
          lua_concat(L, 2);
          return 1;
        }
        lua_pop(L, 1);
      }
      return 1;
    }
    const char* type = luaL_typename(L, 1);     // (no C++ object here: a failing __tostring longjmps out)
    for (int level = 1; level <= 2; ++level) {  // the caller of error(), past error() itself
      luaL_where(L, level);
      if (lua_rawlen(L, -1) > 0) break;
      lua_pop(L, 1);
      if (level == 2) lua_pushliteral(L, "");
    }
    // error(42), or an error object that says what it is (__tostring, as lua.c prints it): its text
    bool says = lua_type(L, 1) == LUA_TNUMBER;
    if (!says && luaL_getmetafield(L, 1, "__tostring") != LUA_TNIL) {
      lua_pop(L, 1);
      says = true;
    }
    if (says)
      luaL_tolstring(L, 1, nullptr);  // pushes its text
    else
      lua_pushfstring(L, "error() was raised with a %s value, not a message; give error a string", type);
    lua_concat(L, 2);
    return 1;
  }

  /// "file:line: " of the Lua function in the registry at `ref` (where its definition starts), or `fallback`
  /// for a C function. Errors about what a rule returns point there rather than at its section's call.
  std::string function_at(int ref, const std::string& fallback) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, ref);
    lua_Debug ar;
    std::string out = fallback;
    if (lua_getinfo(L, ">S", &ar) && ar.linedefined > 0)
      out = script_name + ":" + std::to_string(ar.linedefined) + ": ";
    return out;
  }

  /// "file:line: " of the script line calling at `level`; through a C function (pcall(run, {...}), say)
  /// the nearest script line further out.
  std::string where(int level = 1) {
    std::string w;
    lua_Debug ar;
    for (int l = level; w.empty() && l < level + 8 && lua_getstack(L, l, &ar); ++l) {
      luaL_where(L, l);
      w = whole_path(lua_tostring(L, -1));
      lua_pop(L, 1);
    }
    if (w.empty()) w = script_name + ": ";
    return w;
  }

  /// Converts the Lua value at `idx` for field f; throws InvalidInput with `at` prefix.
  Value from_lua(const Field& f, int idx, const std::string& at);

  Value from_text(const Field& f, const std::string& text, const std::string& at);

  void check_range(const Field& f, Value& v, const std::string& at);

  /// Reads the table argument of a section function at stack index `idx` against the schema.
  Values read_section(const std::string& section, int idx, const std::string& at, nlohmann::json* record);

  /// Where the value of `key` (section.name) came from, for a message about it: "--set key=value: " when
  /// overridden, else `at` (the script line).
  std::string value_at(const std::string& key, const std::string& at) const {
    if (overrides)
      if (auto it = overrides->find(key); it != overrides->end()) return "--set " + key + "=" + it->second + ": ";
    return at;
  }

  void once(const std::string& section, const std::string& at) {
    if (sections_seen.emplace(section, at).second) return;
    throw InvalidInput(at + section + "{...} is given twice (first at " + seen_at(section) + ")");
  }

  /// Where the script gave `section`, as "file:line" (sections_seen keeps the prefix "file:line: ").
  std::string seen_at(const std::string& section) const {
    std::string where = sections_seen.at(section);
    while (!where.empty() && (where.back() == ' ' || where.back() == ':')) where.pop_back();
    return where;
  }

  /// The scene is described while the script loads; a rule function runs later, during the steps.
  void require_loading(const std::string& section, const std::string& at) const {
    if (!cfg || !sampling.empty())
      throw InvalidInput(at + section +
                         "{...} describes the scene and can only be called at the top level of the script, not "
                         "inside " +
                         (sampling.empty() ? std::string("a rule function") : sampling) +
                         (section == "print" ? std::string(kPrintTableHint) : std::string()));
  }
  /// print(t) of one table is print{...}; what to write instead to show a table's values.
  static constexpr const char* kPrintTableHint =
      " (print with one table is the print{...} section; to show a table, print its fields: for k, v in "
      "pairs(t) do print(k, v) end)";
  /// Set while a function given to a section is called as the script loads (colonisation.growth_x, ...).
  std::string sampling;
};

using Impl = ScriptHost::Impl;

/// The host of the Lua state running now (kept in the state's extra space).
inline Impl* self_of(lua_State* L) { return *static_cast<Impl**>(lua_getextraspace(L)); }

/// Pushes t[name] of the table at `idx` without metamethods (a script's __index could raise a Lua error,
/// which would longjmp past the C++ objects of the caller); returns its type.
inline int raw_field(lua_State* L, int idx, const char* name) {
  idx = lua_absindex(L, idx);
  lua_pushstring(L, name);
  return lua_rawget(L, idx);
}

/// Lets the script's memory limit fail allocations again while Lua code runs inside host code.
class LuaRunsHere {
 public:
  explicit LuaRunsHere(Impl& i) : i_(i), was_(i.in_host), was_script_(i.in_script.exchange(true)) { i.in_host = false; }
  ~LuaRunsHere() {
    i_.in_host = was_;
    i_.in_script.store(was_script_);
  }
  LuaRunsHere(const LuaRunsHere&) = delete;
  LuaRunsHere& operator=(const LuaRunsHere&) = delete;

 private:
  Impl& i_;
  bool was_, was_script_;
};

// The script API's sections (script_sections.cpp): each reads the table at stack index 1 against the
// schema and fills the scene configuration; `at` is "file:line: " of the call.
void section_cells(Impl& I, const std::string& at);
void section_division(Impl& I, const std::string& at);
void section_run(Impl& I, const std::string& at);
void section_venation(Impl& I, const std::string& at);
void section_leaf(Impl& I, const std::string& at);
void section_colonisation(Impl& I, const std::string& at);
void section_domain(Impl& I, const std::string& section, const std::string& at);  // volume{}, surface{}
/// After the script ran: checks and completes a space-colonisation configuration.
void finish_colonisation(Impl& I);
/// Rewrites a venation::Domain message ("domain.initial_nodes[2] ...") with the script's names.
std::string script_domain_message(const std::string& message, const std::string& section);
void section_print(Impl& I, const std::string& at);
void section_output(Impl& I, const std::string& at);
void section_shape(Impl& I, const std::string& kind, const std::string& at);
void section_constraint(Impl& I, const std::string& kind, const std::string& at);
/// Turns the recorded shape calls into initial cells and petioles (after the script ran).
void build_shapes(Impl& I);
/// Runs `body` (which returns the number of Lua results) and turns a C++ exception into a Lua error.
/// lua_error longjmps, so it is raised only after every C++ object of the body is destroyed.
template <class Body>
inline int guarded(lua_State* L, Body&& body) {
  Impl& I = *self_of(L);
  I.wait_if_dying();
  if (I.stopping) {  // as print(): a handler that runs with hooks off (xpcall's, after a stop) ends here
    lua_pushstring(L, I.stop_message.c_str());
    return lua_error(L);
  }
  int results = 0;
  bool failed = false;
  const bool was_host = I.in_host;  // (a nested call, a __tostring of params{} from a print, restores it)
  I.in_host = true;                 // no Lua memory error inside the body (the script's next allocation fails instead)
  // and no watchdog: the body is the host's own work (reading a large mesh), not a library call
  const bool was_script = I.in_script.exchange(false, std::memory_order_acq_rel);
  lua_State* const main = I.L;
  I.L = L;  // the body reads its arguments from the calling thread: a coroutine has a stack of its own
  try {
    results = body(I);
  } catch (const std::exception& e) {
    I.pending_error = core::error_text(e);
    failed = true;
  }
  I.in_script.store(was_script, std::memory_order_release);
  I.in_host = was_host;
  I.L = main;
  if (failed) {
    lua_pushstring(L, I.pending_error.c_str());
    return lua_error(L);
  }
  return results;
}

/// The string keys of the table at `idx`, in byte order: Lua's own order changes from run to run (its string
/// hashes are seeded per process). `unnamed` tells whether the table has other keys too. Raw: no metamethod
/// runs (script_values.cpp).
std::vector<std::string> sorted_names(lua_State* L, int idx, bool& unnamed);

/// params{name = default, ...}: the script's knobs, with --set overrides (script_values.cpp).
int api_params(lua_State* L);

/// print(P) of params{}' knobs, P on top of the stack (script_values.cpp).
int api_print_knobs(lua_State* L);

/// Throws if the script changed a knob of params{} after it was made (run.json records the knobs as made):
/// while it was read (step 0), or in a rule function during `step`.
void check_knobs_unchanged(Impl& I, std::uint64_t step = 0);

/// Replaces pairs with one that visits a table's keys in a fixed order (numbers ascending, then strings in byte
/// order, then false and true, then the rest), and table.sort with a stable merge sort (script_order.cpp).
/// Lua's own pairs follows string hashes seeded anew in every process, and its sort picks random pivots.
void install_fixed_orders(lua_State* L);

/// __index of the cell table: a misspelt field is an error naming the closest one (script_values.cpp).
int api_cell_index(lua_State* L);

}  // namespace cellform::app
