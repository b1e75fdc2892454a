// PNG previews of vein trees: the file decodes, has the requested size and the colours where they belong.
#include "export/vein_png.h"

#include <catch2/catch.hpp>

#include "core/errors.h"
#include "tests/app/test_util.h"

using namespace cellform;
namespace fs = std::filesystem;

namespace {

/// A square leaf 100 x 100 with one straight vein up its middle (radius 2) and a thin side vein.
venation::VeinTree straight_vein() {
  venation::VeinTree t;
  t.positions = {core::Vec3(50, 10, 0), core::Vec3(50, 50, 0), core::Vec3(50, 90, 0), core::Vec3(80, 50, 0)};
  t.parent = {core::kNoIndex, 0, 1, 1};
  t.birth_step = {0, 1, 2, 2};
  t.radius = {2, 2, 2, 0.2};
  return t;
}

venation::Outline square() { return {{{0, 0}, {100, 0}, {100, 100}, {0, 100}}}; }

std::uint32_t rgb(std::uint32_t argb) { return argb & 0xffffff; }

}  // namespace

TEST_CASE("write_vein_png draws veins and outline into an image of the requested size", "[png]") {
  test::TempDir t("png");
  const fs::path file = t.path / "veins.png";
  exporters::PngParams p;
  p.size = 220;
  p.margin = 10;
  const auto tree = straight_vein();
  exporters::write_vein_png(file, tree, square(), p);
  const exporters::Image img = exporters::read_png(file);
  CHECK(img.width == 220);  // a square drawing: both sides are `size`
  CHECK(img.height == 220);
  const exporters::PngFrame f = exporters::png_frame(tree, square(), p);
  CHECK(f.scale == Approx(2.0));  // (220 - 2 * 10) pixels over 100 units
  auto pixel = [&](double x, double y) { return rgb(img.at(static_cast<int>(f.px(x)), static_cast<int>(f.py(y)))); };
  CHECK(rgb(img.at(2, 2)) == p.background);  // the margin around the leaf
  CHECK(rgb(img.at(217, 110)) == p.background);
  CHECK(pixel(20, 20) == p.blade);  // inside the leaf, away from veins
  CHECK(pixel(80, 80) == p.blade);
  for (double y : {15.0, 30.0, 50.0, 70.0, 85.0}) CHECK(pixel(50, y) == p.vein);  // on the main vein, 8 px wide
  CHECK(pixel(53, 30) == p.blade);  // 6 px beside its axis: outside the stroke (half width 4 px)
  CHECK(pixel(50, 96) == p.blade);  // beyond the vein tip and its round cap
  // y points up: the side vein at y = 50 runs to the right, in the middle row of the image
  CHECK(rgb(img.at(static_cast<int>(f.px(70)), 110)) != p.blade);
}

TEST_CASE("write_vein_png fits wide drawings to the longer side and refuses bad sizes", "[png]") {
  test::TempDir t("png-wide");
  venation::Outline wide{{{0, 0}, {200, 0}, {200, 50}, {0, 50}}};
  venation::VeinTree tree;
  tree.positions = {core::Vec3(10, 25, 0), core::Vec3(190, 25, 0)};
  tree.parent = {core::kNoIndex, 0};
  tree.birth_step = {0, 1};
  exporters::PngParams p;
  p.size = 410;
  p.margin = 5;
  exporters::write_vein_png(t.path / "w.png", tree, wide, p);
  const auto img = exporters::read_png(t.path / "w.png");
  CHECK(img.width == 410);
  CHECK(img.height == 110);  // 50 units at 2 px per unit + 2 x 5 margin
  // no widths computed: veins are drawn min_stroke wide, still on the segment
  CHECK(rgb(img.at(205, 55)) != p.blade);
  p.size = 8;
  CHECK_THROWS_AS(exporters::write_vein_png(t.path / "x.png", tree, wide, p), core::InvalidInput);
  CHECK_FALSE(fs::exists(t.path / "x.png"));
  CHECK_THROWS_AS(exporters::read_png(t.path / "missing.png"), core::FileError);
  t.write("not.png", "plain text");
  CHECK_THROWS_AS(exporters::read_png(t.path / "not.png"), core::FileError);
}

TEST_CASE("write_vein_png keeps a thick vein at the edge of the drawing whole", "[png]") {
  // the petiole's vein, 16 units wide, starts on the outline's lower edge: half its stroke lies below it
  test::TempDir t("png-edge");
  venation::VeinTree tree = straight_vein();
  tree.positions[0] = core::Vec3(50, 0, 0);
  tree.radius = {8, 8, 2, 0.2};
  exporters::PngParams p;
  p.size = 220;
  p.margin = 10;
  exporters::write_vein_png(t.path / "v.png", tree, square(), p);
  const exporters::Image img = exporters::read_png(t.path / "v.png");
  for (int x = 0; x < img.width; ++x) {
    INFO("x " << x);
    CHECK(rgb(img.at(x, img.height - 1)) == p.background);  // the bottom row: nothing cut off
  }
  const exporters::PngFrame f = exporters::png_frame(tree, square(), p);
  CHECK(f.py(-8) <= img.height - p.margin + 1e-9);  // the stroke's lowest point, inside the margin
}

TEST_CASE("write_vein_png draws a loop's closing segment at the width of the finer vein it joins", "[png]") {
  // the side vein's tip (80, 50; radius 0.2) joined to the main vein's tip (50, 90; radius 2): the closing
  // segment is drawn 0.2 wide (as veins.svg and the print), not 2
  test::TempDir t("png-loop");
  venation::VeinTree tree = straight_vein();
  using Pair = std::pair<core::Index, core::Index>;
  for (const Pair& loop : {Pair{3, 2}, Pair{2, 3}}) {
    INFO("the loop " << loop.first << " - " << loop.second);  // the finer node listed first, then second
    tree.anastomoses = {loop};
    exporters::PngParams p;
    p.size = 220;
    p.margin = 10;
    exporters::write_vein_png(t.path / "l.png", tree, square(), p);
    const exporters::Image img = exporters::read_png(t.path / "l.png");
    const exporters::PngFrame f = exporters::png_frame(tree, square(), p);
    auto pixel = [&](double x, double y) { return rgb(img.at(static_cast<int>(f.px(x)), static_cast<int>(f.py(y)))); };
    CHECK(pixel(65, 70) != p.blade);  // on the segment's middle
    // 3 px (1.5 units) to either side across it, direction (-0.6, 0.8): outside a thin stroke, inside an 8 px one
    CHECK(pixel(65 + 0.8 * 1.5, 70 + 0.6 * 1.5) == p.blade);
    CHECK(pixel(65 - 0.8 * 1.5, 70 - 0.6 * 1.5) == p.blade);
  }
}
