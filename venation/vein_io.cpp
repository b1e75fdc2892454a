// SVG, PLY and OBJ writers for space-colonisation vein graphs.
#include "venation/vein_io.h"

#include <algorithm>
#include <iomanip>
#include <ostream>

#include "core/atomic_file.h"

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
  for (const Vec3& q : tree.positions) grow(Vec2(q.x(), q.y()));
  return {lo, hi};
}

void write_svg(const std::filesystem::path& path, const VeinTree& tree, const Outline& outline, const SvgParams& sp,
               const std::vector<Vec3>& sources) {
  const auto [lo, hi] = drawing_bounds(tree, outline);
  const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-12});
  const double s = sp.pixels_per_unit > 0 ? sp.pixels_per_unit : 1000.0 / extent;
  const double w = (hi.x() - lo.x()) * s + 2 * sp.margin, h = (hi.y() - lo.y()) * s + 2 * sp.margin;
  auto X = [&](double x) { return (x - lo.x()) * s + sp.margin; };
  auto Y = [&](double y) { return (hi.y() - y) * s + sp.margin; };
  double tip = 0;
  if (tree.radius.size() == tree.size() && !tree.radius.empty())
    tip = *std::min_element(tree.radius.begin(), tree.radius.end());
  core::write_file_atomically(path, [&](std::ostream& out) {
    out << std::fixed << std::setprecision(2);
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" viewBox=\"0 0 " << w
        << ' ' << h << "\">\n";
    if (!outline.points.empty()) {
      out << "<path fill=\"#d8ecc0\" stroke=\"#4a7a2a\" stroke-width=\"1\" d=\"";
      for (std::size_t i = 0; i < outline.points.size(); ++i)
        out << (i ? " L" : "M") << X(outline.points[i].x()) << ' ' << Y(outline.points[i].y());
      out << " Z\"/>\n";
    }
    out << "<g stroke=\"#2b3a1a\" stroke-linecap=\"round\" fill=\"none\">\n";
    auto segment = [&](Index a, Index b, double r) {
      const double width = std::max(sp.min_stroke, 2 * r * s);
      out << "<path stroke-width=\"" << width << "\" d=\"M" << X(tree.positions[a].x()) << ' '
          << Y(tree.positions[a].y()) << " L" << X(tree.positions[b].x()) << ' ' << Y(tree.positions[b].y())
          << "\"/>\n";
    };
    for (Index i = 0; i < tree.size(); ++i)
      if (tree.parent[i] != kNoIndex) segment(tree.parent[i], i, radius_of(tree, i));
    for (const auto& [a, b] : tree.anastomoses) segment(a, b, tip);
    out << "</g>\n";
    if (sp.draw_sources)
      for (const Vec3& q : sources)
        out << "<circle cx=\"" << X(q.x()) << "\" cy=\"" << Y(q.y()) << "\" r=\"2\" fill=\"#c03020\"/>\n";
    out << "</svg>\n";
  });
}

void write_vein_ply(const std::filesystem::path& path, const VeinTree& tree) {
  const auto edges = tree.edges();
  core::write_file_atomically(path, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment cellform space-colonisation veins\nelement vertex " << tree.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty float radius\nproperty float "
           "flow\nproperty int order\n"
        << "element edge " << edges.size() << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    out << std::setprecision(9);
    for (Index i = 0; i < tree.size(); ++i) {
      const Vec3& q = tree.positions[i];
      out << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << radius_of(tree, i) << ' '
          << (tree.flow.size() == tree.size() ? tree.flow[i] : 0.0) << ' '
          << (tree.order.size() == tree.size() ? tree.order[i] : 0) << '\n';
    }
    for (const auto& [a, b] : edges) out << a << ' ' << b << '\n';
  });
}

void write_vein_obj(const std::filesystem::path& path, const VeinTree& tree) {
  core::write_file_atomically(path, [&](std::ostream& out) {
    out << "# cellform space-colonisation veins: " << tree.size()
        << " nodes\n# per vertex: \"# r radius order flow\"\n";
    out << std::setprecision(9);
    for (Index i = 0; i < tree.size(); ++i) {
      const Vec3& q = tree.positions[i];
      out << "v " << q.x() << ' ' << q.y() << ' ' << q.z() << "\n# r " << radius_of(tree, i) << ' '
          << (tree.order.size() == tree.size() ? tree.order[i] : 0) << ' '
          << (tree.flow.size() == tree.size() ? tree.flow[i] : 0.0) << '\n';
    }
    for (const auto& [a, b] : tree.edges()) out << "l " << a + 1 << ' ' << b + 1 << '\n';
  });
}

}  // namespace cellform::venation
