// Reading obstacle meshes (STL, OBJ) through OpenMesh's readers into a plain triangle soup.
#include <OpenMesh/Core/IO/MeshIO.hh>
// MeshIO.hh must come first: it registers the reader modules.
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>

#include "core/errors.h"
#include "forms/obstacles.h"

namespace cellform::forms {

namespace {

namespace fs = std::filesystem;
namespace om = OpenMesh;

// Collects what OpenMesh's readers report into flat arrays. Unlike a half-edge mesh it keeps every
// triangle, so non-manifold obstacle meshes lose no faces (a lost face would be a hole cells leak through).
class SoupImporter final : public om::IO::BaseImporter {
 public:
  TriangleMesh mesh;
  bool bad_index = false;

  om::VertexHandle add_vertex(const om::Vec3f& p) override { return push(Vec3(p[0], p[1], p[2])); }
  om::VertexHandle add_vertex(const om::Vec3d& p) override { return push(Vec3(p[0], p[1], p[2])); }
  om::VertexHandle add_vertex() override { return push(Vec3::Zero()); }

  om::FaceHandle add_face(const VHandles& ids) override {
    if (ids.size() < 3) return om::FaceHandle();
    for (const om::VertexHandle& vh : ids) {
      if (!vh.is_valid() || static_cast<std::size_t>(vh.idx()) >= mesh.vertices.size()) {
        bad_index = true;
        return om::FaceHandle();
      }
    }
    const int first = static_cast<int>(mesh.triangles.size());
    for (std::size_t k = 1; k + 1 < ids.size(); ++k)  // fan
      mesh.triangles.push_back(
          {static_cast<Index>(ids[0].idx()), static_cast<Index>(ids[k].idx()), static_cast<Index>(ids[k + 1].idx())});
    return om::FaceHandle(first);
  }

  void set_point(om::VertexHandle vh, const om::Vec3f& p) override {
    if (vh.is_valid() && static_cast<std::size_t>(vh.idx()) < mesh.vertices.size())
      mesh.vertices[static_cast<std::size_t>(vh.idx())] = Vec3(p[0], p[1], p[2]);
  }

  bool is_triangle_mesh() const override { return false; }
  void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
    mesh.vertices.reserve(std::min(nv, 1u << 26));
    mesh.triangles.reserve(std::min(nf, 1u << 26));
  }
  std::size_t n_vertices() const override { return mesh.vertices.size(); }
  std::size_t n_faces() const override { return mesh.triangles.size(); }
  std::size_t n_edges() const override { return 0; }

  // Everything else a reader may report (normals, colours, texture data, half-edge wiring) is not needed.
  om::HalfedgeHandle add_edge(om::VertexHandle, om::VertexHandle) override { return om::HalfedgeHandle(); }
  om::FaceHandle add_face(om::HalfedgeHandle) override { return om::FaceHandle(); }
  void add_face_texcoords(om::FaceHandle, om::VertexHandle, const std::vector<om::Vec2f>&) override {}
  void add_face_texcoords(om::FaceHandle, om::VertexHandle, const std::vector<om::Vec3f>&) override {}
  void set_face_texindex(om::FaceHandle, int) override {}
  void set_halfedge(om::VertexHandle, om::HalfedgeHandle) override {}
  void set_normal(om::VertexHandle, const om::Vec3f&) override {}
  void set_normal(om::VertexHandle, const om::Vec3d&) override {}
  void set_color(om::VertexHandle, const om::Vec3uc&) override {}
  void set_color(om::VertexHandle, const om::Vec4uc&) override {}
  void set_color(om::VertexHandle, const om::Vec3f&) override {}
  void set_color(om::VertexHandle, const om::Vec4f&) override {}
  void set_texcoord(om::VertexHandle, const om::Vec2f&) override {}
  void set_status(om::VertexHandle, const om::Attributes::StatusInfo&) override {}
  void set_next(om::HalfedgeHandle, om::HalfedgeHandle) override {}
  void set_face(om::HalfedgeHandle, om::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(om::HalfedgeHandle, const om::Vec2f&) override {}
  void set_texcoord(om::VertexHandle, const om::Vec3f&) override {}
  void set_texcoord(om::HalfedgeHandle, const om::Vec3f&) override {}
  void set_status(om::HalfedgeHandle, const om::Attributes::StatusInfo&) override {}
  void set_color(om::EdgeHandle, const om::Vec3uc&) override {}
  void set_color(om::EdgeHandle, const om::Vec4uc&) override {}
  void set_color(om::EdgeHandle, const om::Vec3f&) override {}
  void set_color(om::EdgeHandle, const om::Vec4f&) override {}
  void set_status(om::EdgeHandle, const om::Attributes::StatusInfo&) override {}
  void set_normal(om::FaceHandle, const om::Vec3f&) override {}
  void set_normal(om::FaceHandle, const om::Vec3d&) override {}
  void set_color(om::FaceHandle, const om::Vec3uc&) override {}
  void set_color(om::FaceHandle, const om::Vec4uc&) override {}
  void set_color(om::FaceHandle, const om::Vec3f&) override {}
  void set_color(om::FaceHandle, const om::Vec4f&) override {}
  void set_status(om::FaceHandle, const om::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  om::VertexHandle push(const Vec3& p) {
    mesh.vertices.push_back(p);
    return om::VertexHandle(static_cast<int>(mesh.vertices.size() - 1));
  }
};

// OpenMesh reports problems on its own log streams; library code must not print, so they are muted while
// a file is read and restored afterwards. The streams are process-wide, so readers take turns (a mutex):
// two overlapping reads would otherwise restore each other's state in the wrong order.
std::mutex& openmesh_log_mutex() {
  static std::mutex m;
  return m;
}

class MuteOpenMesh {
 public:
  MuteOpenMesh()
      : lock_(openmesh_log_mutex()),
        err_(::omerr().is_enabled()),
        out_(::omout().is_enabled()),
        log_(::omlog().is_enabled()) {
    ::omerr().disable();
    ::omout().disable();
    ::omlog().disable();
  }
  ~MuteOpenMesh() {
    if (err_) ::omerr().enable();
    if (out_) ::omout().enable();
    if (log_) ::omlog().enable();
  }
  MuteOpenMesh(const MuteOpenMesh&) = delete;
  MuteOpenMesh& operator=(const MuteOpenMesh&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
  bool err_, out_, log_;
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// A binary STL is exactly 84 + 50 n bytes for the n triangles its header announces. A file of another size is
// read as ASCII, which must start with "solid"; anything else is a damaged binary file.
void check_stl_size(std::istream& in, std::uintmax_t size, const std::string& name) {
  char head[84] = {};
  in.read(head, sizeof head);
  const auto got = static_cast<std::size_t>(in.gcount());
  in.clear();
  in.seekg(0);
  if (got < 84) {
    if (std::string(head, std::min<std::size_t>(got, 5)) != "solid")
      throw core::InvalidInput("mesh " + name +
                               " is not an STL file: too short for binary STL and does not start with 'solid'");
    return;
  }
  std::uint32_t n = 0;
  for (int k = 3; k >= 0; --k) n = (n << 8) | static_cast<unsigned char>(head[80 + k]);
  const std::uintmax_t expected = 84 + 50 * static_cast<std::uintmax_t>(n);
  if (size == expected || std::string(head, 5) == "solid") return;
  throw core::InvalidInput("mesh " + name + " is a damaged binary STL: its header announces " + std::to_string(n) +
                           " triangles (" + std::to_string(expected) + " bytes) but the file has " +
                           std::to_string(size) + " bytes");
}

// Lines of an OBJ file that define a vertex position ("v x y z"), to notice ones the reader had to skip.
std::size_t count_obj_vertex_lines(std::istream& in) {
  std::size_t count = 0;
  std::string line;
  while (std::getline(in, line)) {
    const auto start = line.find_first_not_of(" \t");
    if (start != std::string::npos && line.size() > start + 1 && line[start] == 'v' &&
        (line[start + 1] == ' ' || line[start + 1] == '\t'))
      ++count;
  }
  in.clear();
  in.seekg(0);
  return count;
}

}  // namespace

TriangleMesh load_mesh(const fs::path& path) {
  const std::string name = std::string(1, '\'').append(path.string()).append(1, '\'');
  const std::string ext = lower(path.extension().string());
  if (ext != ".stl" && ext != ".obj")
    throw core::InvalidInput("mesh " + name + ": unsupported format '" + path.extension().string() +
                             "'; allowed: .stl (ASCII or binary), .obj");
  std::error_code ec;
  if (!fs::exists(path, ec)) throw core::FileError("mesh " + name + " does not exist");
  if (fs::is_directory(path, ec)) throw core::FileError("mesh " + name + " is a directory, not a file");
  const auto size = fs::file_size(path, ec);
  std::ifstream probe(path, std::ios::binary);
  if (!probe || ec) throw core::FileError("mesh " + name + " cannot be opened for reading");
  if (size == 0) throw core::InvalidInput("mesh " + name + " is empty: not a mesh");
  if (ext == ".stl") check_stl_size(probe, size, name);
  const std::size_t vertex_lines = ext == ".obj" ? count_obj_vertex_lines(probe) : 0;
  probe.close();

  SoupImporter importer;
  bool ok = false;
  {
    MuteOpenMesh mute;
    om::IO::Options options;
    try {
      ok = om::IO::IOManager().read(path.string(), importer, options);
    } catch (const std::exception& e) {
      throw core::InvalidInput("mesh " + name + " could not be read: " + e.what());
    }
  }
  if (!ok) throw core::InvalidInput("mesh " + name + " is malformed: OpenMesh could not parse it as " + ext.substr(1));
  if (ext == ".obj" && importer.mesh.vertices.size() != vertex_lines)
    throw core::InvalidInput("mesh " + name + " is malformed: " +
                             std::to_string(vertex_lines - std::min(vertex_lines, importer.mesh.vertices.size())) +
                             " of " + std::to_string(vertex_lines) +
                             " vertex lines ('v x y z') are not three numbers (NaN and infinity are not allowed)");
  if (importer.bad_index)
    throw core::InvalidInput("mesh " + name + " is malformed: a face uses a vertex that does not exist");
  TriangleMesh mesh = std::move(importer.mesh);
  if (mesh.triangles.empty()) throw core::InvalidInput("mesh " + name + " has no triangles: not a mesh");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite())
      throw core::InvalidInput("mesh " + name + ": vertex " + std::to_string(i) +
                               " has a non-finite coordinate (NaN or infinity)");
  return mesh;
}

}  // namespace cellform::forms
