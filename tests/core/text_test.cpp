// Tests of numbers as text: byte for byte what printf writes, the oracle, on awkward and random values.
#include "core/text.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
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
