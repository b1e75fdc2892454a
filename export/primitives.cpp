// The model as printing primitives: vein segments (round cones) and cell-sheet triangles (slabs).
#include "export/printable.h"

namespace cellform::exporters {

std::vector<Segment> vein_segments(const venation::VeinGraph& g) {
  std::vector<Segment> out;
  out.reserve(g.edges.size());
  const bool orders = g.order.size() == g.position.size();
  for (const auto& [c, p] : g.edges) {
    // a side branch (of the next order) starts at its own width, as veins.svg draws it, not flared to its
    // parent's: the vein it leaves is thicker, round the joint; the main child tapers from its parent
    const bool side = orders && g.order[c] != g.order[p];
    out.push_back({g.position[c], g.position[p], g.radius[c], side ? g.radius[c] : g.radius[p]});
  }
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
