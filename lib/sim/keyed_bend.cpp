#include "sweep/sim/keyed_bend.h"

#include <algorithm>
#include <cmath>

namespace sweep::sim {

KeyedBend::KeyedBend(double spacing, int sections, std::vector<Eigen::Vector3f> accelerations, long long first)
    : spacing_(spacing), sections_(sections), first_(first), accelerations_(std::move(accelerations)) {
  const std::size_t samples = sections_ > 0 ? accelerations_.size() / static_cast<std::size_t>(sections_) : 0;
  moving_before_.assign(samples + 1, 0);
  for (std::size_t n = 0; n < samples; ++n) {
    const auto begin = accelerations_.begin() + static_cast<std::ptrdiff_t>(n * sections_);
    const bool moving =
        std::any_of(begin, begin + sections_, [](const Eigen::Vector3f& a) { return a != Eigen::Vector3f::Zero(); });
    moving_before_[n + 1] = moving_before_[n] + (moving ? 1 : 0);
  }
}

KeyedBend KeyedBend::repeating(double period, double origin, int sections, std::vector<Eigen::Vector3f> accelerations) {
  const std::size_t count = sections > 0 ? accelerations.size() / static_cast<std::size_t>(sections) : 0;
  KeyedBend bend(count > 0 ? period / static_cast<double>(count) : 0, sections, std::move(accelerations));
  if (!(period > 0)) bend.accelerations_.clear();  // no period: nothing repeats
  bend.period_ = period;
  bend.origin_ = origin;
  return bend;
}

void KeyedBend::at(double t, std::span<Vec3> out) const {
  std::fill(out.begin(), out.end(), Vec3::Zero());
  if (empty()) return;
  const long long samples = this->samples();
  long long n = 0, next = 0;
  double s = 0;
  if (period_ > 0) {
    double phase = std::fmod(t - origin_, period_);
    if (phase < 0) phase += period_;
    if (!std::isfinite(phase)) return;
    const double u = phase / spacing_;
    n = static_cast<long long>(std::floor(u));
    s = u - static_cast<double>(n);
    n %= samples;  // a phase rounded up to the period is phase 0
    next = (n + 1) % samples;
  } else {
    // As sample n of a bend held from time 0, so that a window gives the same values bit for bit.
    const double u = t / spacing_;
    const long long last = first_ + samples - 1;
    if (!(u >= static_cast<double>(first_)) || u > static_cast<double>(last)) return;
    const long long m = std::min(static_cast<long long>(std::floor(u)), last);
    s = u - static_cast<double>(m);
    n = m - first_;
    next = n + 1 < samples ? n + 1 : n;
  }
  const std::size_t count = std::min(out.size(), static_cast<std::size_t>(sections_));
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 a = accelerations_[static_cast<std::size_t>(n) * sections_ + i].cast<double>();
    if (next != n && s > 0) {
      out[i] = a + s * (accelerations_[static_cast<std::size_t>(next) * sections_ + i].cast<double>() - a);
    } else {
      out[i] = a;
    }
  }
}

bool KeyedBend::loads_between(double from, double to) const {
  if (empty()) return false;
  const long long samples = this->samples();
  if (period_ > 0) {
    if (!(to - from < period_)) return moving(0, samples);  // a whole period (or not a number: be safe)
    double phase = std::fmod(from - origin_, period_);
    if (phase < 0) phase += period_;
    // The samples whose linear pieces reach into [from, to], counted from the one before `from`'s
    // phase, around the period: [a, b) with sample samples + k that of k.
    const double u = phase / spacing_;
    long long a = static_cast<long long>(std::floor(u));
    long long b = static_cast<long long>(std::ceil(u + (to - from) / spacing_)) + 1;
    if (a >= samples) a -= samples, b -= samples;
    if (b - a >= samples) return moving(0, samples);
    return moving(a, std::min(b, samples)) || (b > samples && moving(0, b - samples));
  }
  // The samples whose linear pieces reach into [from, to].
  const long long a = std::clamp(static_cast<long long>(std::floor(from / spacing_)) - first_, 0LL, samples);
  const long long b = std::clamp(static_cast<long long>(std::ceil(to / spacing_)) + 1 - first_, 0LL, samples);
  return moving(a, b);
}

}  // namespace sweep::sim
