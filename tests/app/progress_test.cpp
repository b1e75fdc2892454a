// Tests of the progress bar and lines (app/progress.cpp).
#include "app/progress.h"

#include <catch2/catch.hpp>
#include <sstream>
#include <thread>

using Catch::Matchers::Contains;

TEST_CASE("progress is of the whole run, also when a resume starts part of the way", "[cli]") {
  std::ostringstream lines;
  cellform::app::Progress resumed(lines, false, false, 2148, 4000);
  resumed.update(4000, 10);  // the last step is always said
  CHECK_THAT(lines.str(), Contains("step 4000/4000 (100%)"));
  std::ostringstream bar;
  cellform::app::Progress on_terminal(bar, true, false, 2148, 4000);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  on_terminal.update(3052, 10);  // 76% of the run (it once drew 49%, the part since the resume)
  CHECK_THAT(bar.str(), Contains("[" + std::string(22, '#') + std::string(8, '.') + "] step 3052/4000"));
  std::ostringstream quiet;
  cellform::app::Progress silent(quiet, true, true, 0, 10);
  silent.update(10, 1);
  CHECK(quiet.str().empty());
}
