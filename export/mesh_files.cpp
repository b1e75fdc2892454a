// Writers for printable meshes.
#include "export/mesh_files.h"

#include <bit>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text.h"

namespace cellform::exporters {

using core::Vec3;

// binary PLY and STL are little-endian; the writers and readers copy values in host order
static_assert(std::endian::native == std::endian::little, "cellform's binary files need a little-endian host");

namespace {

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (x86-64, arm64)
  out.append(b, sizeof(T));
}

void put_vec(std::string& out, const Vec3& v) {
  put<float>(out, static_cast<float>(v.x()));
  put<float>(out, static_cast<float>(v.y()));
  put<float>(out, static_cast<float>(v.z()));
}

}  // namespace

void write_stl(const std::filesystem::path& path, const PrintableMesh& m) {
  if (m.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw core::InvalidInput(path.string() + ": " + std::to_string(m.triangles.size()) +
                             " triangles; a binary STL holds at most 4294967295 (write PLY or OBJ instead)");
  core::write_file_atomically(path, [&](std::ostream& os) {  // in pieces: 50 bytes a triangle
    std::string out = "binary STL from cellform, units: mm";
    out.resize(80, ' ');
    put<std::uint32_t>(out, static_cast<std::uint32_t>(m.triangles.size()));
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      put_vec(out, n.allFinite() ? n : Vec3::Zero());
      put_vec(out, a);
      put_vec(out, b);
      put_vec(out, c);
      put<std::uint16_t>(out, 0);
      core::drain(out, os);
    }
    core::drain(out, os, 0);
  });
}

void write_obj(const std::filesystem::path& path, const PrintableMesh& m) {
  core::write_file_atomically(path, [&](std::ostream& os) {
    std::string out = "# cellform printable mesh, units: mm\n# ";
    core::append_integer(out, m.vertices.size());
    out += " vertices, ";
    core::append_integer(out, m.triangles.size());
    out += " triangles\n";
    for (const Vec3& v : m.vertices) {  // "v %.9g %.9g %.9g"
      out += 'v';
      for (double x : {v.x(), v.y(), v.z()}) {
        out += ' ';
        core::append_general(out, x);
      }
      out += '\n';
      core::drain(out, os);
    }
    for (const auto& t : m.triangles) {
      out += 'f';
      for (std::uint32_t i : t) {
        out += ' ';
        core::append_integer(out, i + 1);
      }
      out += '\n';
      core::drain(out, os);
    }
    core::drain(out, os, 0);
  });
}

void write_ply(const std::filesystem::path& path, const PrintableMesh& m) {
  if (m.vertices.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw core::InvalidInput(path.string() + ": " + std::to_string(m.vertices.size()) +
                             " vertices; a PLY's 32-bit indices reach at most 2147483647 (write STL instead)");
  core::write_file_atomically(path, [&](std::ostream& os) {  // in pieces: 12 bytes a vertex, 13 a triangle
    std::string out =
        "ply\nformat binary_little_endian 1.0\ncomment cellform printable mesh, units: mm\nelement vertex " +
        std::to_string(m.vertices.size()) + "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
        std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& v : m.vertices) {
      put_vec(out, v);
      core::drain(out, os);
    }
    for (const auto& t : m.triangles) {
      put<std::uint8_t>(out, 3);
      for (std::uint32_t i : t) put<std::int32_t>(out, static_cast<std::int32_t>(i));
      core::drain(out, os);
    }
    core::drain(out, os, 0);
  });
}

void write_scad(const std::filesystem::path& path, const PrintableMesh& m) {
  core::write_file_atomically(path, [&](std::ostream& os) {
    std::string out =
        "// cellform printable mesh, units: mm. Render: openscad -o out.stl this.scad\npolyhedron(points = [\n";
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {  // "[%.9g,%.9g,%.9g]"
      const Vec3& v = m.vertices[i];
      out += '[';
      core::append_general(out, v.x());
      out += ',';
      core::append_general(out, v.y());
      out += ',';
      core::append_general(out, v.z());
      out += i + 1 < m.vertices.size() ? "],\n" : "]\n";
      core::drain(out, os);
    }
    out += "], faces = [\n";
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const auto& t = m.triangles[i];
      out += '[';
      core::append_integer(out, t[0]);
      out += ',';
      core::append_integer(out, t[2]);
      out += ',';
      core::append_integer(out, t[1]);
      out += i + 1 < m.triangles.size() ? "],\n" : "]\n";
      core::drain(out, os);
    }
    out += "], convexity = 10);\n";
    core::drain(out, os, 0);
  });
}

void write_mesh(const std::filesystem::path& path, const PrintableMesh& mesh) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".stl")
    write_stl(path, mesh);
  else if (ext == ".obj")
    write_obj(path, mesh);
  else if (ext == ".ply")
    write_ply(path, mesh);
  else if (ext == ".scad")
    write_scad(path, mesh);
  else
    throw core::InvalidInput(path.string() + ": unknown mesh format '" + ext + "' (use .stl, .obj, .ply or .scad)");
}

}  // namespace cellform::exporters
