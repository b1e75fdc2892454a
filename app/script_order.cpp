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

/// table.sort's order of keys: numbers ascending, then strings in byte order (not the locale's), then false
/// before true, then the rest, all equal.
int key_before(lua_State* L) {
  const int a = key_rank(L, 1), b = key_rank(L, 2);
  bool before = a < b;
  if (a == b && a == 0) {
    before = lua_compare(L, 1, 2, LUA_OPLT) != 0;  // numbers: no metamethod, integers and floats exactly
  } else if (a == b && a == 1) {
    std::size_t la = 0, lb = 0;
    const char* sa = lua_tolstring(L, 1, &la);
    const char* sb = lua_tolstring(L, 2, &lb);
    const int c = std::memcmp(sa, sb, la < lb ? la : lb);
    before = c < 0 || (c == 0 && la < lb);
  } else if (a == b && a == 2) {
    before = !lua_toboolean(L, 1) && lua_toboolean(L, 2);
  }
  lua_pushboolean(L, before);
  return 1;
}

/// Whether the value at `a` goes before the one at `b`: the comparator at `cmp` if it is a function, else `<`.
bool sort_less(lua_State* L, int cmp, int a, int b) {
  if (lua_isnil(L, cmp)) return lua_compare(L, a, b, LUA_OPLT) != 0;
  lua_pushvalue(L, cmp);
  lua_pushvalue(L, a);
  lua_pushvalue(L, b);
  lua_call(L, 2, 1);
  const bool less = lua_toboolean(L, -1) != 0;
  lua_pop(L, 1);
  return less;
}

/// table.sort(t [, comp]): a merge sort, stable, with the elements read and written as table.sort does
/// (lua_geti, lua_seti: metamethods apply). Lua's own sort is not stable either, so a script that relied
/// on where equal elements went had no order to rely on; now they keep theirs.
int ordered_sort(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const lua_Integer n = luaL_len(L, 1);
  if (n < 2) return 0;
  luaL_argcheck(L, n < INT_MAX, 1, "array too big");
  if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_settop(L, 2);
  lua_createtable(L, static_cast<int>(n), 0);  // 3: the elements, merged runs of `width` at a time
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_geti(L, 1, i);
    lua_rawseti(L, 3, i);
  }
  lua_createtable(L, static_cast<int>(n), 0);  // 4: the next merge
  for (lua_Integer width = 1; width < n; width *= 2) {
    for (lua_Integer lo = 1; lo <= n; lo += 2 * width) {
      const lua_Integer mid = lo + width < n + 1 ? lo + width : n + 1,
                        hi = lo + 2 * width < n + 1 ? lo + 2 * width : n + 1;
      lua_Integer i = lo, j = mid, k = lo;
      while (i < mid && j < hi) {
        lua_rawgeti(L, 3, j);
        lua_rawgeti(L, 3, i);
        const int top = lua_gettop(L);
        if (sort_less(L, 2, top - 1, top)) {  // the right one strictly first: equal ones keep their order
          lua_pop(L, 1);
          lua_rawseti(L, 4, k++);
          ++j;
        } else {
          lua_rawseti(L, 4, k++);
          lua_pop(L, 1);
          ++i;
        }
      }
      for (; i < mid; ++i) {
        lua_rawgeti(L, 3, i);
        lua_rawseti(L, 4, k++);
      }
      for (; j < hi; ++j) {
        lua_rawgeti(L, 3, j);
        lua_rawseti(L, 4, k++);
      }
    }
    lua_rotate(L, 3, 1);  // the merged runs become the elements
  }
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

/// pairs(t): t's __pairs if it has one, as Lua's; otherwise its keys in key_before's order.
int ordered_pairs(lua_State* L) {
  if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {
    lua_pushvalue(L, 1);
    lua_call(L, 1, 3);
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
  lua_pushcfunction(L, ordered_sort);
  lua_pushvalue(L, 2);
  lua_pushcfunction(L, key_before);
  lua_call(L, 2, 0);
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
