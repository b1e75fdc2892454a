// Writers for the vein graph.
#include "export/vein_files.h"

#include <bit>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/atomic_file.h"
#include "core/polylines.h"
#include "core/text.h"

namespace cellform::exporters {

// binary PLY and STL are little-endian; the writers and readers copy values in host order
static_assert(std::endian::native == std::endian::little, "cellform's binary files need a little-endian host");

namespace {
template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (x86-64, arm64), as the header says
  out.append(b, sizeof(T));
}
}  // namespace

void write_veins_ply(const std::filesystem::path& path, const venation::VeinGraph& g, const cells::Cells& cells) {
  std::string body;
  body.reserve(g.cell.size() * 40 + g.edges.size() * 8);
  for (std::size_t i = 0; i < g.cell.size(); ++i) {
    for (int k = 0; k < 3; ++k) put<double>(body, g.position[i][k]);  // (as cells.ply's, exact far out)
    put<float>(body, static_cast<float>(g.flow[i]));
    put<float>(body, static_cast<float>(g.radius[i]));
    put<std::int32_t>(body, g.order[i]);
    put<std::uint32_t>(body, static_cast<std::uint32_t>(cells.id[g.cell[i]]));
  }
  for (const auto& e : g.edges) {
    put<std::int32_t>(body, static_cast<std::int32_t>(e[0]));
    put<std::int32_t>(body, static_cast<std::int32_t>(e[1]));
  }
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment cellform vein graph, in model units (printable.* is in mm): edges "
      "run child -> parent\nelement vertex " +
      std::to_string(g.cell.size()) +
      "\nproperty double x\nproperty double y\nproperty double z\nproperty float flow\n"
      "property float radius\nproperty int order\nproperty uint id\n"
      "element edge " +
      std::to_string(g.edges.size()) + "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  core::write_file_atomically(path, [&](std::ostream& os) {
    os << header;
    os.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

void write_veins_obj(const std::filesystem::path& path, const venation::VeinGraph& g) {
  core::write_file_atomically(path, [&](std::ostream& os) {
    os << "# cellform vein graph: " << g.cell.size() << " nodes, " << g.edges.size()
       << " segments, in model units (a print{...} writes printable.* in mm, and run.json gives "
          "print.scale_mm_per_unit)\n"
       << "# per vertex: '#a flow radius order' follows its 'v' line\no veins\n";
    std::string out;
    // "v %.9g %.9g %.9g\n#a %.9g %.9g %d", with more digits for positions far from the origin
    const int digits = core::coordinate_digits(g.position);
    for (std::size_t i = 0; i < g.cell.size(); ++i) {
      out += 'v';
      for (double x : {g.position[i].x(), g.position[i].y(), g.position[i].z()}) {
        out += ' ';
        core::append_general(out, x, digits);
      }
      out += "\n#a ";
      core::append_general(out, g.flow[i]);
      out += ' ';
      core::append_general(out, g.radius[i]);
      out += ' ';
      core::append_integer(out, g.order[i]);
      out += '\n';
      core::drain(out, os);
    }
    for (const auto& line : core::polylines(g.cell.size(), g.edges)) {  // a curve per branch
      out += 'l';
      for (const core::Index v : line) {
        out += ' ';
        core::append_integer(out, v + 1);
      }
      out += '\n';
      core::drain(out, os);
    }
    core::drain(out, os, 0);
  });
}

}  // namespace cellform::exporters
