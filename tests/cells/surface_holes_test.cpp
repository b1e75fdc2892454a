// The small holes of the one-layer cell surface: which are closed, and that the fill lies flat in them.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cells/surface.h"
#include "tests/fixtures.h"

using namespace cellform::cells;

namespace {

double area(const Cells& c, const std::vector<std::array<Index, 3>>& tris) {
  double a = 0;
  for (const auto& t : tris)
    a += 0.5 * (c.position[t[1]] - c.position[t[0]]).cross(c.position[t[2]] - c.position[t[0]]).norm();
  return a;
}

/// Sides with one triangle, counted from the directed sides (each must run once).
std::size_t boundary_sides(const Surface& s) {
  std::map<std::pair<Index, Index>, int> directed;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  std::size_t boundary = 0;
  for (const auto& [side, count] : directed) {
    CHECK(count == 1);
    boundary += directed.count({side.second, side.first}) == 0;
  }
  return boundary;
}

/// Replaces the links of `c` by `pairs` (each one way: a's row holds b), `stride` a row.
void link_all(Cells& c, const std::vector<std::pair<Index, Index>>& pairs, std::size_t stride = 6) {
  c.link_stride = static_cast<int>(stride);
  c.links.assign(c.size() * stride, cellform::core::kNoIndex);
  std::vector<std::size_t> used(c.size(), 0);
  for (const auto& [a, b] : pairs) c.links[a * stride + used[a]++] = b;
}

/// A 9 x 9 hex sheet less the cells at (row, column) in `gone`, with lattice links.
Cells holed_sheet(const std::set<std::pair<int, int>>& gone) {
  const Cells full = cellform::testing::hex_sheet(9, 9);
  Cells c;
  for (int r = 0; r < 9; ++r)
    for (int q = 0; q < 9; ++q)
      if (!gone.count({r, q})) add_cell(c, full.position[static_cast<std::size_t>(r * 9 + q)]);
  cellform::testing::link_lattice(c);
  return c;
}

}  // namespace

TEST_CASE("holes of up to twelve cells around are closed flat, facing as the sheet; larger ones stay", "[surface]") {
  const Cells full = holed_sheet({});
  const Surface whole = triangulate(full);
  const double full_area = area(full, whole.triangles);
  REQUIRE(full_area == Approx(8 * 8 * 2 * std::sqrt(3.0) / 4));
  const std::size_t outline = boundary_sides(whole);
  // (cells taken out, fill triangles): one cell, two, three in a row, a triangle, a bent row, four in a
  // row (holes of 6, 8, 10, 9, 10 and 12 cells round: n - 2 triangles each); two cells two apart, whose
  // holes touch at the cell between them (a pinch: two holes of 6)
  const std::vector<std::pair<std::set<std::pair<int, int>>, std::size_t>> holes = {
      {{{4, 4}}, 4},
      {{{4, 4}, {4, 5}}, 6},
      {{{4, 3}, {4, 4}, {4, 5}}, 8},
      {{{4, 4}, {4, 5}, {5, 4}}, 7},
      {{{4, 3}, {4, 4}, {5, 4}}, 8},
      {{{4, 2}, {4, 3}, {4, 4}, {4, 5}}, 10},
      {{{4, 3}, {4, 5}}, 8},
  };
  for (const auto& [gone, fills] : holes) {
    CAPTURE(fills, gone.size());
    const Cells c = holed_sheet(gone);
    const Surface cliques = triangulate(c, false);
    REQUIRE(area(c, cliques.triangles) < full_area - 0.5);  // the cliques leave the hole open
    const Surface s = triangulate(c);
    CHECK(s.triangles.size() == cliques.triangles.size() + fills);
    for (const auto& t : s.triangles)
      CHECK((c.position[t[1]] - c.position[t[0]]).cross(c.position[t[2]] - c.position[t[0]]).z() > 0);
    // all facing up and adding up to the whole sheet: no fill triangle lies outside its hole or over another
    CHECK(area(c, s.triangles) == Approx(full_area));
    CHECK(boundary_sides(s) == outline);
  }
  // five in a row: fourteen cells round, left open
  const Cells c = holed_sheet({{4, 2}, {4, 3}, {4, 4}, {4, 5}, {4, 6}});
  const Surface s = triangulate(c);
  CHECK(area(c, s.triangles) == Approx(area(c, triangulate(c, false).triangles)));
  CHECK(boundary_sides(s) == outline + 14);
}

TEST_CASE("a hole another sheet passes through stays open", "[surface]") {
  // the one-cell hole of the sheet above, and a small upright triangle of three more cells through its middle
  Cells c = holed_sheet({{4, 4}});
  const Cells plain = c;
  const Vec3 middle = cellform::testing::hex_sheet(9, 9).position[4 * 9 + 4];
  const auto n = static_cast<Index>(c.size());
  for (const Vec3& d : {Vec3(0, 0, -0.3), Vec3(0.2, 0.05, 0.3), Vec3(-0.2, -0.05, 0.3)}) add_cell(c, middle + d);
  c.links.assign(c.size() * 6, cellform::core::kNoIndex);
  std::copy(plain.links.begin(), plain.links.end(), c.links.begin());
  for (Index k = 0; k < 3; ++k) {
    c.links[(n + k) * 6] = n + (k + 1) % 3;
    c.links[(n + k) * 6 + 1] = n + (k + 2) % 3;
  }
  REQUIRE(triangulate(plain).triangles.size() == triangulate(plain, false).triangles.size() + 4);  // filled
  const Surface s = triangulate(c);
  CHECK(s.triangles.size() == triangulate(c, false).triangles.size());  // not filled: the fill would cross it
  CHECK(area(c, s.triangles) ==
        Approx(area(plain, triangulate(plain, false).triangles) + area(c, {{n, n + 1, n + 2}})));
}

TEST_CASE("a concave hole is closed inside its outline; a chord over a hole is kept", "[surface]") {
  // A wide pentagon A B C D E with a deep notch C-D-E (D reflex), one triangle outside each side (X above the
  // notch). The shortest diagonals, C-E and A-C (or B-E), pass outside over the notch; the fill must be the
  // fan from D, the only one inside.
  Cells notch;
  enum : Index { A, B, C, D, E, O1, O2, O3, X };
  for (const Vec3& p : {Vec3(-3, 0, 0), Vec3(9, 0, 0), Vec3(4, 3, 0), Vec3(3, 0.4, 0), Vec3(2, 3, 0), Vec3(3, -4, 0),
                        Vec3(9, 3, 0), Vec3(-3, 3, 0), Vec3(3, 3.5, 0)})
    add_cell(notch, p);
  const std::vector<std::pair<Index, Index>> rim = {{A, B},  {B, C},  {C, D}, {D, E}, {E, A}, {A, O1}, {B, O1},
                                                    {B, O2}, {C, O2}, {C, X}, {D, X}, {E, X}, {E, O3}, {A, O3}};
  link_all(notch, rim);
  const Surface cliques = triangulate(notch, false);
  REQUIRE(cliques.triangles.size() == 5);
  const Surface s = triangulate(notch);
  REQUIRE(s.triangles.size() == 8);
  std::set<std::array<Index, 3>> fill;
  for (const auto& t : s.triangles) {
    CHECK((notch.position[t[1]] - notch.position[t[0]]).cross(notch.position[t[2]] - notch.position[t[0]]).z() > 0);
    if (std::find(cliques.triangles.begin(), cliques.triangles.end(), t) == cliques.triangles.end()) {
      std::array<Index, 3> sorted = t;
      std::sort(sorted.begin(), sorted.end());
      fill.insert(sorted);
    }
  }
  CHECK(fill == std::set<std::array<Index, 3>>{{A, B, D}, {B, C, D}, {A, D, E}});
  // the pentagon's area (shoelace) is what the fill adds
  CHECK(area(notch, s.triangles) - area(notch, cliques.triangles) ==
        Approx(0.5 * (9 * 3 + (4 * 0.4 - 3 * 3) + (3 * 3 - 2 * 0.4) + 3 * 3)));

  // A regular octagon of cells, one triangle outside each side, and a link from cell 0 to cell 4 over the
  // hole that no triangle has: the fill keeps it, three triangles on either side (the halves are pentagons,
  // which no quad closing reaches).
  Cells octagon;
  std::vector<std::pair<Index, Index>> links = {{0, 4}};
  for (int k = 0; k < 8; ++k) add_cell(octagon, 2 * Vec3(std::cos(k * M_PI / 4), std::sin(k * M_PI / 4), 0));
  for (int k = 0; k < 8; ++k) {
    add_cell(octagon, 3 * Vec3(std::cos((k + 0.5) * M_PI / 4), std::sin((k + 0.5) * M_PI / 4), 0));
    const auto o = static_cast<Index>(8 + k), a = static_cast<Index>(k), b = static_cast<Index>((k + 1) % 8);
    links.insert(links.end(), {{a, b}, {a, o}, {b, o}});
  }
  link_all(octagon, links);
  const Surface oc = triangulate(octagon, false);
  REQUIRE(oc.triangles.size() == 8);
  const Surface os = triangulate(octagon);
  REQUIRE(os.triangles.size() == 8 + 6);
  int on_chord = 0;
  for (const auto& t : os.triangles) {
    CHECK((octagon.position[t[1]] - octagon.position[t[0]]).cross(octagon.position[t[2]] - octagon.position[t[0]]).z() >
          0);
    on_chord += std::count(t.begin(), t.end(), 0) && std::count(t.begin(), t.end(), 4);
  }
  CHECK(on_chord == 2);
  CHECK(area(octagon, os.triangles) - area(octagon, oc.triangles) == Approx(8 * 2 * std::sin(M_PI / 4)));
}

TEST_CASE("a fill does not fold across its diagonal, nor cross a triangle at one of its corners", "[surface]") {
  // a quad p s q r bent into a V (s and r raised), one triangle outside each side in the plane of the fill
  // triangle next to it: either diagonal folds the fill by less than 90 degrees, so it stays open
  Cells vee;
  enum : Index { P, S, Q, R, O1, O2, O3, O4 };
  const Vec3 p(0, -1, 0), s(1.2, 0, 2), q(0, 1, 0), r(-1.2, 0, 2);
  for (const Vec3& x : {p, s, q, r, Vec3(p + s - q), Vec3(s + q - p), Vec3(q + r - p), Vec3(r + p - q)})
    add_cell(vee, x);
  link_all(vee,
           {{P, S}, {S, Q}, {Q, R}, {R, P}, {P, O1}, {S, O1}, {S, O2}, {Q, O2}, {Q, O3}, {R, O3}, {R, O4}, {P, O4}});
  REQUIRE(triangulate(vee, false).triangles.size() == 4);
  CHECK(triangulate(vee).triangles.size() == 4);
  // flattened (s and r lowered to the plane), the same hole is closed
  Cells flat = vee;
  for (const Index i : {S, R, O1, O2, O3, O4}) flat.position[i].z() = 0;
  CHECK(triangulate(flat).triangles.size() == 6);

  // a one-cell hole and an upright triangle from one of the six cells round it through the hole: each
  // triangulation of the hole has a triangle at that cell which the upright one cuts, so it stays open
  for (int which = 0; which < 6; ++which) {
    CAPTURE(which);
    Cells c = holed_sheet({{4, 4}});
    const Vec3 m = cellform::testing::hex_sheet(9, 9).position[4 * 9 + 4];
    std::vector<std::pair<double, Index>> by_distance;
    for (Index i = 0; i < c.size(); ++i) by_distance.push_back({(c.position[i] - m).norm(), i});
    std::sort(by_distance.begin(), by_distance.end());
    const Index v = by_distance[static_cast<std::size_t>(which)].second;
    const Vec3 inside = c.position[v] + 0.3 * (m - c.position[v]);
    const std::vector<Index> lattice = c.links;
    const Index a = add_cell(c, inside + Vec3(0, 0, 0.5)), b = add_cell(c, inside + Vec3(0, 0, -0.5));
    c.links.assign(c.size() * 6, cellform::core::kNoIndex);
    std::copy(lattice.begin(), lattice.end(), c.links.begin());
    c.links[v * 6 + 5] = a;  // a cell round the hole has five lattice links
    c.links[a * 6] = b;
    c.links[b * 6] = v;
    const Surface cliques = triangulate(c, false);
    REQUIRE(std::count(cliques.triangles.begin(), cliques.triangles.end(), std::array<Index, 3>{v, a, b}) +
                std::count(cliques.triangles.begin(), cliques.triangles.end(), std::array<Index, 3>{v, b, a}) ==
            1);
    CHECK(triangulate(c).triangles.size() == cliques.triangles.size());
  }
}

TEST_CASE("a long triangle through a hole keeps it open; a tube's open ends stay open", "[surface]") {
  // a triangle 40 cells across, upright, through the middle of a one-cell hole: no corner of it is near
  Cells c = holed_sheet({{4, 4}});
  const Vec3 m = cellform::testing::hex_sheet(9, 9).position[4 * 9 + 4];
  const std::vector<Index> lattice = c.links;
  const auto n = static_cast<Index>(c.size());
  for (const Vec3& d : {Vec3(-20, 0.1, -20), Vec3(20, 0.1, -20), Vec3(0, -0.1, 20)}) add_cell(c, m + d);
  c.links.assign(c.size() * 6, cellform::core::kNoIndex);
  std::copy(lattice.begin(), lattice.end(), c.links.begin());
  c.links[n * 6] = n + 1;
  c.links[n * 6 + 1] = n + 2;
  c.links[(n + 1) * 6] = n + 2;
  const Surface cliques = triangulate(c, false);
  CHECK(triangulate(c).triangles.size() == cliques.triangles.size());

  // a tube of 12 cells round and four rings (staggered), triangles between the rings: its ends are loops of
  // 12 boundary sides whose triangles face every way round, not holes in a sheet
  Cells tube;
  const double radius = 0.5 / std::sin(M_PI / 12);
  for (int ring = 0; ring < 4; ++ring)
    for (int j = 0; j < 12; ++j) {
      const double angle = (j + 0.5 * (ring % 2)) * M_PI / 6;
      add_cell(tube, Vec3(radius * std::cos(angle), radius * std::sin(angle), 0.9 * ring));
    }
  tube.link_stride = 6;
  tube.links.assign(tube.size() * 6, cellform::core::kNoIndex);
  std::vector<int> used(tube.size(), 0);
  auto link = [&](int a, int b) { tube.links[static_cast<std::size_t>(a * 6 + used[a]++)] = static_cast<Index>(b); };
  for (int ring = 0; ring < 4; ++ring)
    for (int j = 0; j < 12; ++j) {
      const int a = ring * 12 + j;
      link(a, ring * 12 + (j + 1) % 12);
      if (ring == 3) continue;
      // the next ring is turned half a step on (odd rings) or back (even rings)
      link(a, (ring + 1) * 12 + j);
      link(a, (ring + 1) * 12 + (ring % 2 ? (j + 1) % 12 : (j + 11) % 12));
    }
  const Surface t = triangulate(tube);
  CHECK(t.triangles.size() == 3 * 12 * 2);
  CHECK(t.triangles.size() == triangulate(tube, false).triangles.size());
}

TEST_CASE("a chord one hole's fill takes no longer blocks the hole on its other side", "[surface]") {
  // Two holes either side of an island of six triangles (a1 a2 m1 m2 b1 b2), inside an outline of eight
  // cells (each with a triangle outside it), and a link x-y with no triangle across the left hole. The left
  // hole's fill must keep x-y; once it has, the right hole's must not use it. Whichever hole comes first,
  // both close: only the outline stays open. Mirrored (x -> -x), the other hole comes first.
  struct Point {
    const char* name;
    double x, y;
  };
  const std::vector<Point> inner = {{"x", 0, 0},       {"y", 0, 2},       {"a1", 0.3, 0.6},  {"a2", 1.0, 0.5},
                                    {"m1", 0.5, 1.0},  {"m2", 1.1, 1.0},  {"b1", 0.3, 1.4},  {"b2", 1.0, 1.5},
                                    {"L1", -0.7, 1.7}, {"L2", -0.9, 1.0}, {"L3", -0.7, 0.3}, {"R3", 1.8, 0.3},
                                    {"R2", 2.0, 1.0},  {"R1", 1.8, 1.7}};
  std::map<std::string, Index> id;
  std::vector<Vec3> at;
  for (const Point& p : inner) {
    id[p.name] = static_cast<Index>(at.size());
    at.emplace_back(p.x, p.y, 0);
  }
  std::vector<std::pair<Index, Index>> links;
  for (const auto& [a, b] : std::vector<std::pair<const char*, const char*>>{{"x", "a1"},
                                                                             {"x", "a2"},
                                                                             {"a1", "a2"},
                                                                             {"a2", "m2"},
                                                                             {"a1", "m2"},
                                                                             {"a1", "m1"},
                                                                             {"m1", "m2"},
                                                                             {"m2", "b2"},
                                                                             {"m1", "b2"},
                                                                             {"m1", "b1"},
                                                                             {"b1", "b2"},
                                                                             {"b1", "y"},
                                                                             {"b2", "y"},
                                                                             {"x", "y"}})
    links.push_back({id[a], id[b]});
  const std::vector<std::string> outline = {"y", "L1", "L2", "L3", "x", "R3", "R2", "R1", "y"};
  for (std::size_t i = 0; i + 1 < outline.size(); ++i) {
    const Vec3 u = at[id[outline[i]]], v = at[id[outline[i + 1]]];
    const Vec3 side = Vec3(v.y() - u.y(), u.x() - v.x(), 0).normalized(), mid = (u + v) / 2;
    const Vec3 out = (mid + 0.6 * side - Vec3(0.55, 1, 0)).norm() > (mid - 0.6 * side - Vec3(0.55, 1, 0)).norm()
                         ? Vec3(mid + 0.6 * side)
                         : Vec3(mid - 0.6 * side);
    const auto o = static_cast<Index>(at.size());
    at.push_back(out);
    links.insert(links.end(), {{id[outline[i]], id[outline[i + 1]]}, {o, id[outline[i]]}, {o, id[outline[i + 1]]}});
  }
  for (const double mirror : {1.0, -1.0}) {
    CAPTURE(mirror);
    Cells c;
    for (const Vec3& p : at) add_cell(c, Vec3(mirror * p.x(), p.y(), 0));
    link_all(c, links, 8);
    const Surface cliques = triangulate(c, false), s = triangulate(c);
    REQUIRE(cliques.triangles.size() == 6 + 8);  // the island, the ring outside the outline
    CHECK(s.triangles.size() == 6 + 8 + 6 + 6);  // the left hole (8 sides, x-y across) and the right (8)
    CHECK(boundary_sides(s) == 2 * 8);           // the outer sides of the ring's triangles only
    int on_chord = 0;
    for (const auto& t : s.triangles)
      on_chord += std::count(t.begin(), t.end(), id["x"]) && std::count(t.begin(), t.end(), id["y"]);
    CHECK(on_chord == 2);  // one on either side of it, both from the left hole's fill
  }
}
