// Every example script runs on small settings, so examples cannot rot.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "tests/app/test_util.h"

using namespace cellform::test;
namespace fs = std::filesystem;

TEST_CASE("every example runs on small settings", "[examples]") {
  std::vector<fs::path> scripts;
  for (const auto& e : fs::directory_iterator(fs::path(CELLFORM_SOURCE_DIR) / "examples"))
    if (e.path().extension() == ".lua") scripts.push_back(e.path());
  std::sort(scripts.begin(), scripts.end());
  REQUIRE(scripts.size() >= 4);
  TempDir t("examples");
  for (const fs::path& s : scripts) {
    DYNAMIC_SECTION(s.filename().string()) {
      const fs::path out = t.path / s.stem();
      const auto r = cli(
          {"run", s.string(), "--out", out.string(), "--quiet", "--steps", "60", "--set", "division.max_cells=1500"});
      INFO(r.err);
      REQUIRE(r.code == 0);
      const auto run = nlohmann::json::parse(slurp(out / "run.json"));
      if (run.value("mode", "") == "colonisation") {  // space colonisation: veins in a leaf, volume or surface
        CHECK(run["steps"]["completed"].get<int>() <= 60);
        CHECK(run["veins"]["nodes"].get<int>() > 10);
        CHECK(fs::file_size(out / "veins.ply") > 0);
        if (run["domain"] == "leaf") {
          CHECK(fs::file_size(out / "veins.svg") > 0);
        } else {  // a 3-D structural example prints as one watertight piece
          REQUIRE(run.contains("print"));
          CHECK(run["print"]["parts"] == 1);
          const auto check = cli({"check", (out / "printable.stl").string(), "--json"});
          CHECK(nlohmann::json::parse(check.out)["printable"] == true);
        }
      } else {
        CHECK(run["steps"]["completed"] == 60);
        CHECK(run["cells"]["final"].get<int>() >= run["cells"]["initial"].get<int>());
        CHECK(fs::file_size(out / "cells.ply") > 0);
      }
    }
  }
}
