// Mesh checks for printing: topology, orientation, and the counts of check_mesh (self-intersections are
// found in export/self_intersection.cpp).
#include "export/mesh_check.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/union_find.h"

namespace cellform::exporters {

using core::Vec3;
using Tri = std::array<std::uint32_t, 3>;

using core::UnionFind;

std::vector<std::uint32_t> weld_positions(const std::vector<Vec3>& v) {
  std::vector<std::uint32_t> order(v.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto less = [&](std::uint32_t a, std::uint32_t b) {
    if (v[a].x() != v[b].x()) return v[a].x() < v[b].x();
    if (v[a].y() != v[b].y()) return v[a].y() < v[b].y();
    if (v[a].z() != v[b].z()) return v[a].z() < v[b].z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> canon(v.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    canon[order[k]] = (k > 0 && v[order[k]] == v[order[k - 1]]) ? canon[order[k - 1]] : order[k];
  return canon;
}

double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  return 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
}

double signed_volume(const PrintableMesh& m) {
  double s = 0;
  for (const Tri& t : m.triangles) s += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]]));
  return s / 6;
}

double surface_area(const PrintableMesh& m) {
  double s = 0;
  for (const Tri& t : m.triangles)
    s += (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return s / 2;
}

std::vector<std::uint32_t> part_labels(const PrintableMesh& m) {
  UnionFind uf(m.vertices.size());
  for (const Tri& t : m.triangles) {
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
  }
  // a parent's index is never above its child's, so in index order each parent already holds its root
  std::vector<std::uint32_t> label = std::move(uf.parent);
  for (std::uint32_t i = 0; i < label.size(); ++i) label[i] = label[label[i]];
  return label;
}

std::size_t count_parts(const PrintableMesh& m) {
  const std::vector<std::uint32_t> label = part_labels(m);
  std::vector<char> used(m.vertices.size(), 0);
  for (const Tri& t : m.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::size_t parts = 0;
  for (std::uint32_t i = 0; i < m.vertices.size(); ++i) parts += used[i] && label[i] == i;
  return parts;
}

MeshReport check_mesh(const PrintableMesh& mesh, int threads) {
  MeshReport r;
  const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
  r.triangles = nt;
  for (const Tri& t : mesh.triangles)
    for (std::uint32_t i : t)
      if (i >= nv)
        throw core::InvalidInput("check_mesh: a triangle refers to vertex " + std::to_string(i) + " of " +
                                 std::to_string(nv));
  if (nt == 0) return r;

  const std::vector<std::uint32_t> canon = weld_positions(mesh.vertices);
  std::vector<Tri> tris(nt);
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) used[tris[t][k] = canon[mesh.triangles[t][k]]] = 1;
    const Tri& w = tris[t];
    const Vec3 &a = mesh.vertices[w[0]], &b = mesh.vertices[w[1]], &c = mesh.vertices[w[2]];
    r.degenerate_triangles += w[0] == w[1] || w[1] == w[2] || w[0] == w[2] || (b - a).cross(c - a).squaredNorm() == 0;
  }
  r.welded_vertices = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    r.vertices += used[i] && canon[i] == i;
    r.welded_vertices += canon[i] != i;
  }
  r.volume = signed_volume(mesh);
  r.area = surface_area(mesh);
  r.bbox_min = Vec3::Constant(std::numeric_limits<double>::infinity());
  r.bbox_max = -r.bbox_min;
  for (std::size_t i = 0; i < nv; ++i)
    if (used[i]) {
      r.bbox_min = r.bbox_min.cwiseMin(mesh.vertices[i]);
      r.bbox_max = r.bbox_max.cwiseMax(mesh.vertices[i]);
    }

  // Edges: every triangle side as (low, high, forward?), sorted so equal edges are adjacent.
  struct Side {
    std::uint32_t lo, hi, tri;
    bool forward;
    bool operator<(const Side& o) const { return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : tri < o.tri; }
  };
  const auto collapsed = [&](std::size_t t) {
    const Tri& w = tris[t];
    return w[0] == w[1] || w[1] == w[2] || w[0] == w[2];
  };
  std::vector<Side> sides;
  sides.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Tri& w = tris[t];
    if (collapsed(t)) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = w[k], b = w[(k + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t), a < b});
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<char> bad_vertex(nv, 0);                         // touches a boundary or non-manifold edge
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // unique undirected edges
  for (std::size_t k = 0; k < sides.size();) {
    std::size_t e = k;
    while (e < sides.size() && sides[e].lo == sides[k].lo && sides[e].hi == sides[k].hi) ++e;
    const std::size_t uses = e - k;
    edges.emplace_back(sides[k].lo, sides[k].hi);
    if (uses == 1)
      ++r.boundary_edges;
    else if (uses > 2)
      ++r.nonmanifold_edges;
    else if (sides[k].forward == sides[k + 1].forward)
      ++r.misoriented_edges;
    if (uses != 2) bad_vertex[sides[k].lo] = bad_vertex[sides[k].hi] = 1;
    k = e;
  }
  r.consistently_oriented = r.misoriented_edges == 0;

  // Non-manifold vertices: the triangles around a vertex must form one fan (connected through edges at it).
  std::vector<std::uint32_t> start(nv + 1, 0), around;
  for (std::size_t t = 0; t < nt; ++t)
    if (!collapsed(t))
      for (std::uint32_t i : tris[t]) ++start[i + 1];
  for (std::size_t i = 0; i < nv; ++i) start[i + 1] += start[i];
  around.resize(start[nv]);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
      if (!collapsed(t))
        for (std::uint32_t i : tris[t]) around[fill[i]++] = static_cast<std::uint32_t>(t);
  }
  std::vector<char> fan_broken(nv, 0);
  core::parallel_for(
      nv, threads,
      [&](std::size_t b0, std::size_t e0) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> spokes;  // (other vertex, local triangle)
        for (std::size_t v = b0; v < e0; ++v) {
          const std::uint32_t n = start[v + 1] - start[v];
          if (n == 0) continue;
          spokes.clear();
          for (std::uint32_t j = 0; j < n; ++j) {
            const Tri& w = tris[around[start[v] + j]];
            for (std::uint32_t o : w)
              if (o != v) spokes.emplace_back(o, j);
          }
          std::sort(spokes.begin(), spokes.end());
          UnionFind uf(n);
          for (std::size_t k = 1; k < spokes.size(); ++k)
            if (spokes[k].first == spokes[k - 1].first) uf.unite(spokes[k].second, spokes[k - 1].second);
          std::uint32_t fans = 0;
          for (std::uint32_t j = 0; j < n; ++j) fans += uf.find(j) == j;
          fan_broken[v] = fans > 1;
        }
      },
      4096);
  for (std::size_t v = 0; v < nv; ++v) {
    r.nonmanifold_vertices += fan_broken[v];
    if (fan_broken[v]) bad_vertex[v] = 1;
  }

  // Parts and the genus of each closed manifold part: V - E + F = 2 - 2g.
  UnionFind uf(nv);
  for (const Tri& w : tris) {
    uf.unite(w[0], w[1]);
    uf.unite(w[0], w[2]);
  }
  std::vector<std::int64_t> part_of(nv, -1);
  for (std::uint32_t i = 0; i < nv; ++i)
    if (used[i] && uf.find(i) == i) part_of[i] = static_cast<std::int64_t>(r.parts++);
  std::vector<std::int64_t> V(r.parts, 0), E(r.parts, 0), F(r.parts, 0);
  std::vector<char> closed(r.parts, 1);
  for (std::uint32_t i = 0; i < nv; ++i)
    if (used[i] && canon[i] == i) {
      const auto p = part_of[uf.find(i)];
      ++V[p];
      if (bad_vertex[i]) closed[p] = 0;
    }
  for (const auto& e : edges) ++E[part_of[uf.find(e.first)]];
  for (std::size_t t = 0; t < nt; ++t)
    if (!collapsed(t)) ++F[part_of[uf.find(tris[t][0])]];
  // per part: the signed volume (a closed pocket's walls face into it, so its volume is negative)
  std::vector<double> part_volume(r.parts, 0.0);
  for (std::size_t t = 0; t < nt; ++t)
    if (!collapsed(t)) {
      const Vec3& a = mesh.vertices[tris[t][0]];
      const Vec3& b = mesh.vertices[tris[t][1]];
      const Vec3& c = mesh.vertices[tris[t][2]];
      part_volume[part_of[uf.find(tris[t][0])]] += a.dot(b.cross(c)) / 6.0;
    }
  for (const double v : part_volume) {
    r.pieces += v > 0;
    r.cavities += v < 0;
  }
  r.genus.resize(r.parts);
  for (std::size_t p = 0; p < r.parts; ++p) {
    const std::int64_t chi = V[p] - E[p] + F[p];
    r.genus[p] = closed[p] && chi % 2 == 0 ? static_cast<int>((2 - chi) / 2) : -1;
  }

  // skips the degenerate ones too; a grid cell that leaves more than 3e8 candidate pairs after its fans are
  // peeled off (a stack of triangles over one another, minutes of tests) ends the search, untested
  const SelfIntersectionCount found = count_self_intersections(mesh.vertices, tris, 16, 3e8, threads);
  r.self_intersections = found.count;
  r.intersecting_pairs = found.examples;
  r.intersections_tested = found.tested;

  // Nesting: the surfaces of a solid wind once round every point of it. Seen from a point on part p, the
  // other parts' winding number W is 0 outside every piece (p must face out) and 1 inside a piece (p is a
  // pocket's wall and must face in); anything else is a surface facing the wrong way for where it lies (two
  // outward cubes, one inside the other).
  if (r.parts > 1 && r.closed_manifold() && r.consistently_oriented && r.intersections_tested &&
      r.self_intersections == 0) {  // parts apart from each other: each lies inside another or outside it
    std::vector<std::int64_t> tri_part(nt, -1);
    std::vector<Vec3> lo(r.parts, Vec3::Constant(std::numeric_limits<double>::infinity())), hi(r.parts, -lo[0]);
    std::vector<std::size_t> first(r.parts, nt);
    for (std::size_t t = 0; t < nt; ++t) {
      if (collapsed(t)) continue;
      const auto p = static_cast<std::size_t>(part_of[uf.find(tris[t][0])]);
      tri_part[t] = static_cast<std::int64_t>(p);
      if (first[p] == nt) first[p] = t;
      for (const std::uint32_t i : tris[t]) {
        lo[p] = lo[p].cwiseMin(mesh.vertices[i]);
        hi[p] = hi[p].cwiseMax(mesh.vertices[i]);
      }
    }
    std::vector<std::vector<std::uint32_t>> part_tris(r.parts);
    for (std::size_t t = 0; t < nt; ++t)
      if (tri_part[t] >= 0) part_tris[static_cast<std::size_t>(tri_part[t])].push_back(static_cast<std::uint32_t>(t));
    // the work: a solid angle per triangle of every part whose box holds another's point; beyond 3e8 (thousands
    // of pockets in a shell of millions of triangles: minutes) the nesting is not checked, and the report says so
    double work = 0;
    if (r.parts <= 20000)
      for (std::size_t p = 0; p < r.parts && work <= 3e8; ++p) {
        if (first[p] == nt) continue;
        const Tri& w = tris[first[p]];
        const Vec3 q = (mesh.vertices[w[0]] + mesh.vertices[w[1]] + mesh.vertices[w[2]]) / 3.0;
        for (std::size_t o = 0; o < r.parts; ++o)
          if (o != p && (q.array() >= lo[o].array()).all() && (q.array() <= hi[o].array()).all())
            work += static_cast<double>(part_tris[o].size());
      }
    r.nesting_tested = r.parts <= 20000 && work <= 3e8;
    std::vector<char> wrong(r.parts, 0);
    if (r.nesting_tested)
      core::parallel_for(
          r.parts, threads,
          [&](std::size_t b0, std::size_t e0) {
            for (std::size_t p = b0; p < e0; ++p) {
              if (first[p] == nt) continue;
              const Tri& w = tris[first[p]];
              const Vec3 q = (mesh.vertices[w[0]] + mesh.vertices[w[1]] + mesh.vertices[w[2]]) / 3.0;
              double seen = 0;  // solid angle of the other parts whose boxes hold q (only those can wind round it)
              for (std::size_t o = 0; o < r.parts; ++o) {
                if (o == p || (q.array() < lo[o].array()).any() || (q.array() > hi[o].array()).any()) continue;
                for (const std::uint32_t t : part_tris[o])
                  seen += exporters::solid_angle(mesh.vertices[tris[t][0]] - q, mesh.vertices[tris[t][1]] - q,
                                                 mesh.vertices[tris[t][2]] - q);
              }
              const double winding = seen / (4 * M_PI);
              const bool outside = std::abs(winding) < 0.25, inside = std::abs(winding - 1) < 0.25;
              wrong[p] = !((outside && part_volume[p] > 0) || (inside && part_volume[p] < 0));
            }
          },
          1);
    for (const char x : wrong) r.misnested_parts += x;
  }

  return r;
}

std::vector<std::string> MeshReport::problems() const {
  std::vector<std::string> p;
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  if (triangles == 0) p.push_back("no triangles");
  if (boundary_edges > 0) p.push_back("not closed: " + count(boundary_edges, "boundary edge", "boundary edges"));
  if (nonmanifold_edges > 0 || nonmanifold_vertices > 0)
    p.push_back("not 2-manifold: " + count(nonmanifold_edges, "edge", "edges") + " of three or more triangles, " +
                count(nonmanifold_vertices, "vertex", "vertices") + " where separate fans touch");
  if (!consistently_oriented)
    p.push_back("misoriented: " + count(misoriented_edges, "edge whose", "edges whose") +
                " two triangles run it the same way");
  if (!intersections_tested)
    p.push_back(
        "self-intersections not tested: too many triangles overlap in one place (more than 3e8 pairs to test in "
        "one cell of the search grid, as in a stack of triangles over one another)");
  if (!nesting_tested)
    p.push_back(
        "nesting not tested: too many parts inside others' boxes (more than 20,000 parts, or 3e8 solid angles "
        "to sum), so a closed surface facing the wrong way for where it lies may go unseen");
  if (self_intersections > 0)
    p.push_back("self-intersecting: " + count(self_intersections, "pair", "pairs") + " of triangles cross");
  if (degenerate_triangles > 0)
    p.push_back(count(degenerate_triangles, "degenerate triangle", "degenerate triangles") +
                " (repeated corners or zero area)");
  if (misnested_parts > 0)
    p.push_back("misoriented shells: " +
                (misnested_parts == 1
                     ? std::string("1 closed surface faces the wrong way for where it lies")
                     : std::to_string(misnested_parts) + " closed surfaces face the wrong way for where they lie") +
                " (a surface inside a solid is a pocket's wall and must face into the pocket; one outside every "
                "solid, or inside a pocket, must face out)");
  // a negative total is the whole mesh turned inside out when every shell faces the wrong way (one alone, or
  // all of them misnested) and none crosses another: reversing every triangle fixes it; otherwise (one shell
  // of two reversed, say) the problems above say what to fix
  if (triangles > 0 && closed_manifold() && consistently_oriented && !(volume > 0))
    p.push_back(!(volume < 0) ? "encloses no volume"
                : (parts == 1 || (nesting_tested && misnested_parts == parts)) && self_intersections == 0 &&
                        intersections_tested
                    ? "inside out: every triangle faces inward (the enclosed volume is negative); reverse the "
                      "triangles' winding"
                    : "the enclosed volume is negative");
  return p;
}

std::string MeshReport::summary() const {
  std::ostringstream s;
  s << triangles << " triangles, " << vertices << " vertices, ";
  // the inner walls of closed pockets are parts too, but not pieces that come apart (a volume's sign means
  // that only on a closed, consistently oriented mesh, and only if it is not inside out)
  if (cavities > 0 && pieces > 0 && solid())
    s << pieces << (pieces == 1 ? " solid piece with " : " solid pieces with ") << cavities
      << (cavities == 1 ? " closed cavity" : " closed cavities") << " inside (" << parts << " surfaces)";
  else if (solid())
    s << parts << (parts == 1 ? " part" : " parts");
  else  // pieces and pockets are not told apart on such a mesh
    s << parts << (parts == 1 ? " connected surface" : " connected surfaces");
  // a volume means something only inside a closed, consistently oriented surface
  s << "; volume ";
  if (solid())
    s << volume;
  else
    s << "none ("
      << (!closed_manifold()       ? boundary_edges > 0 ? "not closed" : "not 2-manifold"
          : !consistently_oriented ? "misoriented"
          : !nesting_tested        ? "nesting not tested"
                                   : "misoriented shells")
      << ")";
  const Vec3 size = bbox_max - bbox_min;
  s << ", area " << area << "; bounding box " << size.x() << " x " << size.y() << " x " << size.z() << "\n";
  s << "boundary edges " << boundary_edges << ", non-manifold edges " << nonmanifold_edges << ", non-manifold vertices "
    << nonmanifold_vertices << ", misoriented edges " << misoriented_edges << ", self-intersecting pairs "
    << (intersections_tested ? std::to_string(self_intersections) : std::string("not tested"))
    << ", degenerate triangles " << degenerate_triangles << "\n";
  s << "genus per part:";
  for (std::size_t p = 0; p < genus.size() && p < 20; ++p)
    s << " " << (genus[p] < 0 ? std::string("open") : std::to_string(genus[p]));
  if (genus.size() > 20) s << " ...";
  s << "\n" << (printable() ? "printable" : "NOT printable");
  const auto why = problems();
  for (std::size_t k = 0; k < why.size(); ++k) s << (k ? "; " : ": ") << why[k];
  s << "\n";
  return s.str();
}

}  // namespace cellform::exporters
