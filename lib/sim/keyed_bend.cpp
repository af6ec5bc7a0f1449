#include "sweep/sim/keyed_bend.h"

#include <algorithm>
#include <cmath>

namespace sweep::sim {

KeyedBend::KeyedBend(double spacing, int sections, std::vector<Eigen::Vector3f> accelerations)
    : spacing_(spacing), sections_(sections), accelerations_(std::move(accelerations)) {
  const std::size_t samples = sections_ > 0 ? accelerations_.size() / static_cast<std::size_t>(sections_) : 0;
  moving_before_.assign(samples + 1, 0);
  for (std::size_t n = 0; n < samples; ++n) {
    const auto first = accelerations_.begin() + static_cast<std::ptrdiff_t>(n * sections_);
    const bool moving =
        std::any_of(first, first + sections_, [](const Eigen::Vector3f& a) { return a != Eigen::Vector3f::Zero(); });
    moving_before_[n + 1] = moving_before_[n] + (moving ? 1 : 0);
  }
}

void KeyedBend::at(double t, std::span<Vec3> out) const {
  std::fill(out.begin(), out.end(), Vec3::Zero());
  if (empty()) return;
  const long long samples = static_cast<long long>(moving_before_.size()) - 1;
  const double u = t / spacing_;
  if (!(u >= 0) || u > static_cast<double>(samples - 1)) return;
  const long long n = std::min(static_cast<long long>(std::floor(u)), samples - 1);
  const double s = u - static_cast<double>(n);
  const std::size_t count = std::min(out.size(), static_cast<std::size_t>(sections_));
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 a = accelerations_[static_cast<std::size_t>(n) * sections_ + i].cast<double>();
    if (n + 1 < samples && s > 0) {
      out[i] = a + s * (accelerations_[static_cast<std::size_t>(n + 1) * sections_ + i].cast<double>() - a);
    } else {
      out[i] = a;
    }
  }
}

bool KeyedBend::loads_between(double from, double to) const {
  if (empty()) return false;
  const long long samples = static_cast<long long>(moving_before_.size()) - 1;
  // The samples whose linear pieces reach into [from, to].
  const long long a = std::clamp(static_cast<long long>(std::floor(from / spacing_)), 0LL, samples);
  const long long b = std::clamp(static_cast<long long>(std::ceil(to / spacing_)) + 1, 0LL, samples);
  return b > a && moving_before_[b] > moving_before_[a];
}

}  // namespace sweep::sim
