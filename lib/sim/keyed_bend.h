#pragma once
// A part's keyed bend as its springs feel it: the acceleration of each section's centre in the
// pose an animator keyed, relative to the part's root (a skinned tail whose own joints are keyed to
// sway while the hip stands still). The deviation q of a section from its keyed pose then obeys
// the driven oscillator every spring-bone tool has, m q'' + c q' + k q = −m a_key: the section
// takes −m a_key as it takes the root's own acceleration at its centre (ElasticSweep's body
// loads). Each section's acceleration in the root's axes (mesh units/s²), sampled at a fixed
// spacing on the simulator's clock and linear between samples. Only what the keys can produce is
// stored, so that its size is bounded by the clip's length, not the bake's:
//  - a window: samples n = first … first + count − 1 at n · spacing, zero outside them (a clip
//    that holds its first pose before it and its last after it);
//  - a repeating bend (a looping clip): one period of `count` samples, sample k at phase
//    k · period / count, phase 0 at time `origin` and every period from it, at every time.
#include <span>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::sim {

class KeyedBend {
 public:
  KeyedBend() = default;
  // A window. `accelerations`: sample first + k, section i at k · sections + i.
  KeyedBend(double spacing, int sections, std::vector<Eigen::Vector3f> accelerations, long long first = 0);
  // A repeating bend. `accelerations`: phase k · period / count, section i at k · sections + i.
  static KeyedBend repeating(double period, double origin, int sections, std::vector<Eigen::Vector3f> accelerations);

  bool empty() const { return sections_ == 0 || accelerations_.empty(); }
  int sections() const { return sections_; }
  double spacing() const { return spacing_; }
  double period() const { return period_; }  // 0: a window
  // The samples held (each sections() accelerations of 12 bytes).
  long long samples() const { return static_cast<long long>(moving_before_.size()) - 1; }
  // Each section's keyed acceleration at time t (out: sections() entries).
  void at(double t, std::span<Vec3> out) const;
  // Whether any section's keyed acceleration is non-zero during [from, to].
  bool loads_between(double from, double to) const;

 private:
  double spacing_ = 0;
  int sections_ = 0;
  long long first_ = 0;  // a window's first sample
  double period_ = 0;    // a repeating bend's period (0: a window)
  double origin_ = 0;    // a repeating bend's time of phase 0
  // In single precision (6e-8 relative, far below the second differences' own error).
  std::vector<Eigen::Vector3f> accelerations_;
  std::vector<int> moving_before_;  // samples before k with any non-zero acceleration (count + 1 entries)
  // Samples [a, b) of those held with any non-zero acceleration (0 <= a <= b <= samples()).
  bool moving(long long a, long long b) const { return b > a && moving_before_[b] > moving_before_[a]; }
};

}  // namespace sweep::sim
