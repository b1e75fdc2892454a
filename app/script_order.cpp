// pairs() and table.sort() in a fixed order. Lua seeds its string hashes anew in every process, so its own
// order of a table's keys changed from run to run with the same script and seed; and its sort picks random
// pivots (from the clock) once a split is badly unbalanced, so equal elements came out in another order.
#include <climits>
#include <cstring>

#include "app/script_impl.h"

namespace cellform::app {

namespace {

// (No C++ object lives in these functions: a Lua error longjmps past them.)

int key_rank(lua_State* L, int i) {
  switch (lua_type(L, i)) {
    case LUA_TNUMBER:
      return 0;
    case LUA_TSTRING:
      return 1;
    case LUA_TBOOLEAN:
      return 2;
    default:
      return 3;  // tables, functions, ...: Lua's order (their hashes are addresses)
  }
}

/// pairs' order of keys (the values at stack indices a and b): numbers ascending, then strings in byte
/// order (not the locale's), then false before true, then the rest, all equal.
bool key_less(lua_State* L, int a, int b) {
  const int ra = key_rank(L, a), rb = key_rank(L, b);
  if (ra != rb) return ra < rb;
  if (ra == 0) return lua_compare(L, a, b, LUA_OPLT) != 0;  // numbers: no metamethod, integers and floats exactly
  if (ra == 1) {
    std::size_t la = 0, lb = 0;
    const char* sa = lua_tolstring(L, a, &la);
    const char* sb = lua_tolstring(L, b, &lb);
    const int c = std::memcmp(sa, sb, la < lb ? la : lb);
    return c < 0 || (c == 0 && la < lb);
  }
  return ra == 2 && !lua_toboolean(L, a) && lua_toboolean(L, b);
}

/// Whether the value at `a` goes before the one at `b`: with `cmp` 0, pairs' key order; else the comparator
/// at stack index `cmp` if it is a function, or `<` if it is nil.
bool sort_less(lua_State* L, int cmp, int a, int b) {
  if (cmp == 0) return key_less(L, a, b);
  if (lua_isnil(L, cmp)) return lua_compare(L, a, b, LUA_OPLT) != 0;
  lua_pushvalue(L, cmp);
  lua_pushvalue(L, a);
  lua_pushvalue(L, b);
  lua_call(L, 2, 1);
  const bool less = lua_toboolean(L, -1) != 0;
  lua_pop(L, 1);
  return less;
}

/// Every 4,096 comparisons of a sort: a beat for the watchdog (the sort is progress, not a stuck library call)
/// and, while the script is read, a Ctrl-C stops it here, as the hook stops the script's own code.
void sort_progress(lua_State* L, lua_Integer& compared) {
  if (++compared % 4096 != 0) return;
  Impl& I = *self_of(L);
  I.beats.fetch_add(1, std::memory_order_relaxed);
  if (!I.stopping && !I.rule_call && g_interrupt.load(std::memory_order_relaxed))
    I.stop("interrupted while the script was read; nothing was written");
  if (I.stopping) {
    lua_pushstring(L, I.stop_message.c_str());
    lua_error(L);
  }
}

/// Sorts the array [1, n] of the table at stack index `t` (raw access), stable, by sort_less with `cmp`:
/// by insertion up to 16 elements, else a merge sort through a scratch table (pushed, then popped; the
/// sorted elements end in the table at `t`, which may then be the scratch one).
void stable_sort(lua_State* L, int t, lua_Integer n, int cmp) {
  lua_Integer compared = 0;
  if (n <= 16) {
    for (lua_Integer i = 2; i <= n; ++i) {
      lua_rawgeti(L, t, i);  // v
      lua_Integer j = i - 1;
      for (; j >= 1; --j) {
        lua_rawgeti(L, t, j);
        sort_progress(L, compared);
        if (!sort_less(L, cmp, lua_gettop(L) - 1, lua_gettop(L))) {  // v before t[j]: t[j] moves up
          lua_pop(L, 1);
          break;
        }
        lua_rawseti(L, t, j + 1);
      }
      lua_rawseti(L, t, j + 1);
    }
    return;
  }
  lua_createtable(L, static_cast<int>(n), 0);  // the next merge
  const int next = lua_gettop(L);
  for (lua_Integer width = 1; width < n; width *= 2) {
    for (lua_Integer lo = 1; lo <= n; lo += 2 * width) {
      const lua_Integer mid = lo + width < n + 1 ? lo + width : n + 1;
      const lua_Integer hi = lo + 2 * width < n + 1 ? lo + 2 * width : n + 1;
      lua_Integer i = lo, j = mid, k = lo;
      while (i < mid && j < hi) {
        lua_rawgeti(L, t, j);
        lua_rawgeti(L, t, i);
        const int top = lua_gettop(L);
        sort_progress(L, compared);
        if (sort_less(L, cmp, top - 1, top)) {  // the right one strictly first: equal ones keep their order
          lua_pop(L, 1);
          lua_rawseti(L, next, k++);
          ++j;
        } else {
          lua_rawseti(L, next, k++);
          lua_pop(L, 1);
          ++i;
        }
      }
      for (; i < mid; ++i) {
        lua_rawgeti(L, t, i);
        lua_rawseti(L, next, k++);
      }
      for (; j < hi; ++j) {
        lua_rawgeti(L, t, j);
        lua_rawseti(L, next, k++);
      }
    }
    lua_pushvalue(L, t);  // the merged runs become the elements: the two tables trade places
    lua_copy(L, next, t);
    lua_replace(L, next);
  }
  lua_pop(L, 1);
}

/// table.sort(t [, comp]): stable (stable_sort), with the elements read and written as table.sort does
/// (lua_geti, lua_seti: metamethods apply). Lua's own sort is not stable either, so a script that relied
/// on where equal elements went had no order to rely on; now they keep theirs.
int ordered_sort(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const lua_Integer n = luaL_len(L, 1);
  if (n < 2) return 0;
  luaL_argcheck(L, n < INT_MAX, 1, "array too big");
  if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_settop(L, 2);
  lua_createtable(L, static_cast<int>(n), 0);  // 3: the elements
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_geti(L, 1, i);
    lua_rawseti(L, 3, i);
  }
  stable_sort(L, 3, n, 2);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, 3, i);
    lua_seti(L, 1, i);
  }
  return 0;
}

/// The iterator: upvalues the sorted keys, the table and the position. Keys set to nil since are skipped,
/// as next() skips them.
int ordered_next(lua_State* L) {
  lua_Integer at = lua_tointeger(L, lua_upvalueindex(3));
  for (;;) {
    ++at;
    if (lua_rawgeti(L, lua_upvalueindex(1), at) == LUA_TNIL) return 0;
    lua_pushvalue(L, -1);
    if (lua_rawget(L, lua_upvalueindex(2)) != LUA_TNIL) break;
    lua_pop(L, 2);
  }
  lua_pushinteger(L, at);
  lua_replace(L, lua_upvalueindex(3));
  return 2;
}

/// The continuation of a __pairs that yielded: its three results.
int pairs_continued(lua_State*, int, lua_KContext) { return 3; }

/// pairs(t): t's __pairs if it has one, as Lua's; otherwise its keys in key_less's order.
int ordered_pairs(lua_State* L) {
  if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {  // as Lua's: __pairs may yield
    lua_pushvalue(L, 1);
    lua_callk(L, 1, 3, 0, pairs_continued);
    return 3;
  }
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_settop(L, 1);
  lua_newtable(L);  // 2: the keys
  lua_Integer n = 0;
  lua_pushnil(L);
  while (lua_next(L, 1) != 0) {
    lua_pop(L, 1);
    lua_pushvalue(L, -1);
    lua_rawseti(L, 2, ++n);
  }
  // an array's keys come in order already (Lua visits its array part first): no sort, and no scratch table
  bool in_order = true;
  for (lua_Integer i = 2; i <= n && in_order; ++i) {
    lua_rawgeti(L, 2, i - 1);
    lua_rawgeti(L, 2, i);
    in_order = key_less(L, -2, -1);
    lua_pop(L, 2);
  }
  if (!in_order) stable_sort(L, 2, n, 0);
  lua_pushvalue(L, 2);
  lua_pushvalue(L, 1);
  lua_pushinteger(L, 0);
  lua_pushcclosure(L, ordered_next, 3);
  lua_pushvalue(L, 1);
  lua_pushnil(L);
  return 3;
}

}  // namespace

void install_fixed_orders(lua_State* L) {
  lua_pushcfunction(L, ordered_pairs);
  lua_setglobal(L, "pairs");
  lua_getglobal(L, LUA_TABLIBNAME);
  lua_pushcfunction(L, ordered_sort);
  lua_setfield(L, -2, "sort");
  lua_pop(L, 1);
}

}  // namespace cellform::app
