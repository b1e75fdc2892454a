// Tests of the progress bar and lines (app/progress.cpp).
#include "app/progress.h"

#include <algorithm>
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
  // what follows the steps is said (the coral's print took twice its steps, after "0s left", audit)
  std::ostringstream then;
  cellform::app::Progress printing(then, false, false, 0, 10, "the print");
  printing.update(10, 5);
  CHECK_THAT(then.str(), Contains(" left, then the print\n"));
  std::ostringstream quiet;
  cellform::app::Progress silent(quiet, true, true, 0, 10);
  silent.update(10, 1);
  CHECK(quiet.str().empty());
}

TEST_CASE("the time left of a growing form counts its cells, not only the steps", "[cli]") {
  // 20 steps of one cell, then 1,000 cells: the remaining 79 steps cost about 1,000 times a step so far
  std::ostringstream bar;
  cellform::app::Progress growing(bar, true, false, 0, 100);
  for (std::uint64_t step = 1; step <= 20; ++step) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    growing.update(step, 1);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(110));
  bar.str("");
  growing.update(21, 1000);
  const std::string line = bar.str();
  INFO(line);
  // at least 79 * 1000 * 0.31 s / 1020 cell-steps = 24 s (the step rate said 79 / (21 / 0.31 s) = 1 s)
  const std::size_t at = line.find("steps/s  ");
  REQUIRE(at != std::string::npos);
  const std::string left = line.substr(at + 9);
  const bool minutes = left.find('m') < left.find(' ');
  CHECK((minutes || std::stod(left) >= 20));
}

TEST_CASE("a line written beside the terminal bar starts on a line of its own, the bar drawn again below", "[cli]") {
  std::ostringstream err;
  cellform::app::Progress bar(err, true, false, 0, 10);
  bar.update(10, 5);  // the last step is always drawn
  REQUIRE(err.str().back() != '\n');
  bar.break_line();
  err << "script: at step 10\n";
  CHECK(err.str().find("left   \nscript: at step 10\n") != std::string::npos);
  bar.break_line();  // nothing drawn since: no empty line
  bar.finish();
  CHECK(err.str().substr(err.str().size() - 20) == "\nscript: at step 10\n");
  // not on a terminal the progress lines end themselves
  std::ostringstream log;
  cellform::app::Progress lines(log, false, false, 0, 10);
  lines.update(10, 5);
  lines.break_line();
  lines.finish();
  const std::string said = log.str();
  CHECK(said.rfind("step 10/10 (100%), 5 cells, ", 0) == 0);
  CHECK(std::count(said.begin(), said.end(), '\n') == 1);
}
