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
    if (!p.allFinite()) return kNear;  // written as nan or inf whatever the digits
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  const double reach = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
  if (points.empty() || reach == 0) return kNear;
  if (!(extent > 0) || !std::isfinite(extent)) return kExact;  // points that coincide away from the origin
  // d significant digits keep x to half a unit of its d-th digit, 0.5 * 10^(floor(log10 |x|) - d + 1): with
  // d = 9 + floor(log10 reach) - floor(log10 extent), at most 0.5 * 10^(floor(log10 extent) - 8), which is
  // 5e-9 of the side. (The decades are whole numbers of moderate size: no overflow.)
  auto decade = [](double x) {  // floor(log10 x), exact where log10 rounds up to a whole number
    double e = std::floor(std::log10(x));
    if (std::pow(10.0, e) > x) e -= 1;
    return e;
  };
  const double decades = decade(reach) - decade(extent);
  return static_cast<int>(std::clamp(kNear + decades, double{kNear}, double{kExact}));
}

}  // namespace cellform::core
