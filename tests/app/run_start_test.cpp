// Tests of what resume --script says about an edited script's placed things (app/run_start.cpp).
#include <catch2/catch.hpp>

#include "app/run_internal.h"

using namespace cellform;
using Catch::Matchers::Contains;

namespace {
forms::PetioleSpec petiole(double x, int line) {
  return {core::Vec3(x, 0, 0), true, 0, "e.lua:" + std::to_string(line) + ": "};
}
}  // namespace

TEST_CASE("resume --script names the petioles it changes, not those it only reorders", "[cli][checkpoint]") {
  app::Start s;
  s.resume = true;
  s.step = 10;
  app::SceneConfig before, now;
  before.scene.petioles = {petiole(0, 3), petiole(5, 4)};
  now.scene.petioles = {petiole(5, 3), petiole(0, 4)};  // the same two, lines swapped
  CHECK(app::unplaced_changes(s, before, now).empty());
  now.scene.petioles = {petiole(0, 3), petiole(6, 4)};  // the second moved
  CHECK_THAT(app::unplaced_changes(s, before, now),
             Contains("petioles due by step 10 (e.lua:4; 1 of the run's no longer there (moved or removed))") &&
                 !Contains("e.lua:3"));
  now.scene.petioles = {petiole(0, 3), petiole(5, 4), petiole(9, 7)};  // one added
  CHECK_THAT(app::unplaced_changes(s, before, now), Contains("(e.lua:7)"));
  now.scene.petioles = {petiole(0, 3), petiole(5, 4), {core::Vec3(9, 0, 0), true, 20, "e.lua:8: "}};
  CHECK(app::unplaced_changes(s, before, now).empty());  // due after the checkpoint: placed as the run goes on
}
