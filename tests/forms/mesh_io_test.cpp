// Tests of forms/mesh_io.h: the strict ASCII STL parser reads what real files hold and nothing else.
#include "forms/mesh_io.h"

#include <catch2/catch.hpp>
#include <string>

#include "core/errors.h"

using namespace cellform;
using core::Vec3;

namespace {

std::string facet(const std::string& a, const std::string& b, const std::string& c) {
  return "facet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c + "\nendloop\nendfacet\n";
}

}  // namespace

TEST_CASE("parse_ascii_stl reads facets in file order, in the spellings real files use", "[forms][mesh_io]") {
  // CRLF line ends, upper-case keywords, indentation, blank lines, signs and exponents, a nameless solid,
  // two solids one after the other, and a NaN normal (some writers emit one for degenerate facets)
  const std::string text =
      "solid part one\r\n  FACET NORMAL -nan 0 1\r\n    OUTER LOOP\r\n      VERTEX +1.5e+00 -2 0\r\n"
      "      VERTEX 0 0 0\r\n\r\n      VERTEX 1e-3 .5 7\r\n    ENDLOOP\r\n  ENDFACET\r\nENDSOLID part one\r\n"
      "solid\n" +
      facet("0 0 1", "1 0 1", "0 1 1") + "endsolid\n\n";
  const std::vector<Vec3> corners = forms::parse_ascii_stl(text);
  REQUIRE(corners.size() == 6);
  CHECK(corners[0] == Vec3(1.5, -2, 0));
  CHECK(corners[2] == Vec3(1e-3, 0.5, 7));
  CHECK(corners[5] == Vec3(0, 1, 1));
  CHECK(forms::parse_ascii_stl("solid empty\nendsolid empty").empty());
}

TEST_CASE("parse_ascii_stl refuses anything else, saying the line", "[forms][mesh_io]") {
  using Catch::Contains;
  const std::string f = facet("0 0 0", "1 0 0", "0 1 0");
  auto error = [](const std::string& text) {
    try {
      forms::parse_ascii_stl(text);
    } catch (const core::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK_THAT(error(""), Contains("starts with 'solid'"));
  CHECK_THAT(error("solid\n" + f + "endsolid\nfacet normal 0 0 1\n"),
             Contains("line 10") && Contains("after 'endsolid'"));
  CHECK_THAT(error("solid\nfacet normal 0 0\n"), Contains("line 2") && Contains("'facet normal' and three numbers"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nvertex 0 0 0\n"), Contains("line 3") && Contains("'outer loop'"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0 0\n"),
             Contains("line 4") && Contains("three numbers"));
  CHECK_THAT(error("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 inf\n"), Contains("line 4") && Contains("NaN"));
  CHECK_THAT(error("solid\n" + f.substr(0, f.find("endfacet")) + "endsolid\n"),
             Contains("line 8") && Contains("'endfacet'"));
  CHECK_THAT(error("solid\n" + f + "vertex 0 0 0\nendsolid\n"), Contains("line 9") && Contains("'facet normal"));
  CHECK_THAT(error("solid\n" + f), Contains("line 8") && Contains("without 'endsolid'"));
  CHECK_THAT(error("solid\n" + f.substr(0, f.find("endloop"))), Contains("line 6") && Contains("inside the facet"));
}
