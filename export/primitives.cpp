// The model as printing primitives: vein segments (round cones) and cell-sheet triangles (slabs).
#include "export/printable.h"

namespace cellform::exporters {

std::vector<Segment> vein_segments(const venation::VeinGraph& g) {
  std::vector<Segment> out;
  out.reserve(g.edges.size());
  for (const auto& e : g.edges) out.push_back({g.position[e[0]], g.position[e[1]], g.radius[e[0]], g.radius[e[1]]});
  return out;
}

std::vector<std::array<Vec3, 3>> shell_triangles(const cells::Cells& cells, const cells::Surface& surface) {
  std::vector<std::array<Vec3, 3>> out;
  out.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles)
    out.push_back({cells.position[t[0]], cells.position[t[1]], cells.position[t[2]]});
  return out;
}

}  // namespace cellform::exporters
