// SVG, PLY and OBJ writers for space-colonisation vein graphs.
#include "venation/vein_io.h"

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/chunk_file.h"
#include "core/polylines.h"
#include "core/text.h"
#include "venation/plot_order.h"

namespace cellform::venation {

namespace {
double radius_of(const VeinTree& t, Index i) { return t.radius.size() == t.size() ? t.radius[i] : 0.0; }
}  // namespace

std::pair<Vec2, Vec2> drawing_bounds(const VeinTree& tree, const Outline& outline) {
  Vec2 lo(0, 0), hi(0, 0);
  bool first = true;
  auto grow = [&](const Vec2& q) {
    lo = first ? q : Vec2(lo.cwiseMin(q));
    hi = first ? q : Vec2(hi.cwiseMax(q));
    first = false;
  };
  for (const Vec2& q : outline.points) grow(q);
  // each node with its radius: a vein's round stroke reaches that far (the midvein's wide end ran off the
  // page past the margin)
  for (Index i = 0; i < tree.size(); ++i) {
    const Vec2 q(tree.positions[i].x(), tree.positions[i].y());
    const double r = radius_of(tree, i);
    grow(q - Vec2(r, r));
    grow(q + Vec2(r, r));
  }
  return {lo, hi};
}

namespace {

/// Stroke colour of the layer of vein order `order`: LightBurn's layer colours 00 to 07, then 10 to 13,
/// so software that separates a drawing's operations by colour, as laser cutters' does, gives each order
/// its own layer (LightBurn maps a colour to its nearest palette entry: colours off its palette could share
/// a layer) and its own power or pen. Orders from 12 on share the last colour: the finest veins together,
/// never with the midvein.
const char* order_colour(std::uint32_t order) {
  static const char* const kColours[] = {"#000000", "#0000ff", "#ff0000", "#00e000", "#d0d000", "#ff8000",
                                         "#00e0e0", "#ff00ff", "#a00000", "#00a000", "#a0a000", "#c08000"};
  constexpr std::uint32_t kLast = sizeof kColours / sizeof kColours[0] - 1;
  return kColours[std::min(order == 0 ? 0 : order - 1, kLast)];
}

/// The outline's colour: LightBurn's layer 09, used by no vein order.
constexpr const char* kOutlineColour = "#0000a0";
/// The outline layer's number: fixed, whatever the number of vein orders (below 100: a branch off the main
/// child carries at most half its parent's flow), so a plotter's "plot layer 100" draws any leaf's outline.
constexpr std::size_t kOutlineLayer = 100;

}  // namespace

SvgPage write_svg(const std::filesystem::path& path, const VeinTree& tree, const Outline& outline, const SvgParams& sp,
                  const std::vector<Vec3>& sources) {
  const auto [lo, hi] = drawing_bounds(tree, outline);
  const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-12});
  // the outline's line reaches half its width (in mm, round joins) past its points: inside `size`, not the margin
  const double half = outline.points.empty() ? 0.0 : sp.outline_stroke / 2, edge = sp.margin + half;
  const double s = sp.scale > 0 ? sp.scale : std::max(sp.size - 2 * half, sp.size / 2) / extent;  // mm per unit
  const double w = (hi.x() - lo.x()) * s + 2 * edge, h = (hi.y() - lo.y()) * s + 2 * edge;
  auto X = [&](double x) { return (x - lo.x()) * s + edge; };
  auto Y = [&](double y) { return (hi.y() - y) * s + edge; };

  // Veins as polylines, so a plotter draws a vein without lifting its pen at every node: a path runs on
  // through a node with one child while the width stays the same (between branch points it does).
  const auto n = static_cast<Index>(tree.size());
  const bool orders = tree.order.size() == tree.size();
  auto order_of = [&](Index i) { return orders ? tree.order[i] : 0u; };
  std::vector<Index> children(n, 0), only_child(n, kNoIndex);
  for (Index i = 0; i < n; ++i)
    if (tree.parent[i] != kNoIndex) {
      ++children[tree.parent[i]];
      only_child[tree.parent[i]] = i;
    }
  auto width = [&](Index i) { return std::max(sp.min_stroke, 2 * radius_of(tree, i) * s); };
  auto continues = [&](Index i) {  // does the segment into i go on from the segment into its parent?
    const Index p = tree.parent[i];
    return p != kNoIndex && tree.parent[p] != kNoIndex && children[p] == 1 && width(p) == width(i) &&
           order_of(p) == order_of(i);
  };
  std::vector<Index> stroke_start{0}, stroke_node;  // strokes: runs of nodes (CSR)
  std::vector<double> stroke_width;
  std::vector<std::uint32_t> stroke_order;  // the layer: the order of the segments' child nodes
  if (sp.join_veins) {
    // A path per vein: from where it leaves its parent vein on along its main child (the one of its own
    // order, the widest, the first) to its tip, at its length-weighted mean width.
    std::vector<Index> main_child(n, kNoIndex);
    for (Index i = 0; i < n; ++i) {
      const Index p = tree.parent[i];
      if (p == kNoIndex || order_of(i) != order_of(p)) continue;
      const Index m = main_child[p];
      if (m == kNoIndex || radius_of(tree, i) > radius_of(tree, m)) main_child[p] = i;
    }
    for (Index i = 0; i < n; ++i) {
      const Index p = tree.parent[i];
      if (p == kNoIndex || (tree.parent[p] != kNoIndex && main_child[p] == i)) continue;  // not a vein's first
      stroke_node.push_back(p);
      double length = 0, weighted = 0;
      for (Index at = i; at != kNoIndex; at = main_child[at]) {
        stroke_node.push_back(at);
        const double l = (tree.positions[at] - tree.positions[tree.parent[at]]).norm();
        length += l;
        weighted += l * width(at);
      }
      stroke_start.push_back(static_cast<Index>(stroke_node.size()));
      stroke_width.push_back(length > 0 ? weighted / length : width(i));
      stroke_order.push_back(order_of(i));
    }
  } else {
    for (Index i = 0; i < n; ++i) {
      if (tree.parent[i] == kNoIndex || continues(i)) continue;  // not the first segment of a path
      stroke_node.push_back(tree.parent[i]);
      for (Index at = i;; at = only_child[at]) {
        stroke_node.push_back(at);
        if (children[at] != 1 || !continues(only_child[at])) break;
      }
      stroke_start.push_back(static_cast<Index>(stroke_node.size()));
      stroke_width.push_back(width(i));
      stroke_order.push_back(order_of(i));
    }
  }
  for (const auto& [a, b] : tree.anastomoses) {  // a loop's closing segment: the width of the finer vein it joins
    stroke_node.insert(stroke_node.end(), {a, b});
    stroke_start.push_back(static_cast<Index>(stroke_node.size()));
    stroke_width.push_back(std::min(width(a), width(b)));
    stroke_order.push_back(std::max(order_of(a), order_of(b)));
  }
  std::vector<std::uint32_t> layers = stroke_order;
  std::sort(layers.begin(), layers.end());
  layers.erase(std::unique(layers.begin(), layers.end()), layers.end());

  core::write_file_atomically(path, [&](std::ostream& os) {
    std::string out;  // numbers as "%.3f" (micrometres)
    auto num = [&](double x) { core::append_fixed(out, x, 3); };
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" ";
    out += "width=\"";
    num(w);
    out += "mm\" height=\"";
    num(h);
    out += "mm\" viewBox=\"0 0 ";
    num(w);
    out += ' ';
    num(h);
    out += "\">\n";
    // One Inkscape layer per vein order, the widest first, then the outline (a laser cuts it last, after
    // engraving the veins). Layer names begin with their number, as AxiDraw's "plot one layer" wants.
    // In each layer the strokes come nearest-next from where the pen is (the page's corner, then the end
    // of the previous layer), each drawn from its nearer end: a plotter's pen travels a fraction as far as
    // between strokes in the order the veins grew.
    auto page = [&](Index i) { return Vec2(X(tree.positions[i].x()), Y(tree.positions[i].y())); };
    Vec2 pen(0, 0);
    std::size_t number = 0;
    std::vector<std::size_t> members;
    std::vector<std::array<Vec2, 2>> ends;
    for (const std::uint32_t layer : layers) {
      members.clear();
      ends.clear();
      for (std::size_t k = 0; k < stroke_order.size(); ++k)
        if (stroke_order[k] == layer) {
          members.push_back(k);
          ends.push_back({page(stroke_node[stroke_start[k]]), page(stroke_node[stroke_start[k + 1] - 1])});
        }
      const std::string label =
          std::to_string(++number) + (layer == 0 ? " veins" : " veins of order " + std::to_string(layer));
      out += "<g id=\"veins-order-" + std::to_string(layer) + "\" inkscape:groupmode=\"layer\" inkscape:label=\"" +
             label + "\" stroke=\"" + order_colour(layer) +
             "\" stroke-linecap=\"round\" stroke-linejoin=\"round\" fill=\"none\">\n";
      for (const PlotStep& step : plot_order(ends, pen)) {
        const std::size_t k = members[step.stroke];
        pen = ends[step.stroke][step.reversed ? 0 : 1];
        out += "<path stroke-width=\"";
        num(stroke_width[k]);
        out += "\" d=\"";
        const Index first = stroke_start[k], last = stroke_start[k + 1];
        for (Index m = 0; m < last - first; ++m) {
          const Index node = stroke_node[step.reversed ? last - 1 - m : first + m];
          out += m ? " L" : "M";
          num(X(tree.positions[node].x()));
          out += ' ';
          num(Y(tree.positions[node].y()));
        }
        out += "\"/>\n";
        core::drain(out, os);
      }
      out += "</g>\n";
    }
    if (!outline.points.empty()) {
      // a line, not a filled shape: plotters draw it, laser cutters cut it (a fill they would engrave)
      out += "<g id=\"outline\" inkscape:groupmode=\"layer\" inkscape:label=\"" +
             std::to_string(std::max(kOutlineLayer, number + 1)) + " outline\" stroke=\"" + kOutlineColour +
             "\" stroke-linejoin=\"round\" fill=\"none\">\n<path stroke-width=\"";
      num(sp.outline_stroke);
      out += "\" d=\"";
      for (std::size_t i = 0; i < outline.points.size(); ++i) {
        out += i ? " L" : "M";
        num(X(outline.points[i].x()));
        out += ' ';
        num(Y(outline.points[i].y()));
      }
      out += " Z\"/>\n</g>\n";
    }
    if (sp.draw_sources && !sources.empty()) {
      // a layer whose name begins with "%" is one AxiDraw does not plot
      out += "<g id=\"sources\" inkscape:groupmode=\"layer\" inkscape:label=\"% sources\" fill=\"#c03020\">\n";
      for (const Vec3& q : sources) {
        out += "<circle cx=\"";
        num(X(q.x()));
        out += "\" cy=\"";
        num(Y(q.y()));
        out += "\" r=\"0.5\"/>\n";
        core::drain(out, os);
      }
      out += "</g>\n";
    }
    out += "</svg>\n";
    core::drain(out, os, 0);
  });
  return {s, w, h};
}

void write_vein_ply(const std::filesystem::path& path, const VeinTree& tree) {
  // the layout of the cell runs' veins.ply (export/vein_files.h), without their cell ids: binary, per node
  // x y z flow radius order, edges child -> parent, then the loop-closing edges (anastomoses)
  const bool flows = tree.flow.size() == tree.size(), orders = tree.order.size() == tree.size();
  core::ByteWriter w;  // host byte order: little-endian hosts only (x86-64, arm64), as the header says
  for (Index i = 0; i < tree.size(); ++i) {
    const Vec3& q = tree.positions[i];
    for (int k = 0; k < 3; ++k) w.put(q[k]);  // doubles, as cells.ply's
    for (double x : {flows ? tree.flow[i] : 0.0, radius_of(tree, i)}) w.put(static_cast<float>(x));
    w.put(static_cast<std::int32_t>(orders ? tree.order[i] : 0));
  }
  std::size_t edges = 0;
  auto edge = [&](Index a, Index b) {
    w.put(static_cast<std::int32_t>(a));
    w.put(static_cast<std::int32_t>(b));
    ++edges;
  };
  for (Index i = 0; i < tree.size(); ++i)
    if (tree.parent[i] != kNoIndex) edge(i, tree.parent[i]);
  for (const auto& [a, b] : tree.anastomoses) edge(a, b);
  const std::string body = w.take();
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment cellform space-colonisation veins, in model units (printable.* is "
      "in "
      "mm): edges run "
      "child -> parent, "
      "then the edges that close loops\nelement vertex ";
  core::append_integer(header, tree.size());
  header +=
      "\nproperty double x\nproperty double y\nproperty double z\nproperty float flow\nproperty float radius\n"
      "property int order\nelement edge ";
  core::append_integer(header, edges);
  header += "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  core::write_file_atomically(path, [&](std::ostream& os) {
    os.write(header.data(), static_cast<std::streamsize>(header.size()));
    os.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

void write_vein_obj(const std::filesystem::path& path, const VeinTree& tree) {
  // the layout of the cell runs' veins.obj: "#a flow radius order" after each vertex, lines child parent
  core::write_file_atomically(path, [&](std::ostream& os) {
    std::string out = "# cellform space-colonisation veins: ";
    core::append_integer(out, tree.size());
    out +=
        " nodes, in model units (a print{...} writes printable.* in mm, and run.json gives print.scale_mm_per_unit)\n"
        "# per vertex: '#a flow radius order' follows its 'v' line\no veins\n";
    // positions with 9 significant digits about the origin, more far from it; the rest as "%.9g"
    const int digits = core::coordinate_digits(tree.positions);
    for (Index i = 0; i < tree.size(); ++i) {
      const Vec3& q = tree.positions[i];
      out += 'v';
      for (double x : {q.x(), q.y(), q.z()}) {
        out += ' ';
        core::append_general(out, x, digits);
      }
      out += "\n#a ";
      core::append_general(out, tree.flow.size() == tree.size() ? tree.flow[i] : 0.0);
      out += ' ';
      core::append_general(out, radius_of(tree, i));
      out += ' ';
      core::append_integer(out, tree.order.size() == tree.size() ? tree.order[i] : 0);
      out += '\n';
      core::drain(out, os);
    }
    std::vector<std::array<Index, 2>> edges;  // child -> parent, then the loops' closing segments
    edges.reserve(tree.size() + tree.anastomoses.size());
    for (Index i = 0; i < tree.size(); ++i)
      if (tree.parent[i] != kNoIndex) edges.push_back({i, tree.parent[i]});
    for (const auto& [a, b] : tree.anastomoses) edges.push_back({a, b});
    for (const auto& line : core::polylines(tree.size(), edges)) {  // a curve per branch
      out += 'l';
      for (const Index v : line) {
        out += ' ';
        core::append_integer(out, v + 1);
      }
      out += '\n';
      core::drain(out, os);
    }
    core::drain(out, os, 0);
  });
}

}  // namespace cellform::venation
