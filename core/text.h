// Numbers as text for the text file writers (OBJ, ASCII PLY, SVG, OpenSCAD): the bytes printf writes
// in the "C" locale, without its cost (std::to_chars; several times faster on million-vertex files).
#pragma once

#include <charconv>
#include <concepts>
#include <ostream>
#include <string>
#include <vector>

#include "core/types.h"

namespace cellform::core {

/// Appends x as std::printf("%.*g", precision, x) writes it.
void append_general(std::string& out, double x, int precision = 9);

/// Appends x as std::printf("%.*f", digits, x) writes it.
void append_fixed(std::string& out, double x, int digits);

/// Significant digits (for append_general) that keep each coordinate of `points` within 5e-9 of their
/// bounding box's largest side: 9 ("%.9g") while the coordinates reach no farther decade than the box's side
/// (a form about the origin, or one 30 units across at 10 to 40), more the farther the form lies from the
/// origin for its size (a form 100 units across at 500,000 units: 12), at most 17 (every double exact).
/// 9 for no point, the origin alone, or any point not finite; 17 for points that coincide elsewhere.
int coordinate_digits(const std::vector<Vec3>& points);

/// Appends an integer in decimal.
template <std::integral T>
void append_integer(std::string& out, T x) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, static_cast<std::size_t>(r.ptr - buf));
}

/// Writes `text` to `os` and empties it once it holds at least `limit` bytes; call with limit 0 at the end.
/// Lets a writer build a big file in pieces without holding all of it.
inline void drain(std::string& text, std::ostream& os, std::size_t limit = std::size_t{1} << 20) {
  if (text.size() < limit || text.empty()) return;
  os.write(text.data(), static_cast<std::streamsize>(text.size()));
  text.clear();
}

}  // namespace cellform::core
