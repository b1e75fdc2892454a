// PLY (binary) and OBJ writers for the cell sheet; every write is atomic.
#include "export/cell_files.h"

#include "venation/canalisation.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text.h"

namespace cellform::exporters {

namespace {

using cells::Cells;
using cells::Surface;
using core::Index;

// Refuses to write a file whose connectivity or attributes do not match the cells.
void check_consistent(const std::filesystem::path& path, const Cells& cells, const Surface& surface) {
  const std::size_t n = cells.size();
  const auto where = "cannot write '" + path.string() + "': ";
  if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw core::InvalidInput(where + "too many cells for 32-bit vertex indices");
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    for (Index v : surface.triangles[t])
      if (v >= n)
        throw core::InvalidInput(where + "triangle " + std::to_string(t) + " uses cell " + std::to_string(v) + " of " +
                                 std::to_string(n));
  for (std::size_t e = 0; e < surface.edges.size(); ++e)
    for (Index v : surface.edges[e])
      if (v >= n)
        throw core::InvalidInput(where + "edge " + std::to_string(e) + " uses cell " + std::to_string(v) + " of " +
                                 std::to_string(n));
  for (const auto& [name, values] : cells.attributes)
    if (values.size() != n)
      throw core::InvalidInput(where + "attribute '" + name + "' has " + std::to_string(values.size()) +
                               " values for " + std::to_string(n) + " cells");
}

// Appends `value` to `out` in little-endian byte order, whatever the host order.
template <class T>
void put(std::string& out, T value) {
  static_assert(std::is_trivially_copyable_v<T>);
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

std::string sanitise(const std::string& raw) {
  std::string s;
  for (unsigned char c : raw) s += (std::isalnum(c) || c == '_') && c < 128 ? static_cast<char>(c) : '_';
  if (s.empty()) s = "attribute";
  if (std::isdigit(static_cast<unsigned char>(s[0]))) s.insert(s.begin(), '_');
  return s;
}

// PLY property names of the attributes, in cells.attributes order, distinct from each other and the fixed ones.
std::vector<std::string> attribute_names(const Cells& cells) {
  std::set<std::string> taken = {"x", "y", "z", "type", "age", "generation", "id", "fixed"};
  std::vector<std::string> names;
  for (const auto& entry : cells.attributes) {
    const std::string base = sanitise(entry.first);
    std::string name = base;
    for (int k = 2; taken.count(name); ++k) name = base + "_" + std::to_string(k);
    taken.insert(name);
    names.push_back(name);
  }
  return names;
}

}  // namespace

void write_cells_ply(const std::filesystem::path& path, const Cells& cells, const Surface& surface) {
  check_consistent(path, cells, surface);
  const std::size_t n = cells.size();
  const std::vector<std::string> names = attribute_names(cells);

  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment cellform cell sheet, in model units (printable.* is in mm)\n";
  header += "comment id is the low 32 bits of the 64-bit cell id\n";
  header += "comment type: 0 general, 1 petiole, 2 vein\n";
  header += "element vertex " + std::to_string(n) + "\n";
  // positions as doubles: a form placed at site coordinates (millions of units out) keeps them exactly, and every
  // frame of a sequence has one layout (floats snapped such cells to a grid of a quarter unit)
  header += "property double x\nproperty double y\nproperty double z\n";
  header += "property uchar type\nproperty uint age\nproperty uint generation\nproperty uint id\n";
  header += "property uchar fixed\n";
  // vein order is a whole number (1 = primary); every other attribute is written as a float
  std::vector<const std::vector<double>*> columns;
  std::vector<char> whole_column;
  for (const auto& entry : cells.attributes) {
    columns.push_back(&entry.second);
    whole_column.push_back(entry.first == venation::kOrder ? 1 : 0);
  }
  for (std::size_t k = 0; k < names.size(); ++k)
    header += (whole_column[k] ? "property int " : "property float ") + names[k] + "\n";
  header += "element face " + std::to_string(surface.triangles.size()) + "\n";
  header += "property list uchar int vertex_indices\n";
  header += "element edge " + std::to_string(surface.edges.size()) + "\n";
  header += "property int vertex1\nproperty int vertex2\n";
  header += "end_header\n";

  std::string body;
  body.reserve(n * (34 + 4 * columns.size()) + surface.triangles.size() * 13 + surface.edges.size() * 8);
  for (std::size_t i = 0; i < n; ++i) {
    const core::Vec3& p = cells.position[i];
    for (int k = 0; k < 3; ++k) put(body, p[k]);
    put(body, static_cast<std::uint8_t>(cells.type[i]));
    put(body, cells.age[i]);
    put(body, cells.generation[i]);
    put(body, static_cast<std::uint32_t>(cells.id[i] & 0xffffffffu));
    put(body, static_cast<std::uint8_t>(cells.fixed[i] ? 1 : 0));
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const double v = (*columns[k])[i];
      if (whole_column[k])
        put(body, static_cast<std::int32_t>(std::isfinite(v) && std::abs(v) < 2e9 ? std::llround(v) : 0));
      else
        put(body, static_cast<float>(v));
    }
  }
  for (const auto& t : surface.triangles) {
    put(body, std::uint8_t{3});
    for (Index v : t) put(body, static_cast<std::int32_t>(v));
  }
  for (const auto& e : surface.edges) {
    put(body, static_cast<std::int32_t>(e[0]));
    put(body, static_cast<std::int32_t>(e[1]));
  }

  core::write_file_atomically(path, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

void write_cells_obj(const std::filesystem::path& path, const Cells& cells, const Surface& surface) {
  check_consistent(path, cells, surface);
  const std::size_t n = cells.size();

  // Links that are a side of some triangle are drawn by the faces already.
  std::unordered_set<std::uint64_t> sides;
  const auto key = [](Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
  };
  for (const auto& t : surface.triangles) {
    sides.insert(key(t[0], t[1]));
    sides.insert(key(t[1], t[2]));
    sides.insert(key(t[2], t[0]));
  }
  std::vector<std::array<Index, 2>> lines;
  for (const auto& e : surface.edges)
    if (!sides.count(key(e[0], e[1]))) lines.push_back(e);

  std::string text;
  text.reserve(n * 40 + surface.triangles.size() * 24 + lines.size() * 16);
  text +=
      "# cellform cell sheet, in model units (a print{...} writes printable.* in mm, and run.json gives "
      "print.scale_mm_per_unit)\n";
  text += "# " + std::to_string(n) + " vertices, " + std::to_string(surface.triangles.size()) + " faces, " +
          std::to_string(lines.size()) + " lines\n";
  const int digits = core::coordinate_digits(cells.position);  // "v %.9g %.9g %.9g" about the origin
  for (std::size_t i = 0; i < n; ++i) {
    const core::Vec3& p = cells.position[i];
    text += 'v';
    for (double x : {p.x(), p.y(), p.z()}) {
      text += ' ';
      core::append_general(text, x, digits);
    }
    text += '\n';
  }
  auto indices = [&](char kind, std::initializer_list<Index> v) {
    text += kind;
    for (Index i : v) {
      text += ' ';
      core::append_integer(text, i + 1ull);
    }
    text += '\n';
  };
  for (const auto& t : surface.triangles) indices('f', {t[0], t[1], t[2]});
  for (const auto& l : lines) indices('l', {l[0], l[1]});

  core::write_file_atomically(
      path, [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

std::string frame_name(const std::string& stem, std::uint64_t step, const std::string& ext) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%06llu", static_cast<unsigned long long>(step));
  std::string name = stem + "_" + digits;
  if (!ext.empty()) name += (ext.front() == '.' ? "" : ".") + ext;
  return name;
}

}  // namespace cellform::exporters
