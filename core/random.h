// Seeded, platform-independent random numbers (no std distributions, no global state).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
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
  Vec3 unit_vector() { return random_unit_vector(*this); }

  /// Rejection sampling in the unit ball, from any generator with uniform(lo, hi).
  template <class G>
  static Vec3 random_unit_vector(G& g) {
    for (;;) {
      // one draw per statement: C++ leaves the order of a call's arguments open (g++ takes the last
      // first, which these keep, so g++ builds give the numbers they gave before)
      const double z = g.uniform(-1, 1);
      const double y = g.uniform(-1, 1);
      const double x = g.uniform(-1, 1);
      const Vec3 v(x, y, z);
      const double n2 = v.squaredNorm();
      if (n2 > 1e-6 && n2 <= 1.0) return v / std::sqrt(n2);
    }
  }

 private:
  std::mt19937_64 engine_;
};

/// The same numbers as Rng(seed), for a stream that draws only a few (one per cell and step). The first
/// outputs of std::mt19937_64 need only part of its seeded state: output k is the twist of state words
/// k, k + 1 and k + 156, tempered. So the first kQuick cost 156 + kQuick seeding steps instead of 312
/// plus a twist of all 312 words; later ones come from a real engine advanced past them.
class StreamRng {
 public:
  explicit StreamRng(std::uint64_t seed) : seed_(seed) {
    std::uint64_t v = low_[0] = seed;
    for (std::uint64_t i = 1; i < 156 + kQuick; ++i) {
      v = 6364136223846793005ull * (v ^ (v >> 62)) + i;  // the standard's seeding recurrence
      if (i <= kQuick) low_[i] = v;
      if (i >= 156) high_[i - 156] = v;
    }
  }
  std::uint64_t next() {
    if (k_ < kQuick) {
      const std::uint64_t y = (low_[k_] & ~0ull << 31) | (low_[k_ + 1] & ((1ull << 31) - 1));
      std::uint64_t z = high_[k_] ^ (y >> 1) ^ ((y & 1) ? 0xb5026f5aa96619e9ull : 0);
      ++k_;
      z ^= (z >> 29) & 0x5555555555555555ull;
      z ^= (z << 17) & 0x71d67fffeda60000ull;
      z ^= (z << 37) & 0xfff7eee000000000ull;
      return z ^ (z >> 43);
    }
    if (!engine_) {
      engine_.emplace(seed_);
      engine_->discard(kQuick);
    }
    return (*engine_)();
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  Vec3 unit_vector() { return Rng::random_unit_vector(*this); }

 private:
  static constexpr std::uint64_t kQuick = 16;
  std::uint64_t seed_;
  std::uint64_t k_ = 0;
  std::uint64_t low_[kQuick + 1];          // seeded words 0 .. kQuick
  std::uint64_t high_[kQuick];             // seeded words 156 .. 156 + kQuick - 1
  std::optional<std::mt19937_64> engine_;  // seeded only if more than kQuick numbers are drawn
};

}  // namespace cellform::core
