// Helpers for error messages.
#include "core/errors.h"

#include <new>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace cellform::core {

std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e))
    return "out of memory: the machine (or a limit such as ulimit -v) gave no more; fewer cells or nodes, a coarser "
           "print.voxel_size or a smaller print.size need less";
  return e.what();
}

std::string number_text(double x) {
  if (std::isnan(x)) return "NaN";  // the stream writes "nan" or "-nan", by the sign bit
  if (x == 0) return "0";           // and "-0" for negative zero
  std::ostringstream o;
  o << x;
  return o.str();
}

std::string point_text(double x, double y, double z) {
  std::string s = "{";  // (appended: GCC 12 warns falsely of an overlapping copy in "{" + std::string)
  s += number_text(x) + ", " + number_text(y) + ", " + number_text(z) + "}";
  return s;
}

std::string lower_case(std::string text) {
  for (char& c : text)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return text;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  // optimal string alignment: insertions, deletions, substitutions and swaps of neighbours cost 1 each
  const std::size_t m = b.size();
  std::vector<std::size_t> two(m + 1), one(m + 1), row(m + 1);  // rows i - 2, i - 1, i
  for (std::size_t j = 0; j <= m; ++j) one[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      row[j] = std::min({one[j] + 1, row[j - 1] + 1, one[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], two[j - 2] + 1);
    }
    std::swap(two, one);
    std::swap(one, row);
  }
  return one[m];
}

namespace {
/// Length of the well-formed UTF-8 sequence starting at text[i] (2 to 4 bytes), or 0 if there is none
/// (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF, or cut short) or it is a
/// C1 control character.
std::size_t utf8_sequence(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
  const unsigned c = byte(i);
  std::size_t len = 0;
  unsigned lo = 0x80, hi = 0xbf;  // the range of the second byte (tighter after E0, ED, F0, F4)
  if (c >= 0xc2 && c <= 0xdf) {
    len = 2;
    if (c == 0xc2) lo = 0xa0;  // U+0080 to U+009F: the C1 controls (U+009B starts a terminal command)
  } else if (c >= 0xe0 && c <= 0xef) {
    len = 3;
    if (c == 0xe0) lo = 0xa0;
    if (c == 0xed) hi = 0x9f;
  } else if (c >= 0xf0 && c <= 0xf4) {
    len = 4;
    if (c == 0xf0) lo = 0x90;
    if (c == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < len; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xbf) return 0;
  return len;
}
}  // namespace

std::string printable(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += text[i++];
      continue;
    }
    if (const std::size_t len = c >= 0x80 ? utf8_sequence(text, i) : 0; len > 0) {  // UTF-8 text stays
      out.append(text.substr(i, len));
      i += len;
      continue;
    }
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
    ++i;
  }
  return out;
}

bool is_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0u;
    const std::size_t len = c < 0x80                                    ? 1
                            : c == 0xc2 && next >= 0x80 && next <= 0x9f ? 2  // a C1 control: UTF-8 all the same
                                                                        : utf8_sequence(text, i);
    if (len == 0) return false;
    i += len;
  }
  return true;
}

}  // namespace cellform::core
