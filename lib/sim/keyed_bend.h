#pragma once
// A part's keyed bend as its springs feel it: the acceleration of each section's centre in the
// pose an animator keyed, relative to the part's root (a skinned tail whose own joints are keyed to
// sway while the hip stands still). The deviation q of a section from its keyed pose then obeys
// the driven oscillator every spring-bone tool has, m q'' + c q' + k q = −m a_key: the section
// takes −m a_key as it takes the root's own acceleration at its centre (ElasticSweep's body
// loads). Sampled on the simulator's clock at a fixed spacing (sample n at n · spacing), each
// section's acceleration in the root's axes (mesh units/s²); between samples it is linear, and
// before the first or after the last sample zero.
#include <span>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::sim {

class KeyedBend {
 public:
  KeyedBend() = default;
  // `accelerations`: sample n, section i at n · sections + i.
  KeyedBend(double spacing, int sections, std::vector<Eigen::Vector3f> accelerations);

  bool empty() const { return sections_ == 0 || accelerations_.empty(); }
  int sections() const { return sections_; }
  double spacing() const { return spacing_; }
  // Each section's keyed acceleration at time t (out: sections() entries).
  void at(double t, std::span<Vec3> out) const;
  // Whether any section's keyed acceleration is non-zero during [from, to].
  bool loads_between(double from, double to) const;

 private:
  double spacing_ = 0;
  int sections_ = 0;
  // In single precision (6e-8 relative, far below the second differences' own error): a long bake
  // holds a sample of every section every internal step.
  std::vector<Eigen::Vector3f> accelerations_;
  std::vector<int> moving_before_;  // samples before n with any non-zero acceleration (n + 1 entries)
};

}  // namespace sweep::sim
