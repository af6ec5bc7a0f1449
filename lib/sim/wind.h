#pragma once
// Wind: a mean velocity with gusts (its strength swelling and easing) and turbulence
// (its direction wandering), both from seeded smooth noise — sums of a few sines whose periods and
// phases are drawn from the seed — so a bake is the same, byte for byte, every time and at any
// frame rate. Uniform in space. It drags on the spans of material-mode parts (core/elastic_sweep.h).
#include <array>
#include <cstdint>

#include "sweep/core/frame.h"

namespace sweep::sim {

struct WindSettings {
  Vec3 velocity = Vec3::Zero();  // mean air velocity, m/s, world axes
  double gust = 0;               // the strength swells by up to this fraction of the mean (0..1)
  double gust_period = 4;        // s: the typical time between gusts
  double turbulence = 0;         // the direction wanders by up to this fraction of the mean speed
  std::uint64_t seed = 1;
  double air_density = 1.225;     // kg/m³ (sea level)
  double drag_coefficient = 1.2;  // a cylinder across the flow
  bool enabled = false;           // a scene with "wind": the air is there (still air drags too)
  bool any() const { return enabled; }
};

class Wind {
 public:
  Wind() = default;
  explicit Wind(const WindSettings& settings);
  const WindSettings& settings() const { return settings_; }
  // The air's velocity at time t, m/s, world axes.
  Vec3 at(double t) const;
  // ½ ρ C_d, what the drag takes.
  double drag() const { return settings_.any() ? 0.5 * settings_.air_density * settings_.drag_coefficient : 0.0; }

 private:
  struct Wave {
    double angular_frequency = 0, phase = 0;
  };
  // Smooth noise in [−1, 1]: the mean of three waves.
  static double noise(const std::array<Wave, 3>& waves, double t);
  WindSettings settings_;
  std::array<Wave, 3> gust_{};
  std::array<std::array<Wave, 3>, 3> turbulence_{};  // per axis
};

}  // namespace sweep::sim
