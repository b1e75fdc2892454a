// Tests of numbers as text: byte for byte what printf writes, the oracle, on awkward and random values.
#include "core/text.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/random.h"

namespace {
std::string printf_text(const char* format, int precision, double x) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, precision, x);
  return buf;
}

std::vector<double> awkward_values() {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> v = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.1,
                           0.5,
                           2.5,
                           1e-5,
                           123456789.0,
                           1234567891.0,
                           0.000123456789,
                           999999999.5,
                           9.9999999995,
                           1e300,
                           -1e300,
                           1e-300,
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::denorm_min(),
                           inf,
                           -inf,
                           std::nan("")};
  cellform::core::Rng rng(7);
  for (int i = 0; i < 20000; ++i) {
    const double m = rng.uniform(-1, 1);
    v.push_back(std::ldexp(m, static_cast<int>(rng.next() % 200) - 100));  // random mantissas and scales
    std::uint64_t bits = rng.next();                                       // any bit pattern
    double d;
    std::memcpy(&d, &bits, sizeof d);
    v.push_back(d);
    v.push_back(std::round(rng.uniform(-2000, 2000) * 100) / 100 + 0.005);  // halfway-looking cents
  }
  return v;
}
}  // namespace

TEST_CASE("append_general writes what printf(\"%.*g\") writes", "[core][text]") {
  for (int precision : {1, 2, 6, 9, 17}) {
    for (double x : awkward_values()) {
      std::string s = "a";  // appends, keeping what is there
      cellform::core::append_general(s, x, precision);
      INFO("precision " << precision << ", x bits " << std::hexfloat << x);
      REQUIRE(s.substr(1) == printf_text("%.*g", precision, x));
      REQUIRE(s[0] == 'a');
    }
  }
}

TEST_CASE("append_fixed writes what printf(\"%.*f\") writes, huge values included", "[core][text]") {
  for (int digits : {0, 2, 5}) {
    for (double x : awkward_values()) {
      std::string s;
      cellform::core::append_fixed(s, x, digits);
      INFO("digits " << digits << ", x bits " << std::hexfloat << x);
      REQUIRE(s == printf_text("%.*f", digits, x));
    }
  }
  std::string s;
  cellform::core::append_fixed(s, 1e300, 100);  // longer than the fast path's buffer
  CHECK(s == printf_text("%.*f", 100, 1e300));
}

TEST_CASE("append_integer and drain", "[core][text]") {
  std::string s;
  cellform::core::append_integer(s, std::uint32_t{4294967295u});
  s += ' ';
  cellform::core::append_integer(s, std::int64_t{-9223372036854775807 - 1});
  s += ' ';
  cellform::core::append_integer(s, 0);
  CHECK(s == "4294967295 -9223372036854775808 0");
  std::ostringstream os;
  cellform::core::drain(s, os, 100);  // below the limit: kept
  CHECK(os.str().empty());
  CHECK(s.size() == 33);
  cellform::core::drain(s, os, 0);  // written and emptied
  CHECK(os.str() == "4294967295 -9223372036854775808 0");
  CHECK(s.empty());
}

TEST_CASE("coordinate_digits keeps every coordinate to 5e-9 of the form's size, however far out it lies",
          "[core][text]") {
  using cellform::core::coordinate_digits;
  using cellform::core::Vec3;
  // about the origin: "%.9g", as the files always had
  CHECK(coordinate_digits({Vec3(-3, 0, 1), Vec3(5, 2, -1)}) == 9);
  CHECK(coordinate_digits({Vec3(0, 0, 0), Vec3(0, 120, 0)}) == 9);      // a leaf from its petiole
  CHECK(coordinate_digits({Vec3(10, 10, 10), Vec3(40, 40, 40)}) == 9);  // the same decade: as the files had
  CHECK(coordinate_digits({Vec3(0.5, 0, 0), Vec3(0.9, 0, 0)}) == 9);
  // nothing to span: none, the origin, a non-finite point; one point elsewhere is kept exact
  CHECK(coordinate_digits({}) == 9);
  CHECK(coordinate_digits({Vec3(0, 0, 0), Vec3(0, 0, 0)}) == 9);
  CHECK(coordinate_digits({Vec3(5e5, 2e5, 30)}) == 17);
  CHECK(coordinate_digits({Vec3(1e6, 0, 0), Vec3(1e6 + 1, 0, 0), Vec3(std::nan(""), 1, 1)}) == 9);
  // a leaf 100 units across at site coordinates: 9 digits kept it to 5e-4 units (the audit's case)
  CHECK(coordinate_digits({Vec3(5e5, 2e5, 30), Vec3(5e5 + 100, 2e5 + 60, 30)}) == 12);
  CHECK(coordinate_digits({Vec3(1e15, 0, 0), Vec3(1e15 + 1, 0, 0)}) == 17);    // capped: exact
  CHECK(coordinate_digits({Vec3(1e300, 0, 0), Vec3(1e300, 1e-10, 0)}) == 17);  // reach / side overflows
  // the oracle: written with that many digits and read back, each coordinate is off by at most 5e-9 of the side
  cellform::core::Rng rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const double side = std::ldexp(rng.uniform(1, 2), static_cast<int>(rng.next() % 40) - 20);
    const Vec3 at = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)) *
                    std::ldexp(1.0, static_cast<int>(rng.next() % 60) - 10);
    std::vector<Vec3> points;
    for (int k = 0; k < 20; ++k) points.push_back(at + side * Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
    const int digits = coordinate_digits(points);
    double extent = 0;
    for (int a = 0; a < 3; ++a) {
      double lo = points[0][a], hi = lo;
      for (const Vec3& p : points) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
      extent = std::max(extent, hi - lo);
    }
    for (const Vec3& p : points)
      for (int a = 0; a < 3; ++a) {
        std::string s;
        cellform::core::append_general(s, p[a], digits);
        INFO("trial " << trial << ", digits " << digits << ", " << s);
        REQUIRE(std::abs(std::strtod(s.c_str(), nullptr) - p[a]) <= 5e-9 * extent);
      }
  }
}
