// Helpers of the script host tests: a script loaded by a fresh host, or the error it stops with.
#pragma once

#include <catch2/catch.hpp>
#include <string>

#include "app/script_host.h"
#include "core/errors.h"

namespace cellform::test {

/// The scene `src` describes, read by a fresh host as "test/leaf.lua" with overrides `o`.
inline app::SceneConfig load(const std::string& src, const app::Overrides& o = {}, app::ScriptLimits limits = {}) {
  app::ScriptHost host(limits);
  return host.load(src, "test/leaf.lua", o);
}

/// The message `src` is refused with; fails the test if it loads.
inline std::string load_error(const std::string& src, const app::Overrides& o = {}, app::ScriptLimits limits = {}) {
  try {
    load(src, o, limits);
  } catch (const core::InvalidInput& e) {
    return e.what();
  }
  FAIL("no error for: " << src);
  return {};
}

}  // namespace cellform::test
