// Numbers as text: std::to_chars with a precision is specified to give printf's output ("C" locale).
#include "core/text.h"

#include <cstdio>

namespace cellform::core {

namespace {
void append_chars(std::string& out, double x, std::chars_format f, int precision, const char* printf_format) {
  char buf[400];  // %.9g needs at most 16; fixed with a few digits fits any double (at most 309 integer digits)
  const auto r = std::to_chars(buf, buf + sizeof buf, x, f, precision);
  if (r.ec == std::errc()) {
    out.append(buf, static_cast<std::size_t>(r.ptr - buf));
    return;
  }
  const int len = std::snprintf(nullptr, 0, printf_format, precision, x);  // longer than the buffer: rare
  std::string s(static_cast<std::size_t>(len) + 1, '\0');
  std::snprintf(s.data(), s.size(), printf_format, precision, x);
  out.append(s.data(), static_cast<std::size_t>(len));
}
}  // namespace

void append_general(std::string& out, double x, int precision) {
  append_chars(out, x, std::chars_format::general, precision, "%.*g");
}

void append_fixed(std::string& out, double x, int digits) {
  append_chars(out, x, std::chars_format::fixed, digits, "%.*f");
}

}  // namespace cellform::core
