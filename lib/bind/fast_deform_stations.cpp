// The fast deformation path, per frame: the station table (fast_deform.h). Each station holds the
// sweep's centre and frame axes and, for every angle cell, the cubic in the cell's coordinate that
// the radii interpolate to there: the core's interpolants (core/sweep_shape.h) evaluated at the
// stations — the Hermite in t, the periodic Catmull-Rom in θ, the slerp of the frames.
#include <omp.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>

#include "sweep/bind/fast_deform.h"
#include "sweep/bind/fast_deform_detail.h"

namespace sweep::bind {

using detail::kAxisX;
using detail::kAxisY;
using detail::kAxisZ;
using detail::kCells;
using detail::kCenter;

void FastDeformer::tabulate(const SweepShape& shape) {
  tabulate(shape, parallel_);
}

void FastDeformer::tabulate(const SweepShape& shape, bool split) {
  assert(shape.section_count() * stations_per_span_ - stations_per_span_ + 1 == station_count_);
  assert(shape.radial_count == n_);
  const int k = shape.section_count(), n = n_, per = stations_per_span_;
  double lowest = shape.radii.empty() ? 0.0 : *std::min_element(shape.radii.begin(), shape.radii.end());
  radius_floor_ = static_cast<float>(kMinRadiusFraction * lowest);
  // Scratch for one span at a time: slopes (8n floats) and rotations (S + 1), one set a thread.
  const std::size_t w4 = 4 * static_cast<std::size_t>(n);
  const int slots = split ? omp_get_max_threads() : 1;
  if (slopes_.size() < slots * 2 * w4) slopes_.resize(slots * 2 * w4);
  if (rotations_.size() < static_cast<std::size_t>(slots * (per + 1))) rotations_.resize(slots * (per + 1));
  // Each section's periodic Catmull-Rom, cell by cell, as the cubic c0 + w·c1 + w²·c2 + w³·c3
  // in the cell's coordinate w.
  for (int i = 0; i < k; ++i) {
    float* cell = section_cells_.data() + static_cast<std::size_t>(i) * 4 * n;
    for (int j = 0; j < n; ++j) {
      const std::array<double, 4> c = CatmullRomCell(shape.section_radii(i), j).cubic();
      for (int e = 0; e < 4; ++e) cell[4 * j + e] = static_cast<float>(c[e]);
    }
  }

  // Each span's stations, from its two sections and their neighbours: spans are independent.
  const auto span = [&](int s, int slot) {
    const std::span<Quat> rotations(rotations_.data() + static_cast<std::size_t>(slot) * (per + 1), per + 1);
    const Frame& fa = shape.frames[s];
    const Frame& fb = shape.frames[s + 1];
    const double h = shape.t[s + 1] - shape.t[s];
    const Vec3 ca = fa.center, cb = fb.center;
    const Vec3 ta = h * fa.axis(), tb = h * fb.axis();
    // The frames' slerp at the span's S + 1 stations at once: four transcendentals a span, not
    // two a station (rotation_at, which also finds u from t, differs in the last bits).
    Slerp(fa.rotation, fb.rotation).at_steps(rotations);
    // The radius cubics are linear in the radii, and so is the Hermite in t: the station's cubics
    // are the Hermite combination of the sections' cubics and of their finite-difference slopes
    // (one-sided at the end sections) times h, exactly as radii_at_samples interpolates the radii.
    const int lo0 = std::max(s - 1, 0), hi0 = std::min(s + 1, k - 1);
    const int lo1 = s, hi1 = std::min(s + 2, k - 1);
    const float g0 = static_cast<float>(h / (shape.t[hi0] - shape.t[lo0]));
    const float g1 = static_cast<float>(h / (shape.t[hi1] - shape.t[lo1]));
    const float* k0 = section_cells_.data() + s * w4;
    const float* k1 = k0 + w4;
    const float *l0 = section_cells_.data() + lo0 * w4, *u0 = section_cells_.data() + hi0 * w4;
    const float *l1 = section_cells_.data() + lo1 * w4, *u1 = section_cells_.data() + hi1 * w4;
    float* const m0 = slopes_.data() + static_cast<std::size_t>(slot) * 2 * w4;
    float* const m1 = m0 + w4;
    for (std::size_t e = 0; e < w4; ++e) {
      m0[e] = g0 * (u0[e] - l0[e]);
      m1[e] = g1 * (u1[e] - l1[e]);
    }

    const int last = s + 2 == k ? per : per - 1;  // the last span also writes the tip station
    for (int q = 0; q <= last; ++q) {
      const HermiteBasis& hb = basis_[q];
      float* row = stations_.data() + static_cast<std::size_t>(s * per + q) * row_;
      const Vec3 c = hb.h00 * ca + hb.h10 * ta + hb.h01 * cb + hb.h11 * tb;
      const Mat3 r = rotations[q].normalized().toRotationMatrix();
      for (int e = 0; e < 3; ++e) {
        row[kCenter + e] = static_cast<float>(c[e]);
        row[kAxisX + e] = static_cast<float>(r(e, 0));
        row[kAxisY + e] = static_cast<float>(r(e, 1));
        row[kAxisZ + e] = static_cast<float>(r(e, 2));
      }
      const float b0 = static_cast<float>(hb.h00), b1 = static_cast<float>(hb.h10);
      const float b2 = static_cast<float>(hb.h01), b3 = static_cast<float>(hb.h11);
      float* cell = row + kCells;
      for (std::size_t e = 0; e < w4; ++e) cell[e] = b0 * k0[e] + b1 * m0[e] + b2 * k1[e] + b3 * m1[e];
    }
  };
  if (split && k > 2) {
#pragma omp parallel for schedule(static)
    for (int s = 0; s < k - 1; ++s) span(s, omp_get_thread_num());
  } else {
    for (int s = 0; s < k - 1; ++s) span(s, 0);
  }
}

}  // namespace sweep::bind
