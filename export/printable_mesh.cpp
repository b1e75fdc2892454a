// Meshing a level set (printable.cpp makes it): adaptive volumeToMesh with a repair of the crossings
// adaptivity makes, pieces and cavities, and the .vdb file.
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "core/atomic_file.h"
#include "core/chunk_file.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "export/mesh_check.h"
#include "export/mesh_clean.h"
#include "export/printable.h"
#include "export/printable_internal.h"
#include "export/printable_vdb.h"

namespace cellform::exporters {

using detail::check_params;
using detail::init_openvdb;
using detail::report_progress;
using detail::seconds_since;

namespace {

constexpr double kShortestEdge = 0.05;  // voxels: shorter edges of the mesher's output are collapsed

// One volumeToMesh pass; voxels active in `no_merge` are meshed without adaptivity. Quads are split
// along their shorter diagonal; triangles with a repeated vertex (from merged points) are dropped; edges
// shorter than `shortest` (mm) are collapsed (collapse_short_edges).
PrintableMesh mesh_once(const openvdb::FloatGrid& grid, double adaptivity, const openvdb::BoolTree::Ptr& no_merge,
                        double shortest) {
  openvdb::tools::VolumeToMesh mesher(0.0, adaptivity, true);
  if (no_merge) mesher.setAdaptivityMask(no_merge);
  mesher(grid);
  PrintableMesh mesh;
  mesh.vertices.resize(mesher.pointListSize());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const openvdb::Vec3s& p = mesher.pointList()[i];
    mesh.vertices[i] = Vec3(p.x(), p.y(), p.z());
  }
  const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a != b && b != c && c != a) mesh.triangles.push_back({a, b, c});
  };
  const auto& v = mesh.vertices;
  for (std::size_t n = 0; n < mesher.polygonPoolListSize(); ++n) {
    const openvdb::tools::PolygonPool& pool = mesher.polygonPoolList()[n];
    for (std::size_t i = 0; i < pool.numQuads(); ++i) {
      const openvdb::Vec4I& q = pool.quad(i);
      if ((v[q[0]] - v[q[2]]).squaredNorm() <= (v[q[1]] - v[q[3]]).squaredNorm()) {
        add(q[0], q[1], q[2]);
        add(q[0], q[2], q[3]);
      } else {
        add(q[0], q[1], q[3]);
        add(q[1], q[2], q[3]);
      }
    }
    for (std::size_t i = 0; i < pool.numTriangles(); ++i) {
      const openvdb::Vec3I& t = pool.triangle(i);
      add(t[0], t[1], t[2]);
    }
  }
  collapse_short_edges(mesh, shortest);
  return mesh;
}

}  // namespace

namespace {

/// Signed volume of each connected part (through shared vertices), keyed by its root vertex.
std::vector<double> part_volumes(const PrintableMesh& mesh, std::vector<std::uint32_t>& root) {
  const std::size_t nv = mesh.vertices.size();
  root.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) root[i] = static_cast<std::uint32_t>(i);
  auto find = [&](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const auto& t : mesh.triangles) {
    const std::uint32_t a = find(t[0]), b = find(t[1]);
    root[b] = a;
    root[find(t[2])] = a;
  }
  for (std::size_t i = 0; i < nv; ++i) root[i] = find(static_cast<std::uint32_t>(i));
  std::vector<double> volume(nv, 0.0);
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    volume[root[t[0]]] += a.dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
  }
  return volume;
}

/// Parts of positive volume (pieces) and of negative volume (walls of cavities).
void count_pieces(const PrintableMesh& mesh, std::size_t& pieces, std::size_t& cavities) {
  std::vector<std::uint32_t> root;
  const std::vector<double> volume = part_volumes(mesh, root);
  pieces = cavities = 0;
  std::vector<char> used(root.size(), 0);
  for (const auto& t : mesh.triangles) used[root[t[0]]] = 1;
  for (std::size_t i = 0; i < root.size(); ++i)
    if (root[i] == i && used[i]) (volume[i] < 0 ? cavities : pieces) += 1;
}

/// Removes the triangles of every part `drop` marks (by its root vertex, as part_volumes gives `root`), and the
/// vertices only they used.
void remove_marked_parts(PrintableMesh& mesh, const std::vector<std::uint32_t>& root, const std::vector<char>& drop) {
  std::vector<std::array<std::uint32_t, 3>> kept;
  kept.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    if (!drop[root[t[0]]]) kept.push_back(t);
  mesh.triangles.swap(kept);
  drop_unused_vertices(mesh);
}

/// Removes every part whose signed volume `drop` accepts, and the vertices only they used; returns how many.
template <class Drop>
std::size_t remove_parts(PrintableMesh& mesh, Drop drop) {
  std::vector<std::uint32_t> root;
  const std::vector<double> part_volume = part_volumes(mesh, root);
  const std::size_t nv = mesh.vertices.size();
  std::vector<char> used(nv, 0), marked(nv, 0);
  for (const auto& t : mesh.triangles) used[root[t[0]]] = 1;
  std::size_t removed = 0;
  for (std::size_t i = 0; i < nv; ++i)
    if (used[i] && root[i] == i && drop(part_volume[i])) {
      marked[i] = 1;
      ++removed;
    }
  if (removed > 0) remove_marked_parts(mesh, root, marked);
  return removed;
}

}  // namespace

std::size_t fill_cavities(PrintableMesh& mesh, int threads) {
  // the parts, their volumes, boxes and triangles
  std::vector<std::uint32_t> root;
  const std::vector<double> volume = part_volumes(mesh, root);
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::vector<std::uint32_t>> tris_of(nv);  // by root vertex
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    tris_of[root[mesh.triangles[t][0]]].push_back(static_cast<std::uint32_t>(t));
  std::vector<std::uint32_t> cavities, islands;
  for (std::size_t i = 0; i < nv; ++i)
    if (root[i] == i && !tris_of[i].empty())
      (volume[i] < 0 ? cavities : islands).push_back(static_cast<std::uint32_t>(i));
  if (cavities.empty()) return 0;
  std::vector<Vec3> lo(nv), hi(nv);
  for (const std::uint32_t c : cavities) {
    lo[c] = hi[c] = mesh.vertices[c];
    for (const std::uint32_t t : tris_of[c])
      for (const std::uint32_t i : mesh.triangles[t]) {
        lo[c] = lo[c].cwiseMin(mesh.vertices[i]);
        hi[c] = hi[c].cwiseMax(mesh.vertices[i]);
      }
  }
  // A piece inside a cavity (a grain the shell's closing left in a pocket, the shell round a bubble inside a
  // closed sheet) would be a surface inside solid once the pocket is filled: it goes with the cavity's wall.
  // Inside: the cavity's wall winds round a point of it (solid angles, Van Oosterom and Strackee).
  std::vector<char> drop(nv, 0), inside(islands.size(), 0);
  for (const std::uint32_t c : cavities) drop[c] = 1;
  core::parallel_for(
      islands.size(), threads,
      [&](std::size_t b0, std::size_t e0) {  // each island writes its own slot
        for (std::size_t k = b0; k < e0; ++k) {
          const Vec3& q = mesh.vertices[islands[k]];
          for (const std::uint32_t c : cavities) {
            if ((q.array() < lo[c].array()).any() || (q.array() > hi[c].array()).any()) continue;
            double seen = 0;
            for (const std::uint32_t t : tris_of[c]) {
              const auto& tri = mesh.triangles[t];
              seen += solid_angle(mesh.vertices[tri[0]] - q, mesh.vertices[tri[1]] - q, mesh.vertices[tri[2]] - q);
            }
            if (std::abs(seen) > 2 * M_PI) {  // wound once (inward: -4 pi), not 0
              inside[k] = 1;
              break;
            }
          }
        }
      },
      1);
  std::size_t removed = cavities.size();
  for (std::size_t k = 0; k < islands.size(); ++k)
    if (inside[k]) {
      drop[islands[k]] = 1;
      ++removed;
    }
  remove_marked_parts(mesh, root, drop);
  return removed;
}

PrintableMesh mesh_level_set(const LevelSet& level_set, const ThickenParams& params, ThickenReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  check_params(params);
  const auto& grid = *level_set.impl().grid;
  const double voxel = level_set.voxel_size();
  // Two voxels' vertices that land at their shared corner make micrometre edges, and slivers that repair
  // tools flag: collapsed, where the self-intersection check below follows (adaptive meshing)
  const double shortest = params.adaptivity > 0 ? kShortestEdge * voxel : 0.0;
  PrintableMesh mesh;
  std::size_t repaired = 0, intersections = 0;
  core::with_threads(params.threads, [&] {
    report_progress(params, 0.0);
    // a flat base stays flat: the voxels within two of its plane are meshed without merging (merged
    // polygons there tilt up from the plane: a column's foot had 5.8 of its 36 mm2 on it)
    auto no_merge = std::make_shared<openvdb::BoolTree>(false);
    const double base_z = level_set.impl().base_z;
    if (std::isfinite(base_z) && params.adaptivity > 0) {
      const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
      const int z0 = static_cast<int>(std::floor(base_z / voxel)) - 2,
                z1 = static_cast<int>(std::ceil(base_z / voxel)) + 2;
      if (!box.empty())
        no_merge->sparseFill(openvdb::CoordBBox(openvdb::Coord(box.min().x(), box.min().y(), z0),
                                                openvdb::Coord(box.max().x(), box.max().y(), z1)),
                             true, true);
      no_merge->topologyIntersection(grid.tree());  // only where the grid has voxels: the foot, not its box
    }
    mesh = mesh_once(grid, params.adaptivity, no_merge->empty() ? nullptr : no_merge, shortest);
    report_progress(params, 0.5);
    if (params.adaptivity <= 0) return;  // uniform dual contouring: no folds seen in any test
    // Adaptive merging can fold triangles into each other at creases. Find every intersecting pair and
    // mesh the voxels around them again without merging, until none is left (at most a few passes; the
    // last merges nowhere). Each pass checks the whole mesh again: a changed mask changes the merging of
    // whole leaf nodes, and a fold 9 voxels from the re-meshed box once went unseen.
    auto pairs = self_intersecting_pairs(mesh, params.threads);
    for (int pass = 0; pass < 4 && !pairs.empty(); ++pass) {
      report_progress(params, 0.6 + 0.1 * pass);
      const double a = pass < 3 ? params.adaptivity : 0.0;  // last resort: no merging anywhere
      const int margin = 2 + 2 * pass;                      // voxels
      const auto box = [&](std::uint32_t t, int m) {
        Vec3 lo = mesh.vertices[mesh.triangles[t][0]], hi = lo;
        for (std::uint32_t i : mesh.triangles[t]) {
          lo = lo.cwiseMin(mesh.vertices[i]);
          hi = hi.cwiseMax(mesh.vertices[i]);
        }
        return openvdb::CoordBBox(openvdb::Coord(static_cast<int>(std::floor(lo.x() / voxel)) - m,
                                                 static_cast<int>(std::floor(lo.y() / voxel)) - m,
                                                 static_cast<int>(std::floor(lo.z() / voxel)) - m),
                                  openvdb::Coord(static_cast<int>(std::ceil(hi.x() / voxel)) + m,
                                                 static_cast<int>(std::ceil(hi.y() / voxel)) + m,
                                                 static_cast<int>(std::ceil(hi.z() / voxel)) + m));
      };
      std::vector<std::uint32_t> crossing;  // each triangle once, however many pairs it is in
      for (const auto& pr : pairs) crossing.insert(crossing.end(), pr.begin(), pr.end());
      std::sort(crossing.begin(), crossing.end());
      crossing.erase(std::unique(crossing.begin(), crossing.end()), crossing.end());
      for (const std::uint32_t t : crossing) no_merge->sparseFill(box(t, margin), true, true);
      repaired += crossing.size();
      mesh = mesh_once(grid, a, no_merge, a > 0 ? shortest : 0.0);  // the last resort changes nothing more
      pairs = self_intersecting_pairs(mesh, params.threads);
    }
    intersections = pairs.size();
  });
  report_progress(params, 1.0);
  // volumeToMesh winds level sets inward. Flip the whole mesh, never single parts: an inner wall of a
  // hollow part correctly has negative volume on its own.
  double volume = signed_volume(mesh);
  if (volume < 0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    volume = -volume;
  }
  // Dust: parts smaller than a voxel (a grain left in a pocket by the shell's closing) are no structure
  // and could not be printed.
  const double grain = voxel * voxel * voxel;
  const std::size_t dust = remove_parts(mesh, [grain](double v) { return std::abs(v) < grain; });
  if (dust > 0) volume = signed_volume(mesh);
  // Closed cavities inside the solid (thick capsules walling in a pocket, or a shell around a closed
  // sheet) mesh as separate parts of negative volume: they are not separate pieces. Filled on request.
  std::size_t cavities = 0, pieces = 0;
  count_pieces(mesh, pieces, cavities);
  if (params.fill_cavities && cavities > 0) {
    fill_cavities(mesh, params.threads);
    volume = signed_volume(mesh);
    std::size_t none = 0;
    count_pieces(mesh, pieces, none);  // less the pieces that lay in the pockets
  }
  if (intersections > 0 && (dust > 0 || (params.fill_cavities && cavities > 0)))  // of the mesh as written
    intersections = self_intersecting_pairs(mesh, params.threads).size();
  if (report) {
    report->pieces = pieces;
    report->cavities = cavities;
    report->filled_cavities = params.fill_cavities ? cavities : 0;
    report->dust_parts = dust;
    report->triangles = mesh.triangles.size();
    report->vertices = mesh.vertices.size();
    report->parts = count_parts(mesh);
    report->volume = volume;
    report->area = surface_area(mesh);
    report->remeshed_triangles = repaired;
    report->self_intersections = intersections;
    report->mesh_seconds = seconds_since(t0);
  }
  return mesh;
}

void write_vdb(const std::filesystem::path& path, const LevelSet& level_set) {
  init_openvdb();
  openvdb::GridPtrVec grids{level_set.impl().grid};
  std::ostringstream body;
  try {
    openvdb::io::Stream(body).write(grids);
  } catch (const openvdb::Exception& e) {
    throw core::FileError(path.string() + ": cannot write the level set: " + e.what());
  }
  std::string bytes = std::move(body).str();
  // OpenVDB stamps each file with a random UUID (36 characters after the 21-byte magic and version
  // header); it is made from the content instead, so the same level set gives the same file
  constexpr std::size_t kUuidAt = 21, kUuidLength = 36;
  auto dash_at = [&](std::size_t i) { return bytes[kUuidAt + i] == '-'; };
  if (bytes.size() > kUuidAt + kUuidLength && dash_at(8) && dash_at(13) && dash_at(18) && dash_at(23)) {
    const char* rest = bytes.data() + kUuidAt + kUuidLength;
    const std::size_t n = bytes.size() - kUuidAt - kUuidLength;
    const std::string hex =
        core::hex64(core::fnv1a64(rest, n)) + core::hex64(core::fnv1a64(rest, n, 0x9e3779b97f4a7c15ull));
    const std::string uuid = hex.substr(0, 8) + "-" + hex.substr(8, 4) + "-" + hex.substr(12, 4) + "-" +
                             hex.substr(16, 4) + "-" + hex.substr(20, 12);
    bytes.replace(kUuidAt, kUuidLength, uuid);
  }
  core::write_file_atomically(
      path, [&](std::ostream& os) { os.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

}  // namespace cellform::exporters
