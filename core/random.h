// Seeded, platform-independent random numbers (no std distributions, no global state).
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>

#include "core/types.h"

namespace cellform::core {

/// SplitMix64 finaliser: a good 64-bit mix, used to derive independent streams from (seed, ids).
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// A stream keyed by a seed and up to two ids, so that results never depend on evaluation order.
inline std::uint64_t stream_key(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0) {
  return mix64(mix64(mix64(seed) ^ a) ^ (b * 0xd1b54a32d192ed03ull));
}

/// Random numbers from std::mt19937_64, converted by hand so every standard library gives the same values.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Raw 64 bits.
  std::uint64_t next() { return engine_(); }
  /// The engine's full state as text (the standard's mt19937_64 stream format), for checkpoints.
  std::string state() const {
    std::ostringstream os;
    os << engine_;
    return os.str();
  }
  /// Restores a state() string; false (and the engine unchanged) if it is not one.
  bool set_state(const std::string& s) {
    std::istringstream is(s);
    std::mt19937_64 e;
    is >> e;
    if (is.fail()) return false;
    engine_ = e;
    return true;
  }
  /// A uniformly distributed unit vector (rejection sampling in the unit ball).
  Vec3 unit_vector() {
    for (;;) {
      const Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double n2 = v.squaredNorm();
      if (n2 > 1e-6 && n2 <= 1.0) return v / std::sqrt(n2);
    }
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace cellform::core
