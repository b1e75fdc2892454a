// Tests of leaf outlines: parametric shapes are simple and enclose the petiole, files parse or fail clearly.
#include "venation/leaf_shape.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/errors.h"
#include "core/random.h"

using namespace cellform;
using Catch::Matchers::Contains;
using venation::Outline;
using venation::ShapeKind;
namespace v = cellform::venation;
using venation::Vec2;

TEST_CASE("every parametric shape is a simple counter-clockwise outline with the petiole on it", "[leaf_shape]") {
  for (ShapeKind k : {ShapeKind::ellipse, ShapeKind::ovate, ShapeKind::cordate, ShapeKind::lobed, ShapeKind::palmate}) {
    venation::ShapeParams sp;
    sp.kind = k;
    sp.length = 10;
    sp.width = 6;
    const Outline o = venation::make_outline(sp);
    INFO("kind " << static_cast<int>(k));
    REQUIRE_NOTHROW(venation::validate_outline(o, "test"));
    CHECK(venation::signed_area(o) > 0);
    CHECK(venation::distance_to_boundary(o, Vec2(0, 0)) < 1e-9);
    double xmin = 1e9, xmax = -1e9, ymax = -1e9;
    for (const Vec2& p : o.points) {
      xmin = std::min(xmin, p.x());
      xmax = std::max(xmax, p.x());
      ymax = std::max(ymax, p.y());
    }
    CHECK(xmax - xmin == Approx(6).epsilon(1e-9));
    CHECK(ymax == Approx(10).epsilon(0.02));
  }
  venation::ShapeParams e;
  e.length = 2;
  e.width = 1;
  e.samples = 4096;
  CHECK(venation::signed_area(venation::make_outline(e)) == Approx(M_PI * 0.5 * 1).epsilon(1e-4));  // pi a b
}

TEST_CASE("toothed margins: summed triangular waves stay simple, a too deep tooth is rejected", "[leaf_shape]") {
  venation::ShapeParams sp;
  sp.length = 10;
  sp.width = 6;
  sp.teeth = {{0.3, 24}, {0.1, 96}};
  const Outline o = venation::make_outline(sp);
  CHECK(o.points.size() >= 16 * 96);
  venation::ShapeParams bad = sp;
  bad.kind = ShapeKind::palmate;
  bad.lobe_depth = 0.9;
  bad.teeth = {{3.0, 200}};
  CHECK_THROWS_WITH(venation::make_outline(bad), Contains("shape.teeth"));
  // teeth fade into the notch of a cordate or palmate base instead of crossing there
  for (const ShapeKind kind : {ShapeKind::palmate, ShapeKind::cordate}) {
    venation::ShapeParams notched;
    notched.kind = kind;
    notched.width = 1;
    notched.teeth = {{0.03, 30}};
    const Outline toothed = venation::make_outline(notched);  // throws if the margin crossed itself
    for (const Vec2& q : toothed.points) {
      if (q.norm() >= 0.01) continue;  // within a twelfth of the shortest fade length of the petiole
      notched.teeth.clear();
      const Outline smooth = venation::make_outline(notched);
      double nearest = 1e9;
      for (const Vec2& r : smooth.points) nearest = std::min(nearest, (r - q).norm());
      CHECK(nearest < 0.03 * 0.1 + 0.01);  // barely moved: at most a third of an amplitude plus sampling
      notched.teeth = {{0.03, 30}};
    }
  }
  bad = sp;
  bad.width = -1;
  CHECK_THROWS_WITH(venation::make_outline(bad), Contains("shape.width"));
}

TEST_CASE("outline files: closed polygons parse, open, malformed and self-intersecting ones fail", "[leaf_shape]") {
  const Outline sq = venation::parse_outline("# a square, clockwise\n0 0\n0 1\n1 1\n1 0\n0 0\n", "sq.txt");
  // a byte-order mark from an editor changes nothing
  CHECK(venation::parse_outline("\xEF\xBB\xBF# a square, clockwise\n0 0\n0 1\n1 1\n1 0\n0 0\n", "bom.txt").points ==
        sq.points);
  CHECK(venation::parse_outline("\xEF\xBB\xBF"
                                "0 0\n0 1\n1 1\n1 0\n0 0\n",
                                "bom.txt")
            .points.size() == sq.points.size());
  CHECK(sq.points.size() == 4);
  CHECK(venation::signed_area(sq) == Approx(1));  // reoriented
  CHECK_THROWS_AS(venation::parse_outline("0 0\n1 0\n1 1\n0 1\n", "open.txt"), core::InvalidInput);
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n1 0\n1 1\n0 1\n", "open.txt"),
                    Contains("open.txt") && Contains("open"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n1 zero\n1 1\n0 0\n", "bad.txt"), Contains("bad.txt:2"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n1 0 3\n1 1\n0 0\n", "bad.txt"), Contains("bad.txt:2"));
  // what is wrong with a line is said as it is: a word, not "got one"
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0.3 abc\n1 1\n0 0\n", "w.txt"),
                    Contains("w.txt:2") && Contains("'abc' as y") && !Contains("got one"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0 nan\n1 1\n0 0\n", "n.txt"),
                    Contains("n.txt:2") && Contains("finite") && Contains("'nan'"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n-inf 1\n1 1\n0 0\n", "i.txt"), Contains("finite"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0 1e400\n1 1\n0 0\n", "r.txt"),
                    Contains("r.txt:2") && Contains("'1e400'") && Contains("beyond the range"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0.3\n1 1\n0 0\n", "o.txt"), Contains("got one ('0.3')"));
  CHECK(venation::parse_outline("0 1e-400\n+0 1\n1 1\n1 0\n0 0\n", "tiny.txt").points == sq.points);  // 1e-400 is 0
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n+-1 1\n1 1\n0 0\n", "pm.txt"),
                    Contains("pm.txt:2") && Contains("'+-1'"));
  // "x,y" as a spreadsheet writes it is read; decimal commas are explained
  CHECK(venation::parse_outline("0,0\n0,1\n1,1\n1, 0\n0,0\n", "csv.txt").points == sq.points);
  CHECK_THROWS_WITH(venation::parse_outline("0,5 0,5\n0 1\n1 1\n0,5 0,5\n", "dec.txt"),
                    Contains("dec.txt:1") && Contains("decimals take a point"));
  // closed up to an export's rounding; a real gap is said with its size
  CHECK(venation::parse_outline("0 0\n0 1\n1 1\n1 0\n0 1e-9\n", "near.txt").points == sq.points);
  // a hole after the blade is a second contour, said as such (it was "open", naming the hole's last line)
  CHECK_THROWS_WITH(
      venation::parse_outline("0 0\n0 4\n4 4\n4 0\n0 0\n\n1 1\n1 2\n2 2\n2 1\n1 1\n", "hole.txt"),
      Contains("hole.txt:7: the outline closed at line 5 (its vertex repeats the first), and 5 more lines"));
  CHECK(venation::parse_outline("0 0\n0 1\n1 1\n1 0\n0 0\n0 0\n", "twice.txt").points == sq.points);
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0 1\n1 1\n1 0\n0 0.01\n", "gap.txt"),
                    Contains("gap.txt:5") && Contains("open") && Contains("0.01 apart"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0 1\n1 1\n1 0\n0.03 0.04\n", "gap2.txt"),
                    Contains("0.05 apart"));  // the distance, not the larger of the axes' gaps (0.04; audit)
  // a binary file is named as such, its bytes are not echoed to the terminal
  CHECK_THROWS_WITH(venation::parse_outline(std::string("\x7f"
                                                        "ELF\x02\x01\x01\n",
                                                        8),
                                            "a.out"),
                    Contains("a.out:1") && Contains("not text") && !Contains("ELF"));
  CHECK_THROWS_WITH(venation::parse_outline(std::string(300, 'z'), "long.txt"), Contains("...'"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n1 1\n1 0\n0 1\n0 0\n", "bow.txt"),
                    Contains("crosses itself at (0.5, 0.5)"));
  // the edges are named by the file's lines, past comments and a repeated vertex, and the coordinates as
  // the file has them, not as scaled to be read (1e300 is brought near 1)
  CHECK_THROWS_WITH(
      venation::parse_outline(
          "# a bow tie\n1e300 1e300\n3e300 3e300\n3e300 3e300\n3e300 1e300\n1e300 3e300\n1e300 1e300\n", "bow.txt"),
      Contains("crosses itself at (2e+300, 2e+300) (the edges from lines 2 and 5)"));
  // the point named is where the edges cross, not a vertex of them (a user's bow, found in a review)
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n20 10\n20 30\n-20 50\n-20 60\n20 60\n-20 10\n0 0\n", "bow2.txt"),
                    Contains("crosses itself at (2.85714, 38.5714) (the edges from lines 3 and 6)"));
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n1 0\n2 0\n0 0\n", "line.txt"),
                    Contains("no area") || Contains("folds back"));
  CHECK_THROWS_AS(venation::read_outline("/nonexistent/outline.txt"), core::FileError);
  // a vertex repeated on the next line, or the closing vertex written twice, is one vertex
  CHECK(venation::parse_outline("0 0\n0 1\n0 1\n1 1\n1 0\n0 0\n", "dup.txt").points == sq.points);
  CHECK(venation::parse_outline("0 0\n0 1\n1 1\n1 0\n0 0\n0 0\n", "twice.txt").points == sq.points);
  CHECK_THROWS_WITH(venation::parse_outline("0 0\n0 0\n1 1\n1 1\n0 0\n", "two.txt"), Contains("at least 3 vertices"));
  // any unit: a square of side 1e300 or 1e-300 is a square, brought near 1 by a power of two
  for (const double side : {1e300, 1e-300, 1e-310}) {
    INFO(side);
    std::string text;
    for (const auto& [x, y] : {std::pair{0, 0}, {0, 1}, {1, 1}, {1, 0}, {0, 0}})
      text += core::number_text(x * side) + " " + core::number_text(y * side) + "\n";
    const Outline big = venation::parse_outline(text, "unit.txt");
    REQUIRE(big.points.size() == 4);
    double s = 0;  // the square's side after scaling
    for (const auto& p : big.points) s = std::max(s, p.maxCoeff());
    CHECK(s > 0.5);
    CHECK(s <= 1);
    CHECK(venation::signed_area(big) == Approx(s * s));
  }
  CHECK(venation::parse_outline("0 0\n0 1e300\n1e300 1e300\n1e300 0\n0 0\n", "big.txt").points[1].y() ==
        std::ldexp(1e300, -997));  // an exact power of two: 2^997 <= 1e300 < 2^998
}

TEST_CASE("OutlineIndex agrees with a plain crossing test", "[leaf_shape]") {
  venation::ShapeParams sp;
  sp.kind = ShapeKind::ovate;
  sp.teeth = {{0.02, 40}};
  const Outline o = venation::make_outline(sp);
  const venation::OutlineIndex idx(o);
  int inside = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec2 q(-0.6 + 1.2 * (i % 63) / 62.0, -0.3 + 1.4 * (i / 63) / 63.0);
    bool c = false;
    for (std::size_t a = 0, b = o.points.size() - 1; a < o.points.size(); b = a++)
      if ((o.points[a].y() > q.y()) != (o.points[b].y() > q.y()) &&
          q.x() < o.points[a].x() + (q.y() - o.points[a].y()) * (o.points[b].x() - o.points[a].x()) /
                                        (o.points[b].y() - o.points[a].y()))
        c = !c;
    CHECK(idx.contains(q) == c);
    inside += c;
  }
  CHECK(inside > 100);
}

TEST_CASE("OutlineIndex::segment_inside: the far end inside and no edge crossed, as a scan of every edge says",
          "[leaf_shape]") {
  // toothed and lobed blades, where short segments cut across sinuses with both ends inside
  for (const ShapeKind kind : {ShapeKind::ovate, ShapeKind::lobed}) {
    venation::ShapeParams sp;
    sp.kind = kind;
    sp.teeth = {{0.05, 200}};
    if (kind == ShapeKind::lobed) {
      sp.teeth.clear();
      sp.lobes = 4;
      sp.lobe_depth = 0.9;
    }
    const Outline o = venation::make_outline(sp);
    const venation::OutlineIndex idx(o), plain(o, false);
    core::Rng rng(11);
    int across = 0, within = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec2 a(rng.uniform(idx.lo().x(), idx.hi().x()), rng.uniform(idx.lo().y(), idx.hi().y()));
      if (!idx.contains(a)) continue;
      const double angle = rng.uniform(0, 2 * M_PI), length = rng.uniform(0, 0.05);
      const Vec2 b = a + length * Vec2(std::cos(angle), std::sin(angle));
      bool crossed = false;  // every edge, each end of the segment strictly on either side
      for (std::size_t k = 0, j = o.points.size() - 1; k < o.points.size(); j = k++) {
        const Vec2 &c = o.points[j], &d = o.points[k];
        auto side = [](const Vec2& u, const Vec2& v, const Vec2& w) {
          const double x = (v - u).x() * (w - u).y() - (v - u).y() * (w - u).x();
          return (x > 0) - (x < 0);
        };
        crossed = crossed || (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0);
      }
      const bool expect = idx.contains(b) && !crossed;
      CHECK(idx.segment_inside(a, b) == expect);
      CHECK(plain.segment_inside(a, b) == expect);  // without the grid: the bands alone
      if (expect) {                                 // and then every point of it is inside, sampled
        bool all = true;
        for (int t = 1; t < 50; ++t) all = all && idx.contains(a + (b - a) * (t / 50.0));
        CHECK(all);
      }
      across += idx.contains(b) && crossed;
      within += expect;
    }
    // a start on the outline, or a hair outside it (as validate(Leaf) lets a seed be), may go in; one farther not
    const double diagonal = (idx.hi() - idx.lo()).norm();
    const Vec2 base(0, 0), inward(0, 0.05);  // the petiole, at the bottom of the blade
    CHECK(idx.segment_inside(base, base + inward));
    CHECK(idx.segment_inside(base + Vec2(5e-7, -5e-7) * diagonal, base + inward));
    CHECK_FALSE(idx.segment_inside(base + Vec2(1e-4, -1e-4) * diagonal, base + inward));  // (beside the vertex)
    INFO("segments with both ends inside that cross the outline: " << across << ", inside: " << within);
    CHECK(across > 20);
    CHECK(within > 2000);
  }
}

TEST_CASE("a point on a vertical edge of the outline is inside on the left edge, outside on the right",
          "[leaf_shape]") {
  // the crossing rule is half-open, so a point on an edge two blades share belongs to exactly one of them
  const Outline left{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}, right{{{1, 0}, {2, 0}, {2, 1}, {1, 1}}};
  for (bool grid : {false, true}) {
    const venation::OutlineIndex a(left, grid), b(right, grid);
    for (double y : {0.25, 0.5, 0.75}) {
      INFO("grid " << grid << ", y " << y);
      CHECK(a.contains(Vec2(0, y)));
      CHECK_FALSE(a.contains(Vec2(1, y)));
      CHECK(b.contains(Vec2(1, y)));  // the shared edge: in the right-hand blade only
      CHECK(a.crossing_test(Vec2(0, y)) == a.contains(Vec2(0, y)));
    }
  }
}

TEST_CASE("OutlineIndex's grid gives the crossing test's answer everywhere, at the margin too", "[leaf_shape]") {
  // the grid answers from a cell's class, the crossing test from the edges: they must agree bit for bit,
  // on random points, on points a hair from every vertex and edge, and on outlines of any size and place
  std::vector<std::pair<std::string, Outline>> outlines;
  for (const ShapeKind kind : {ShapeKind::ovate, ShapeKind::lobed, ShapeKind::ellipse}) {
    venation::ShapeParams sp;
    sp.kind = kind;
    sp.teeth = {{0.02, 40}};
    outlines.emplace_back("shape " + std::to_string(static_cast<int>(kind)), venation::make_outline(sp));
  }
  // a tilted square of four long edges, a thin sliver, and the ovate moved far off and shrunk or grown
  outlines.emplace_back("square", Outline{{{0, -1}, {1, 0}, {0, 1}, {-1, 0}}});
  outlines.emplace_back("sliver", Outline{{{0, 0}, {10, 0.001}, {10, 0.003}, {0, 0.001}}});
  for (const double scale : {1e-6, 1e6})
    for (const double off : {0.0, 1e3}) {
      Outline o = outlines[0].second;
      for (Vec2& q : o.points) q = Vec2(off, -off) + scale * q;
      outlines.emplace_back("ovate x " + std::to_string(scale) + " at " + std::to_string(off), o);
    }
  std::uint64_t state = 12345;
  auto uniform = [&] {  // splitmix64
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1p-53;
  };
  for (const auto& [name, o] : outlines) {
    INFO(name);
    const venation::OutlineIndex idx(o);
    // every outline has its grid but the tiny one far from the origin (cells finer than its coordinates' rounding)
    CHECK(idx.has_grid() == (name != "ovate x 0.000001 at 1000.000000"));
    CHECK_FALSE(venation::OutlineIndex(o, false).has_grid());
    const Vec2 lo = idx.lo(), hi = idx.hi(), size = hi - lo;
    std::vector<Vec2> qs;
    for (int i = 0; i < 20000; ++i)
      qs.emplace_back(lo.x() - 0.05 * size.x() + 1.1 * size.x() * uniform(),
                      lo.y() - 0.05 * size.y() + 1.1 * size.y() * uniform());
    const double hair = 1e-12 * size.norm();
    for (std::size_t i = 0; i < o.points.size(); ++i) {
      const Vec2 a = o.points[i], c = o.points[(i + 1) % o.points.size()];
      for (const double t : {0.0, 0.5, uniform()})
        for (const Vec2& d : {Vec2(0, 0), Vec2(hair, 0), Vec2(-hair, 0), Vec2(0, hair), Vec2(0, -hair)})
          qs.push_back(a + t * (c - a) + d);
    }
    int inside = 0, differ = 0;
    for (const Vec2& q : qs) {
      const bool in = idx.contains(q);
      differ += in != idx.crossing_test(q);
      inside += in;
    }
    CHECK(differ == 0);
    CHECK(inside > 1000);
    CHECK(inside < static_cast<int>(qs.size()) - 1000);
  }
}

TEST_CASE("teeth follow a lobed margin into its sinuses without crossing", "[leaf_shape]") {
  using Catch::Matchers::Contains;
  // the defaults of leaf{shape = "lobed"}: width 0.6, five lobes 0.35 deep, teeth 0.02 deep (leaf lengths)
  venation::ShapeParams lobed;
  lobed.kind = ShapeKind::lobed;
  lobed.length = 1;
  lobed.width = 0.6;
  lobed.lobes = 5;
  lobed.lobe_depth = 0.35;
  const Outline smooth = venation::make_outline(lobed);
  for (const int count : {1, 2, 5, 20, 60, 200, 300, 1000}) {
    INFO(count << " teeth");
    lobed.teeth = {{0.02, count}};
    const Outline toothed = venation::make_outline(lobed);  // validated inside: simple, counter-clockwise
    CHECK(venation::signed_area(toothed) > 0);
    // the teeth only add: the toothed blade covers the smooth one (outward offsets, cut loops)
    CHECK(venation::signed_area(toothed) >= venation::signed_area(smooth) * (1 - 1e-9));
    // and stay within a tooth's depth of the smooth margin
    for (const Vec2& q : toothed.points) CHECK(venation::distance_to_boundary(smooth, q) <= 0.02 * (1 + 1e-9));
  }
  // teeth as deep as the leaf is long are refused naming what to change, with a place
  lobed.teeth = {{1.0, 3}};
  CHECK_THROWS_WITH(venation::make_outline(lobed), Contains("shape.teeth: teeth 1 deep cross each other") &&
                                                       Contains("(the margin crosses itself at (") &&
                                                       Contains("shallower or fewer"));
}

TEST_CASE("outline files whose vertex touches a vertical edge, or that fold back, are refused", "[leaf_shape]") {
  // a spike from the left whose tip (1, 1) lies on the vertical edge x = 1: the x ranges meet in one value
  CHECK_THROWS_WITH(v::parse_outline("1 -1\n1 3\n-3 3\n-3 2\n1 1\n-3 0\n-3 -1\n1 -1\n", "spike.txt"),
                    Contains("crosses itself"));
  CHECK_THROWS_WITH(v::parse_outline("0 0\n4 0\n2 0\n2 2\n0 0\n", "fold.txt"), Contains("folds back"));
  CHECK_THROWS_WITH(v::parse_outline("0 0\n1 0\n2 1e-13\n0 0\n", "sliver.txt"), Contains("encloses no area"));
  // the area is measured against the outline's own size: a unit triangle far from the origin has one (review:
  // 1e-12 of the largest coordinate squared refused it at 1e6), a sliver there has none
  v::Outline far;
  far.points = {{1e6, 1e6}, {1e6 + 1, 1e6}, {1e6, 1e6 + 1}};
  CHECK_NOTHROW(v::validate_outline(far, "far"));
  far.points = {{1e6, 1e6}, {1.1e6, 1e6}, {1.2e6, 1e6 + 1e-7}};  // 2e5 long, 1e-7 off its line
  CHECK_THROWS_WITH(v::validate_outline(far, "far"), Contains("encloses no area"));
  // and its winding: a thin clockwise outline at 1e7 comes back counter-clockwise with its own area (about the
  // origin the products cancelled, and the sign came out wrong in about two of five such outlines)
  for (const double dy : {0.02, 0.03, 0.05, 0.07}) {
    const std::string y = std::to_string(1e7 + dy);
    const v::Outline thin = v::parse_outline(
        "10000000 10000000\n10000000 " + y + "\n10000001 " + y + "\n10000001 10000000\n10000000 10000000\n",
        "thin.txt");
    CHECK(v::signed_area(thin) == Approx(dy).epsilon(1e-6));
  }
}
