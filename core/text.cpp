// Numbers as text: std::to_chars with a precision is specified to give printf's output ("C" locale).
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

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

int coordinate_digits(const std::vector<Vec3>& points) {
  constexpr int kNear = 9, kExact = std::numeric_limits<double>::max_digits10;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  const double reach = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
  if (!std::isfinite(extent) || !std::isfinite(reach) || reach <= extent) return kNear;
  if (!(extent > 0)) return kExact;  // points that all coincide, away from the origin
  // d significant digits keep x to 5 * 10^-d of |x|: a coordinate up to `reach` = 10^k times the box's side
  // needs k more digits than one up to the side
  return std::min(kExact, kNear + static_cast<int>(std::ceil(std::log10(reach / extent))));
}

}  // namespace cellform::core
