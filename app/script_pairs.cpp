// pairs() in a fixed order: Lua seeds its string hashes anew in every process, so its own order of a table's
// keys, and whatever a script computes from it, changed from run to run with the same script and seed.
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

/// pairs(t): t's __pairs if it has one, as Lua's; otherwise its keys in key_before's order (upvalue 1: the
/// library's table.sort).
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
  lua_pushvalue(L, lua_upvalueindex(1));
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

void install_ordered_pairs(lua_State* L) {
  lua_getglobal(L, LUA_TABLIBNAME);
  lua_getfield(L, -1, "sort");
  lua_pushcclosure(L, ordered_pairs, 1);
  lua_setglobal(L, "pairs");
  lua_pop(L, 1);
}

}  // namespace cellform::app
