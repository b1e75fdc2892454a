// Reading obstacle meshes: ASCII STL and OBJ with strict parsers of their own, binary STL through OpenMesh's
// reader, into a plain triangle soup.
#include "forms/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
// MeshIO.hh must come first: it registers the reader modules.
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "core/polygon.h"
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
  std::vector<Index> faces;  // every face's corners in turn, face f ending at face_end[f]
  std::vector<std::size_t> face_end;

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
    for (const om::VertexHandle& vh : ids) faces.push_back(static_cast<Index>(vh.idx()));
    face_end.push_back(faces.size());
    return om::FaceHandle(static_cast<int>(face_end.size() - 1));
  }

  /// The faces as triangles, once every point is set: fanned if convex, else cut by ear clipping in
  /// their plane (an L-shaped n-gon). InvalidInput naming the mesh for a concave face too large to cut.
  void split_faces(const std::string& name) {
    std::vector<Vec3> corners;
    for (std::size_t f = 0, from = 0; f < face_end.size(); from = face_end[f++]) {
      corners.clear();
      for (std::size_t k = from; k < face_end[f]; ++k) corners.push_back(mesh.vertices[faces[k]]);
      bool too_large = false;
      const auto tris = core::triangulate_polygon(corners, &too_large);
      if (too_large)
        throw core::InvalidInput("mesh " + name + ": face " + std::to_string(f + 1) + " has " +
                                 std::to_string(corners.size()) + " corners and is not convex (over " +
                                 std::to_string(core::kMaxConcaveCorners) +
                                 " such corners are not cut into triangles here); triangulate it in the modeller");
      for (const auto& t : tris) mesh.triangles.push_back({faces[from + t[0]], faces[from + t[1]], faces[from + t[2]]});
    }
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
  std::size_t n_faces() const override { return face_end.size(); }
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

// A binary STL is exactly 84 + 50 n bytes for the n triangles its header announces (as OpenMesh, which reads
// it, decides; the exporters' reader, for `cellform check`, also takes up to 49 bytes of padding), and true is
// returned. A file of another size is ASCII, which
// must start with "solid"; anything else is a damaged binary file.
bool is_binary_stl(std::istream& in, std::uintmax_t size, const std::string& name) {
  char head[84] = {};
  in.read(head, sizeof head);
  const auto got = static_cast<std::size_t>(in.gcount());
  in.clear();
  in.seekg(0);
  if (got < 84) {
    if (!starts_like_ascii_stl(std::string_view(head, got)))
      throw core::InvalidInput("mesh " + name +
                               " is not an STL file: too short for binary STL and does not start with 'solid'");
    return false;
  }
  std::uint32_t n = 0;
  for (int k = 3; k >= 0; --k) n = (n << 8) | static_cast<unsigned char>(head[80 + k]);
  const std::uintmax_t expected = 84 + 50 * static_cast<std::uintmax_t>(n);
  if (size == expected) return true;
  if (n == 0 && (size - 84) % 50 == 0) return true;  // a count left at 0 by an exporter: read by the size (load_mesh)
  if (starts_like_ascii_stl(std::string_view(head, got))) return false;
  // a few bytes after the last facet (some exporters pad the file) are ignored, as slicers and `cellform check`
  // do; as many as a facet's 50 or more are no padding: the count would leave facets out
  if (n > 0 && size > expected && size < expected + 50) return true;
  throw core::InvalidInput("mesh " + name + " is a damaged binary STL: its header announces " + std::to_string(n) +
                           (n == 1 ? " triangle (" : " triangles (") + std::to_string(expected) +
                           " bytes) but the file has " + std::to_string(size) + " bytes");
}

// Every corner of a binary STL (`size` bytes, its layout checked) finite; names the first that is not.
// Reads 50-byte records in blocks: the file is not held twice beside OpenMesh's mesh.
void check_binary_stl_corners(std::istream& in, std::uintmax_t size, const std::string& name) {
  constexpr std::size_t kRecord = 50, kBlock = 4096;
  const auto triangles = static_cast<std::size_t>((size - 84) / kRecord);
  std::vector<char> block(kRecord * kBlock);
  in.seekg(84);
  for (std::size_t first = 0; first < triangles; first += kBlock) {
    const std::size_t count = std::min(kBlock, triangles - first);
    in.read(block.data(), static_cast<std::streamsize>(count * kRecord));
    if (in.gcount() != static_cast<std::streamsize>(count * kRecord))
      throw core::FileError("mesh " + name + " could not be read");
    for (std::size_t t = 0; t < count; ++t)
      for (int k = 0; k < 9; ++k) {  // the three corners after the normal
        float x;
        std::memcpy(&x, block.data() + kRecord * t + 12 + 4 * k, 4);
        if (!std::isfinite(x))
          throw core::InvalidInput("mesh " + name + ": triangle " + std::to_string(first + t + 1) +
                                   " has a corner with a coordinate that is NaN or infinite");
      }
  }
  in.clear();
  in.seekg(0);
}

// An ASCII STL as a mesh: corners at exactly the same position become one vertex and facets with a repeated
// corner are dropped, as OpenMesh's binary reader does (a surface needs the shared vertices).
TriangleMesh read_ascii_stl(std::istream& in, const std::string& name) {
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::vector<Vec3> corners;
  try {
    corners = parse_ascii_stl(text);
  } catch (const core::InvalidInput& e) {
    throw core::InvalidInput("mesh " + name + " is malformed: " + e.what());
  }
  TriangleMesh mesh;
  std::map<std::array<double, 3>, Index> seen;
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
    std::array<Index, 3> tri{};
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3& p = corners[t + k];
      const auto [it, added] = seen.try_emplace({p.x(), p.y(), p.z()}, static_cast<Index>(mesh.vertices.size()));
      if (added) mesh.vertices.push_back(p);
      tri[k] = it->second;
    }
    if (tri[0] != tri[1] && tri[0] != tri[2] && tri[1] != tri[2]) mesh.triangles.push_back(tri);
  }
  return mesh;
}

// The mesh if it has triangles and finite vertices; names the file otherwise (`polylines`: its OBJ 'l' lines).
TriangleMesh checked(TriangleMesh mesh, const std::string& name, std::size_t polylines = 0) {
  if (mesh.triangles.empty() && polylines > 0)
    throw core::InvalidInput("mesh " + name +
                             " has no triangles, only lines ('l'): a polyline graph such as veins.obj, not a surface "
                             "(use the printable.stl made from it)");
  if (mesh.triangles.empty()) throw core::InvalidInput("mesh " + name + " has no triangles: not a mesh");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite())
      throw core::InvalidInput("mesh " + name + ": vertex " + std::to_string(i) +
                               " has a non-finite coordinate (NaN or infinity)");
  return mesh;
}

}  // namespace

ObjData parse_obj(std::istream& in) {
  ObjData obj;
  std::size_t line_no = 0;
  std::string line;
  while (std::getline(in, line)) {
    if (++line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
    // a line ending in a backslash goes on on the next, as the format allows (an error names the last); not one
    // ending in a comment ("# from C:\\models\\" took the next line with it)
    for (std::string next; !line.empty() && line.find('#') == std::string::npos;) {
      const std::size_t end = line.back() == '\r' ? line.size() - 1 : line.size();
      if (end == 0 || line[end - 1] != '\\' || !std::getline(in, next)) break;
      line.replace(end - 1, std::string::npos, " " + next);
      ++line_no;
    }
    std::istringstream words(line);
    std::string tag;
    if (!(words >> tag)) continue;
    if (tag == "v") {
      double xyz[3];
      std::string word;
      bool good = true;
      for (double& c : xyz) {
        good = good && static_cast<bool>(words >> word);
        if (!good) break;
        char* end = nullptr;
        c = std::strtod(word.c_str(), &end);
        // the whole word (a NUL byte ended it early), or "v 0 0 0#note"
        good = (end == word.c_str() + word.size() || (&c == &xyz[2] && *end == '#')) && std::isfinite(c);
      }
      if (!good)
        throw core::InvalidInput("line " + std::to_string(line_no) + ": '" + core::printable(line.substr(0, 60)) +
                                 (line.size() > 60 ? "..." : "") +
                                 "' is not a vertex of three finite numbers ('v x y z'; NaN and infinity are not "
                                 "allowed)");
      obj.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
    } else if (tag == "l") {
      ++obj.polylines;
    } else if (tag == "f") {
      std::string token;
      const std::size_t from = obj.corners.size();
      while (words >> token && token[0] != '#') {  // a comment may end the line
        try {
          obj.corners.push_back(obj_face_vertex(token, obj.positions.size()));
        } catch (const core::InvalidInput& e) {
          throw core::InvalidInput("line " + std::to_string(line_no) + ": " + e.what());
        }
      }
      if (obj.corners.size() - from < 3)
        throw core::InvalidInput("line " + std::to_string(line_no) +
                                 ": a face needs at least three vertices ('f a b c')");
      obj.face_end.push_back(obj.corners.size());
      obj.face_line.push_back(line_no);
    }
  }
  if (in.bad()) throw core::FileError("the file could not be read to its end");
  return obj;
}

std::uint32_t obj_face_vertex(std::string_view token, std::size_t vertices) {
  const auto bad = [&](const std::string& why) {
    return core::InvalidInput("bad face vertex '" + core::printable(token.substr(0, 40)) +
                              (token.size() > 40 ? "..." : "") + "': " + why);
  };
  const std::size_t slash = token.find('/');
  const std::string_view v = token.substr(0, slash);
  // the texture and normal indices are not used, but must be whole numbers if given
  for (const char c : slash == std::string_view::npos ? std::string_view{} : token.substr(slash + 1))
    if (c != '/' && c != '-' && (c < '0' || c > '9'))
      throw bad("expected whole numbers, as in 'f 1 2 3' or 'f 1/1/1 ...'");
  const bool negative = !v.empty() && v[0] == '-';
  const std::string_view digits = v.substr(negative ? 1 : 0);
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string_view::npos)
    throw bad("a vertex index is a whole number, as in 'f 1 2 3'");
  const std::string_view significant = digits.substr(std::min(digits.find_first_not_of('0'), digits.size()));
  std::uint64_t k = ~std::uint64_t{0};
  if (significant.size() <= 18) {
    k = 0;
    for (const char c : significant) k = 10 * k + static_cast<std::uint64_t>(c - '0');
  }
  if (k == 0) throw bad("vertex indices count from 1 (or back from -1)");
  if (k > vertices)
    throw bad(std::string(negative ? "counts back past the first of the " : "there are only ") +
              std::to_string(vertices) + " vertices before it");
  return static_cast<std::uint32_t>(negative ? vertices - k : k - 1);
}

bool starts_like_ascii_stl(std::string_view head) {
  if (head.find('\0') != std::string_view::npos) return false;
  if (head.substr(0, 3) == "\xEF\xBB\xBF") head.remove_prefix(3);
  head.remove_prefix(std::min(head.find_first_not_of(" \t\r\n\f\v"), head.size()));
  if (head.size() < 5) return false;
  for (std::size_t k = 0; k < 5; ++k)
    if (std::tolower(static_cast<unsigned char>(head[k])) != "solid"[k]) return false;
  return head.size() == 5 || std::isspace(static_cast<unsigned char>(head[5]));
}

std::vector<Vec3> parse_ascii_stl(std::string_view text, std::vector<Vec3>* normals) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);    // a UTF-8 byte-order mark
  enum class Expect { solid, facet, outer, vertex, endfacet, end };  // what the next line may be
  Expect expect = Expect::solid;
  std::vector<Vec3> corners;
  int in_facet = 0;                                        // vertices of the facet being read
  std::size_t line_no = 0, last_line = 0, facet_line = 0;  // last_line: the last one that is not blank
  std::vector<std::string_view> words;
  for (std::size_t at = 0; at <= text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++line_no;
    words.clear();
    for (std::size_t i = 0; i < line.size();) {
      const std::size_t b = line.find_first_not_of(" \t\r\f\v", i);
      if (b == std::string_view::npos) break;
      const std::size_t e = std::min(line.find_first_of(" \t\r\f\v", b), line.size());
      words.push_back(line.substr(b, e - b));
      i = e;
    }
    if (words.empty()) continue;
    last_line = line_no;
    auto fail = [&](const std::string& what) {
      std::string shown(line.substr(0, 80));
      while (!shown.empty() && std::isspace(static_cast<unsigned char>(shown.back()))) shown.pop_back();
      shown.erase(0, std::min(shown.find_first_not_of(" \t"), shown.size()));
      return core::InvalidInput("line " + std::to_string(line_no) + ": " + what + " (the line reads '" +
                                core::printable(shown) + "')");  // (a NUL byte would end the message there)
    };
    // a number, all of the word ("1e-3", "-2", "+0.5"; "5five" is not one); one too small for a double is 0
    // or the nearest, as strtod (the OBJ reader's) reads it, and one too large is refused by name
    bool too_large = false;
    auto number = [&too_large](std::string_view w, double& x) {
      if (w.size() > 1 && w[0] == '+' && w[1] != '-') w.remove_prefix(1);
      const auto r = std::from_chars(w.data(), w.data() + w.size(), x);
      if (r.ptr != w.data() + w.size()) return false;
      if (r.ec == std::errc::result_out_of_range) {
        x = std::strtod(std::string(w).c_str(), nullptr);
        too_large = too_large || std::isinf(x);
        return !std::isinf(x);
      }
      return r.ec == std::errc();
    };
    const char* kTooLarge = "; one is beyond the range of 64-bit numbers, about 1.8e308";
    // word i is this keyword, in any case
    auto is = [&](std::size_t i, std::string_view keyword) {
      if (i >= words.size() || words[i].size() != keyword.size()) return false;
      for (std::size_t k = 0; k < keyword.size(); ++k)
        if (std::tolower(static_cast<unsigned char>(words[i][k])) != keyword[k]) return false;
      return true;
    };
    switch (expect) {
      case Expect::solid:
      case Expect::end:
        if (!is(0, "solid"))
          throw fail(expect == Expect::solid ? "an ASCII STL starts with 'solid'"
                                             : "expected 'solid' or the end of the file after 'endsolid'");
        expect = Expect::facet;  // the rest of the line is the solid's name
        break;
      case Expect::facet:
        if (is(0, "endsolid")) {
          expect = Expect::end;
          break;
        }
        if (!is(0, "facet")) throw fail("expected 'facet normal nx ny nz' or 'endsolid'");
        {
          Vec3 n;
          if (!is(1, "normal") || words.size() != 5 || !number(words[2], n.x()) || !number(words[3], n.y()) ||
              !number(words[4], n.z()))
            throw fail(std::string("a facet starts with 'facet normal' and three numbers") +
                       (too_large ? kTooLarge : ""));
          if (normals) normals->push_back(n);
        }
        facet_line = line_no;
        expect = Expect::outer;
        break;
      case Expect::outer:
        if (!(is(0, "outer") && is(1, "loop") && words.size() == 2)) throw fail("expected 'outer loop'");
        in_facet = 0;
        expect = Expect::vertex;
        break;
      case Expect::vertex:
        if (is(0, "endloop") && words.size() == 1) {
          if (in_facet != 3)
            throw fail("the facet of line " + std::to_string(facet_line) + " has " + std::to_string(in_facet) +
                       " vertices; a facet needs exactly three vertices");
          expect = Expect::endfacet;
          break;
        }
        if (!is(0, "vertex")) throw fail("expected 'vertex x y z' or 'endloop'");
        if (in_facet == 3)
          throw fail("a fourth vertex in the facet of line " + std::to_string(facet_line) +
                     "; a facet needs exactly three vertices");
        {
          Vec3 p;
          if (words.size() != 4 || !number(words[1], p.x()) || !number(words[2], p.y()) || !number(words[3], p.z()))
            throw fail(std::string("a vertex needs three numbers") + (too_large ? kTooLarge : ""));
          if (!p.allFinite()) throw fail("a vertex needs three finite numbers (NaN and infinity are not allowed)");
          corners.push_back(p);
        }
        ++in_facet;
        break;
      case Expect::endfacet:
        if (!(is(0, "endfacet") && words.size() == 1)) throw fail("expected 'endfacet'");
        expect = Expect::facet;
        break;
    }
  }
  if (expect == Expect::solid) throw core::InvalidInput("line 1: an ASCII STL starts with 'solid'; the file is blank");
  if (expect == Expect::outer || expect == Expect::vertex || expect == Expect::endfacet)
    throw core::InvalidInput("line " + std::to_string(last_line) + ": the file ends inside the facet of line " +
                             std::to_string(facet_line) + " (cut short?)");
  if (expect == Expect::facet)
    throw core::InvalidInput("line " + std::to_string(last_line) + ": the file ends without 'endsolid' (cut short?)");
  return corners;
}

TriangleMesh load_mesh(const fs::path& path) {
  const std::string name = std::string(1, '\'').append(path.string()).append(1, '\'');
  const std::string ext = lower(path.extension().string());
  if (std::error_code dir; fs::is_directory(path, dir))
    throw core::FileError("mesh " + name + " is a directory, not a file");
  if (ext != ".stl" && ext != ".obj")
    throw core::InvalidInput("mesh " + name + ": unsupported format '" + path.extension().string() +
                             "'; allowed: .stl (ASCII or binary), .obj");
  std::error_code ec;
  if (!fs::exists(path, ec))  // a name too long or a loop of links is not "missing"
    throw core::FileError("mesh " + name + (ec ? " cannot be read: " + ec.message() : std::string(" does not exist")));
  // a pipe would block the run for good, a device such as /dev/zero never ends: only regular files are read
  if (!fs::is_regular_file(path, ec))
    throw core::FileError("mesh " + name + " is not a regular file (a pipe, socket or device cannot be read)");
  const auto size = fs::file_size(path, ec);
  std::ifstream probe(path, std::ios::binary);
  if (!probe || ec) throw core::FileError("mesh " + name + " cannot be opened for reading");
  if (size == 0) throw core::InvalidInput("mesh " + name + " is empty: not a mesh");
  // OpenMesh reads ASCII STL leniently (a bad number keeps the previous one, a cut file is a smaller mesh)
  if (ext == ".stl" && !is_binary_stl(probe, size, name)) return checked(read_ascii_stl(probe, name), name);
  if (ext == ".stl") check_binary_stl_corners(probe, size, name);  // OpenMesh drops such triangles unsaid
  SoupImporter importer;
  std::size_t polylines = 0;
  if (ext == ".obj") {
    ObjData obj;
    try {
      obj = parse_obj(probe);
    } catch (const core::InvalidInput& e) {
      throw core::InvalidInput("mesh " + name + " is malformed: " + e.what());
    } catch (const core::FileError& e) {
      throw core::FileError("mesh " + name + ": " + e.what());
    }
    importer.mesh.vertices = std::move(obj.positions);
    importer.faces = std::move(obj.corners);
    importer.face_end = std::move(obj.face_end);
    polylines = obj.polylines;
  } else {
    // OpenMesh tells a binary STL by its size and reads as many facets as its header says: a padded one is given its
    // facets alone, and one whose count was left at 0 (is_binary_stl) the count they make
    const std::uintmax_t facets = 84 + 50 * ((size - 84) / 50);
    char count[4] = {};
    probe.seekg(80);
    probe.read(count, 4);
    const bool unset = probe && count[0] == 0 && count[1] == 0 && count[2] == 0 && count[3] == 0 && size > 84;
    std::string padded;
    if (facets != size || unset) {
      padded.resize(facets);
      probe.clear();
      probe.seekg(0);
      if (!probe.read(padded.data(), static_cast<std::streamsize>(facets)))
        throw core::FileError("mesh " + name + " could not be read to its end");
      for (std::uintmax_t n = (size - 84) / 50, k = 80; unset && k < 84; ++k, n >>= 8)
        padded[k] = static_cast<char>(n & 0xFF);
    }
    probe.close();
    bool ok = false;
    MuteOpenMesh mute;
    om::IO::Options options(om::IO::Options::Binary);
    try {
      std::istringstream in(padded);
      ok = padded.empty() ? om::IO::IOManager().read(path.string(), importer, options)
                          : om::IO::IOManager().read(in, "stl", importer, options);
    } catch (const std::exception& e) {
      throw core::InvalidInput("mesh " + name + " could not be read: " + e.what());
    }
    if (!ok) throw core::InvalidInput("mesh " + name + " is malformed: OpenMesh could not parse it as a binary STL");
    if (importer.bad_index)
      throw core::InvalidInput("mesh " + name + " is malformed: a face uses a vertex that does not exist");
  }
  importer.split_faces(name);
  return checked(std::move(importer.mesh), name, polylines);
}

}  // namespace cellform::forms
