// The strict ASCII STL parser shared by the mesh loader (load_mesh) and the exporters' mesh reader.
#pragma once

#include <cstdint>
#include <istream>
#include <string_view>
#include <vector>

#include "core/types.h"

namespace cellform::forms {

/// The triangle corners of an ASCII STL text, three per facet, in file order (model units as written).
/// Strict, so that a damaged file is refused instead of read as something else: the text is one or more
/// "solid [name]" ... "endsolid [name]" blocks, each facet is the seven lines "facet normal nx ny nz",
/// "outer loop", three "vertex x y z" lines, "endloop" and "endfacet" (keywords in any case, blank lines
/// allowed), and a vertex is three finite numbers. Throws core::InvalidInput "line N: ..." saying what was
/// wrong, the caller adds the file name; a file cut short ends inside a facet or before "endsolid" and is
/// refused too. A solid without facets gives no corners.
/// A UTF-8 byte-order mark before the first line is skipped. `normals`, if given, gets each facet's stored
/// normal, in order (the corners' winding is what the callers go by).
std::vector<core::Vec3> parse_ascii_stl(std::string_view text, std::vector<core::Vec3>* normals = nullptr);

/// What an OBJ text holds for a mesh: its 'v' positions, in full double precision, its 'f' faces (the corners of
/// face k are corners[face_end[k-1] .. face_end[k]), from 0; face_line[k] its line number) and the number of its
/// 'l' (polyline) lines. Nothing else is read (not a material library an 'mtllib' line names).
struct ObjData {
  std::vector<core::Vec3> positions;
  std::vector<std::uint32_t> corners;
  std::vector<std::size_t> face_end, face_line;
  std::size_t polylines = 0;
};

/// Reads an OBJ text (after an optional UTF-8 byte-order mark; CRLF lines too). A vertex is three finite numbers,
/// each a whole word ("v 0 0 0#note" too), a face three or more obj_face_vertex corners up to an optional '#'
/// comment. Throws core::InvalidInput "line N: ..." saying what was wrong (the caller adds the file name), and
/// core::FileError if the stream fails. Shared by the obstacle loader and `cellform check`.
ObjData parse_obj(std::istream& in);

/// One corner of an OBJ face line: "v", "v/vt", "v//vn" or "v/vt/vn" with whole numbers (negative counts
/// back from the last vertex read). Returns the vertex index from 0, given the `vertices` read before the
/// face. Throws core::InvalidInput saying what is wrong with the token (the caller adds file and line).
std::uint32_t obj_face_vertex(std::string_view token, std::size_t vertices);

/// Whether `head` (the first bytes of a file, up to 84) starts as an ASCII STL does: after an optional UTF-8
/// byte-order mark and blanks, the word "solid" in any case ("SOLID" from some CAD programs), and no NUL byte
/// (a binary STL's 80-byte header may begin with "solid" too, but a triangle count under 2^24 has a NUL in its
/// last byte, 83; text has none).
bool starts_like_ascii_stl(std::string_view head);

}  // namespace cellform::forms
