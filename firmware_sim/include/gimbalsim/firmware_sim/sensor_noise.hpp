// Seeded Gaussian noise for the simulated sensors: xoshiro256** (Blackman &
// Vigna) seeded through splitmix64, Box-Muller for the normal deviates.
// Written out here rather than std::normal_distribution, whose output is
// implementation-defined: the same seed gives the same noise on every
// standard library. No allocation, no exception.
#pragma once

#include <cmath>
#include <cstdint>

namespace gimbalsim::firmware {

/// splitmix64 (Vigna): advances x and returns the next well-mixed word.
inline std::uint64_t splitmix64(std::uint64_t& x) noexcept {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// The seed of sensor stream `stream` (1, 2, ...) derived from the one scene
/// seed (sensors.seed), so the streams differ from each other and from the
/// encoder stream (the seed itself), and the same seed gives the same
/// streams everywhere.
inline std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream) noexcept {
  std::uint64_t x = seed ^ (stream * 0xd1b54a32d192ed03ULL);
  return splitmix64(x);
}

class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint64_t seed = 1) noexcept {
    std::uint64_t x = seed;
    for (auto& w : s_) w = splitmix64(x);
  }

  /// Uniform 64-bit word.
  std::uint64_t next() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in (0, 1].
  double uniform() noexcept { return (static_cast<double>(next() >> 11) + 1.0) * 0x1.0p-53; }

  /// Standard normal deviate (Box-Muller; the second deviate of a pair is kept).
  double normal() noexcept {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    const double phi = 2.0 * M_PI * uniform();
    spare_ = r * std::sin(phi);
    has_spare_ = true;
    return r * std::cos(phi);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) noexcept { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4]{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace gimbalsim::firmware
