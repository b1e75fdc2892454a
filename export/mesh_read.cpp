// Triangle-soup readers: STL (binary or ASCII), OBJ and PLY, for `cellform check` and the tests.
#include "export/mesh_read.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/polygon.h"
#include "export/mesh_check.h"
#include "forms/mesh_io.h"

namespace cellform::exporters {

using core::Vec3;
using Tri = std::array<std::uint32_t, 3>;

// binary STL and cellform's binary PLY are little-endian: the writers and readers copy values in host order
// (a big-endian PLY's values are byte-swapped as they are read)
static_assert(std::endian::native == std::endian::little, "cellform's binary files need a little-endian host");

namespace {

[[noreturn]] void malformed(const std::filesystem::path& path, const std::string& what) {
  throw core::FileError(path.string() + ": " + core::printable(what));  // `what` may quote the file's bytes
}

bool known_ply_type(const std::string& t) {
  for (const char* k : {"char", "uchar", "int8", "uint8", "short", "ushort", "int16", "uint16", "int", "uint", "float",
                        "int32", "uint32", "float32", "double", "float64"})
    if (t == k) return true;
  return false;
}

PrintableMesh weld_soup(std::vector<Vec3> corners) {  // 3 corners per triangle -> indexed, exact welding
  const std::vector<std::uint32_t> canon = weld_positions(corners);
  PrintableMesh m;
  std::vector<std::uint32_t> index(corners.size());
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (canon[i] == i) {
      index[i] = static_cast<std::uint32_t>(m.vertices.size());
      m.vertices.push_back(corners[i]);
    }
  }
  for (std::size_t i = 0; i < corners.size(); ++i) index[i] = index[canon[i]];
  m.triangles.resize(corners.size() / 3);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    m.triangles[t] = {index[3 * t], index[3 * t + 1], index[3 * t + 2]};
  return m;
}

/// Appends the triangles of a face (corners: indices into m.vertices, all in range): fanned if it is
/// convex, else cut by ear clipping in its plane, as an L-shaped n-gon needs; `where` and `number` ("line",
/// 12) name it in the error for a concave face too large to cut.
void add_face(PrintableMesh& m, std::span<const std::uint32_t> face, const std::filesystem::path& path,
              const char* where, std::size_t number) {
  if (face.size() == 3) {
    m.triangles.push_back({face[0], face[1], face[2]});
    return;
  }
  std::vector<Vec3> corners(face.size());
  for (std::size_t k = 0; k < face.size(); ++k) corners[k] = m.vertices[face[k]];
  bool too_large = false;
  const auto tris = core::triangulate_polygon(corners, &too_large);
  if (too_large)
    malformed(path, where + (" " + std::to_string(number)) + ": a face of " + std::to_string(face.size()) +
                        " corners that is not convex (over " + std::to_string(core::kMaxConcaveCorners) +
                        " such corners are not cut into triangles here); triangulate it in the modeller");
  for (const auto& t : tris) m.triangles.push_back({face[t[0]], face[t[1]], face[t[2]]});
}

template <class T>
T get(const std::string& s, std::size_t at) {
  T v;
  std::memcpy(&v, s.data() + at, sizeof(T));
  return v;
}

/// get() of a value stored big-endian (`big`) or little-endian.
template <class T>
T get_ordered(const std::string& s, std::size_t at, bool big) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, s.data() + at, sizeof(T));
  if (big != (std::endian::native == std::endian::big)) std::reverse(bytes, bytes + sizeof(T));
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

// Counts the stored facet normals of an STL (binary: `stored`, one per facet, else the ASCII "facet normal"
// lines in order, as forms::parse_ascii_stl reads them) that are non-zero and point against their facet's winding
// normal.
void count_stored_normals(const std::vector<Vec3>& corners, const std::vector<Vec3>& stored, MeshFileNotes& notes) {
  if (stored.size() * 3 != corners.size()) return;  // not one per facet: nothing to pair
  notes.normals_checked = true;
  for (std::size_t t = 0; t < stored.size(); ++t) {
    const Vec3& n = stored[t];
    if (!n.allFinite() || n.squaredNorm() == 0) continue;
    ++notes.stored_normals;
    const Vec3 w = (corners[3 * t + 1] - corners[3 * t]).cross(corners[3 * t + 2] - corners[3 * t]);
    if (n.dot(w) < 0) ++notes.normals_against_winding;
  }
}

PrintableMesh read_stl(const std::filesystem::path& path, const std::string& s, MeshFileNotes* notes) {
  if (s.size() >= 84) {
    std::uint32_t n = get<std::uint32_t>(s, 80);
    // a count left at 0 by an exporter that writes as it goes: the facets that fill the file exactly
    if (n == 0 && s.size() > 84 && (s.size() - 84) % 50 == 0 && (s.size() - 84) / 50 <= 0xFFFFFFFFu) {
      n = static_cast<std::uint32_t>((s.size() - 84) / 50);
      if (notes) notes->stl_count_zero = true;
    }
    // a few bytes after the last facet (some exporters pad the file) are ignored, as slicers do; as many as a
    // facet's 50 or more are no padding: the count would leave facets out
    const std::size_t expected = 84 + 50 * std::size_t{n};
    if (s.size() >= expected && s.size() < expected + 50 && (s.size() == expected || n > 0)) {
      if (notes) notes->stl_padding = s.size() - expected;
      std::vector<Vec3> corners(3 * std::size_t{n});
      for (std::size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
          const std::size_t at = 84 + 50 * t + 12 + 12 * k;
          corners[3 * t + k] = Vec3(get<float>(s, at), get<float>(s, at + 4), get<float>(s, at + 8));
        }
      if (n == 0) malformed(path, "no facets in the STL file");  // as for an empty ASCII STL
      for (std::size_t c = 0; c < corners.size(); ++c)           // named by facet: an STL has no vertex numbers
        if (!corners[c].allFinite())
          malformed(path, "facet " + std::to_string(c / 3 + 1) + " has a corner that is NaN or infinite");
      if (notes) {
        std::vector<Vec3> stored(n);
        for (std::size_t t = 0; t < n; ++t)
          stored[t] = Vec3(get<float>(s, 84 + 50 * t), get<float>(s, 84 + 50 * t + 4), get<float>(s, 84 + 50 * t + 8));
        count_stored_normals(corners, stored, *notes);
      }
      return weld_soup(std::move(corners));
    }
  }
  if (!forms::starts_like_ascii_stl(std::string_view(s).substr(0, 84))) {
    if (s.size() >= 84) {  // a binary header whose triangle count does not fit the file: truncated or padded
      const std::size_t n = get<std::uint32_t>(s, 80);
      malformed(path, "a damaged binary STL: its header announces " + std::to_string(n) +
                          (n == 1 ? " triangle (" : " triangles (") + std::to_string(84 + 50 * n) +
                          " bytes), but the file has " + std::to_string(s.size()) + " bytes");
    }
    malformed(path, "not an STL file (neither binary nor ASCII 'solid')");
  }
  std::vector<Vec3> corners, stored;
  try {
    corners = forms::parse_ascii_stl(s, notes ? &stored : nullptr);
  } catch (const core::InvalidInput& e) {
    malformed(path, std::string("malformed ASCII STL: ") + e.what());
  }
  if (corners.empty()) malformed(path, "no facets in the STL file");
  if (notes) count_stored_normals(corners, stored, *notes);
  return weld_soup(std::move(corners));
}

PrintableMesh read_obj(const std::filesystem::path& path, const std::string& s) {
  std::istringstream in(s);
  forms::ObjData obj;
  try {
    obj = forms::parse_obj(in);  // the obstacle loader's reader: a file both read is read the same
  } catch (const core::InvalidInput& e) {
    malformed(path, e.what());
  }
  PrintableMesh m;
  m.vertices = std::move(obj.positions);
  for (std::size_t f = 0, from = 0; f < obj.face_end.size(); from = obj.face_end[f++])
    add_face(m, std::span<const std::uint32_t>(obj.corners).subspan(from, obj.face_end[f] - from), path, "line",
             obj.face_line[f]);
  const bool lines = obj.polylines > 0;
  if (m.triangles.empty())
    malformed(path, lines ? "no faces in the OBJ file, only lines ('l'): a polyline graph such as veins.obj, not a "
                            "surface (check the printable.stl made from it)"
                          : "no faces in the OBJ file");
  return m;
}

PrintableMesh read_ply(const std::filesystem::path& path, const std::string& s) {
  struct Property {
    std::string name, type, count_type;  // count_type non-empty for lists
  };
  struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> props;
  };
  // where the line that holds the word end_header alone (spaces around it allowed) starts: a comment may name it
  std::size_t end = std::string::npos;
  for (std::size_t line = 0; line < s.size() && end == std::string::npos;) {
    const std::size_t next = std::min(s.find('\n', line), s.size());
    std::string_view words(s.data() + line, next - line);
    words.remove_prefix(std::min(words.find_first_not_of(" \t\r"), words.size()));
    words.remove_suffix(words.size() - std::min(words.find_last_not_of(" \t\r") + 1, words.size()));
    if (words == "end_header") end = line;
    line = next + 1;
  }
  if (s.rfind("ply", 0) != 0) malformed(path, "not a PLY file (it does not start with 'ply')");
  if (end == std::string::npos) malformed(path, "a PLY header with no 'end_header' line (a damaged or cut-off file)");
  std::istringstream head(s.substr(0, end));
  std::string line, format, format_version;
  std::vector<Element> elements;
  while (std::getline(head, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format")
      ls >> format >> format_version;
    else if (w == "element") {
      elements.push_back({});
      std::string count;
      ls >> elements.back().name >> count;
      // a count is a whole number (a "-1" read as a size_t would be 2^64 - 1)
      if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos)
        malformed(path, "PLY element '" + elements.back().name + "' has count '" + count +
                            "', which is not a whole number >= 0");
      if (count.size() - std::min(count.find_first_not_of('0'), count.size() - 1) > 12)  // (leading zeros aside)
        malformed(path, "PLY element '" + elements.back().name + "' has count " + count +
                            ", too large (at most 999999999999)");
      elements.back().count = std::stoull(count);  // at most 12 digits: the counts are checked against the size later
    } else if (w == "property") {
      if (elements.empty()) malformed(path, "PLY property before any element");
      Property p;
      ls >> p.type;
      if (p.type == "list") ls >> p.count_type >> p.type;
      ls >> p.name;
      elements.back().props.push_back(p);
    }
  }
  for (const Element& e : elements)  // ASCII data would read under any type name: checked for both forms
    for (const Property& p : e.props)
      for (const std::string& t : {p.type, p.count_type})
        if (!t.empty() && !known_ply_type(t)) malformed(path, "unknown PLY property type '" + t + "'");
  for (const Element& e : elements)  // a vertex without one of x, y, z would silently sit at 0 there
    if (e.name == "vertex")
      for (const char* axis : {"x", "y", "z"}) {
        const auto p = std::find_if(e.props.begin(), e.props.end(), [&](const Property& q) { return q.name == axis; });
        if (p == e.props.end()) malformed(path, std::string("PLY vertices have no '") + axis + "' property");
        if (!p->count_type.empty())  // read as a list, the coordinate would be lost
          malformed(path, std::string("PLY vertex property '") + axis + "' is a list, not one number");
      }
  const bool ascii = format == "ascii";
  const bool big = format == "binary_big_endian";
  if (!ascii && !big && format != "binary_little_endian")
    malformed(path, "PLY format '" + format + "' is not supported (ascii, binary_little_endian or binary_big_endian)");
  if (format_version != "1.0")  // the only PLY version there is; another may lay out its data otherwise
    malformed(path, "PLY version '" + format_version + "' is not supported (1.0)");
  std::size_t at = s.find('\n', end);
  if (at == std::string::npos) malformed(path, "PLY header not terminated");
  ++at;
  std::istringstream body(ascii ? s.substr(at) : std::string());
  std::istringstream row;   // ASCII: the line of the element being read (one line each)
  std::size_t line_no = 0;  // ASCII: its line in the file, counting from 1
  for (std::size_t k = 0; k < at; ++k) line_no += s[k] == '\n';
  // the element being read, for the errors in the data: "(in face 12 of 100, line 40)", counting from 1 as
  // the other messages do
  const std::string* elem = nullptr;
  std::size_t elem_index = 0, elem_count = 0;
  const auto in = [&] {
    return elem ? " (in " + *elem + " " + std::to_string(elem_index + 1) + " of " + std::to_string(elem_count) +
                      (ascii ? ", line " + std::to_string(line_no) : std::string()) + ")"
                : std::string();
  };
  const auto size_of = [&](const std::string& t) -> std::size_t {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    malformed(path, "unknown PLY property type '" + t + "'");
  };
  const auto read = [&](const std::string& t) -> double {
    if (ascii) {
      std::string word;
      if (!(row >> word))
        malformed(path, "PLY data: a line holds fewer values than its element's properties" + in() +
                            "; are the header's counts wrong?");
      // strtod, unlike >>, reads "nan" and "inf" (said as such below, with the vertex) and says what is no number
      char* stop = nullptr;
      const double v = std::strtod(word.c_str(), &stop);
      if (stop != word.c_str() + word.size())
        malformed(path, "PLY data: '" + word.substr(0, 40) + "' is not a number (ASCII PLY holds numbers only)" + in());
      return v;
    }
    const std::size_t n = size_of(t);
    if (at + n > s.size())
      malformed(path, "PLY data ends early" + in() + "; is the file truncated, or are the header's counts wrong?");
    double v = 0;
    if (t == "char" || t == "int8")
      v = get_ordered<std::int8_t>(s, at, big);
    else if (t == "uchar" || t == "uint8")
      v = get_ordered<std::uint8_t>(s, at, big);
    else if (t == "short" || t == "int16")
      v = get_ordered<std::int16_t>(s, at, big);
    else if (t == "ushort" || t == "uint16")
      v = get_ordered<std::uint16_t>(s, at, big);
    else if (t == "int" || t == "int32")
      v = get_ordered<std::int32_t>(s, at, big);
    else if (t == "uint" || t == "uint32")
      v = get_ordered<std::uint32_t>(s, at, big);
    else if (t == "float" || t == "float32")
      v = get_ordered<float>(s, at, big);
    else
      v = get_ordered<double>(s, at, big);
    at += n;
    return v;
  };
  std::size_t vertex_total = 0;  // from the header: faces may come before the vertices
  for (const Element& e : elements)
    if (e.name == "vertex") vertex_total += e.count;
  PrintableMesh m;
  std::vector<double> list;
  std::vector<std::uint32_t> faces;  // every face's corners in turn, face f ending at face_end[f]
  std::vector<std::size_t> face_end;
  for (const Element& e : elements)
    for (std::size_t i = 0; i < e.count && !e.props.empty(); ++i) {  // (no properties: no data, however many)
      elem = &e.name;
      elem_index = i;
      elem_count = e.count;
      if (ascii) {  // the next line that holds anything
        std::string text;
        bool got = false;
        while (!got && std::getline(body, text)) {
          ++line_no;
          got = text.find_first_not_of(" \t\r") != std::string::npos;
        }
        if (!got)
          malformed(path, "PLY data ends early" + in() + "; is the file truncated, or are the header's counts wrong?");
        row.clear();
        row.str(text);
      }
      Vec3 p = Vec3::Zero();
      for (const Property& pr : e.props) {
        if (pr.count_type.empty()) {
          const double v = read(pr.type);
          if (e.name == "vertex" && pr.name.size() == 1 && pr.name[0] >= 'x' && pr.name[0] <= 'z')
            p[pr.name[0] - 'x'] = v;
          continue;
        }
        const double n = read(pr.count_type);
        if (!(n >= 0 && n < 1e6)) malformed(path, "bad PLY list length" + in());
        list.resize(static_cast<std::size_t>(n));
        for (double& x : list) x = read(pr.type);
        if (e.name == "face" && (pr.name == "vertex_indices" || pr.name == "vertex_index")) {
          if (list.size() < 3) malformed(path, "PLY face with fewer than three vertices" + in());
          for (double x : list) {
            if (!(x >= 0 && x < 4294967295.0)) malformed(path, "PLY face index out of range" + in());
            if (x != std::floor(x))  // an index stored as a float type: not read as the vertex below it
              malformed(path, "PLY face index " + core::number_text(x) + " is not a whole number" + in());
            if (x >= static_cast<double>(vertex_total))
              malformed(path, "PLY face index " + std::to_string(static_cast<std::uint32_t>(x)) + " out of range (" +
                                  std::to_string(vertex_total) + " vertices)" + in());
          }
          // split once every vertex is read (a file may list its faces first)
          for (double x : list) faces.push_back(static_cast<std::uint32_t>(x));
          face_end.push_back(faces.size());
        }
      }
      if (e.name == "vertex") m.vertices.push_back(p);
      std::string extra;
      if (ascii && row >> extra)
        malformed(path, "PLY data: a line holds more values than its element's properties" + in() +
                            "; are the header's counts wrong?");
    }
  // what follows the declared elements: the header's counts are too small (blank space at the end is fine)
  std::size_t rest_from = at;  // binary: where the data ended
  if (ascii) {
    const std::streamoff read_to = body.tellg();  // -1 once the last line was read to the end
    rest_from = read_to < 0 ? s.size() : std::min(s.size(), at + static_cast<std::size_t>(read_to));
  }
  if (s.find_first_not_of(" \t\r\n", rest_from) != std::string::npos)
    malformed(path, "PLY data goes on after the elements the header declares (" + std::to_string(s.size() - rest_from) +
                        " bytes more); are the header's counts wrong?");
  for (const std::uint32_t i : faces)
    if (i >= m.vertices.size()) malformed(path, "PLY face index " + std::to_string(i) + " out of range");
  m.triangles.reserve(faces.size() - 2 * face_end.size());
  for (std::size_t f = 0, from = 0; f < face_end.size(); from = face_end[f++])
    add_face(m, std::span<const std::uint32_t>(faces).subspan(from, face_end[f] - from), path, "PLY face", f + 1);
  if (m.triangles.empty()) {
    const bool edges =
        std::any_of(elements.begin(), elements.end(), [](const Element& e) { return e.name == "edge" && e.count > 0; });
    malformed(path, edges ? "no faces in the PLY file, only edges: a polyline graph such as veins.ply, not a "
                            "surface (check the printable.stl made from it)"
                          : "no faces in the PLY file");
  }
  return m;
}

}  // namespace

PrintableMesh read_mesh(const std::filesystem::path& path) {
  MeshFileNotes notes;
  return read_mesh(path, notes);
}

PrintableMesh read_mesh(const std::filesystem::path& path, MeshFileNotes& notes) {
  notes = {};
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // read first: a missing file, a folder or a device is said as such (read_file reads regular files only)
  const std::string s = core::read_file(path);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply")
    throw core::FileError(path.string() +
                          (ext.empty() ? ": no file extension" : ": unknown mesh format '" + ext + "'") +
                          " (use .stl, .obj or .ply)");
  if (s.empty()) malformed(path, "the file is empty (0 bytes)");
  PrintableMesh m = ext == ".stl" ? read_stl(path, s, &notes) : ext == ".obj" ? read_obj(path, s) : read_ply(path, s);
  for (std::size_t i = 0; i < m.vertices.size(); ++i)  // unreadable input, not an unprintable shape
    if (!m.vertices[i].allFinite())
      malformed(path, "vertex " + std::to_string(i + 1) + " has a coordinate that is NaN or infinite");
    else if (m.vertices[i].cwiseAbs().maxCoeff() > 1e15)  // (their differences and products would overflow)
      malformed(path, "vertex " + std::to_string(i + 1) + " has a coordinate beyond 1e15 (the file's units; " +
                          "a printer's are millimetres): a damaged file?");
  return m;
}

}  // namespace cellform::exporters
