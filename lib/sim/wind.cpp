#include "sweep/sim/wind.h"

#include <cmath>
#include <numbers>

namespace sweep::sim {
namespace {

// splitmix64: a tiny generator whose sequence is the same on every platform and compiler (the
// standard library's distributions are not), so the wind is too.
std::uint64_t next(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
double uniform(std::uint64_t& state) {
  return static_cast<double>(next(state) >> 11) * 0x1.0p-53;
}

}  // namespace

Wind::Wind(const WindSettings& settings) : settings_(settings) {
  std::uint64_t state = settings.seed;
  constexpr double kTwoPi = 2 * std::numbers::pi;
  // Gust waves around the gust period (its 1, ~1/2 and ~1/3), turbulence faster (~1/5 to ~1/12).
  const double gust_scale[3] = {1.0, 0.53, 0.29};
  for (int k = 0; k < 3; ++k) {
    const double period = settings.gust_period * gust_scale[k] * (0.8 + 0.4 * uniform(state));
    gust_[k] = {kTwoPi / period, kTwoPi * uniform(state)};
  }
  const double turbulence_scale[3] = {0.21, 0.13, 0.083};
  for (auto& axis : turbulence_) {
    for (int k = 0; k < 3; ++k) {
      const double period = settings.gust_period * turbulence_scale[k] * (0.8 + 0.4 * uniform(state));
      axis[k] = {kTwoPi / period, kTwoPi * uniform(state)};
    }
  }
}

double Wind::noise(const std::array<Wave, 3>& waves, double t) {
  double sum = 0;
  for (const Wave& w : waves) sum += std::sin(w.angular_frequency * t + w.phase);
  return sum / 3;
}

Vec3 Wind::at(double t) const {
  const WindSettings& s = settings_;
  if (!s.any()) return Vec3::Zero();
  // Gusts only strengthen the mean (noise mapped to [0, 1]); turbulence wanders about it.
  Vec3 v = s.velocity * (1 + s.gust * 0.5 * (1 + noise(gust_, t)));
  if (s.turbulence > 0) {
    const double speed = s.velocity.norm();
    for (int c = 0; c < 3; ++c) v[c] += s.turbulence * speed * noise(turbulence_[c], t);
  }
  return v;
}

}  // namespace sweep::sim
