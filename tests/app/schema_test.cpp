// Tests of app/schema.cpp: the parameter reference in docs/scripting.md is the program's own.
#include "app/schema.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

using Catch::Matchers::Contains;

TEST_CASE("docs/scripting.md documents every parameter as the program knows it", "[script][docs]") {
  std::ifstream in(std::string(CELLFORM_SOURCE_DIR) + "/docs/scripting.md");
  std::stringstream s;
  s << in.rdbuf();
  // the reference tables are `cellform params` output pasted verbatim; regenerate them when this fails
  CHECK_THAT(s.str(), Contains(cellform::app::schema_markdown()));
  // every row has the header's five cells (a "|" inside a cell, as in "one of a|b", is escaped)
  std::istringstream rows(cellform::app::schema_markdown());
  std::size_t checked = 0;
  for (std::string row; std::getline(rows, row);) {
    if (row.rfind("| `", 0) != 0) continue;
    std::size_t bars = 0;
    for (std::size_t k = 0; k < row.size(); ++k) bars += row[k] == '|' && (k == 0 || row[k - 1] != '\\');
    CHECK(bars == 6);
    ++checked;
  }
  CHECK(checked > 50);
}

TEST_CASE("allowed values are said as the checks take them", "[script][docs]") {
  using cellform::app::allowed_text;
  using cellform::app::find_field;
  CHECK(allowed_text(*find_field("output", "svg_size")) == "0, or a number from 1 to 100000");
  CHECK(allowed_text(*find_field("cells", "link_range")) == "0, or a number from 1 to 1e+06");
  CHECK(allowed_text(*find_field("output", "png_size")) == "a whole number from 16 to 20000");
  CHECK(allowed_text(*find_field("print", "scale")) == "a number from 0 to 1e+09");
}
