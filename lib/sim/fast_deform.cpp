#include "sim/fast_deform.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sweep::sim {
namespace {

// Station row layout: centre, then the three frame axes, then the padded radii.
constexpr int kCenter = 0, kAxisX = 3, kAxisY = 6, kAxisZ = 9, kRadii = 12;

}  // namespace

FastDeformer::FastDeformer(const SweepShape& rest, const bind::SweepBinding& bound, std::span<const Vec3f> rest_positions,
                           int stations_per_span)
    : n_(rest.radial_count), row_(kRadii + rest.radial_count + 3) {
  assert(stations_per_span >= 1 && rest.radial_count + 3 <= 65535);
  const int k = rest.section_count();
  for (int s = 0; s + 1 < k; ++s) {
    for (int q = 0; q < stations_per_span; ++q) {
      station_t_.push_back(rest.t[s] + (rest.t[s + 1] - rest.t[s]) * q / stations_per_span);
    }
  }
  station_t_.push_back(rest.length());
  stations_.assign(station_t_.size() * row_, 0.0f);
  radii_scratch_.resize(n_);

  // Which station span each vertex falls in, then a counting sort by span (stable: mesh order is
  // kept within a span, which keeps the writes back to mesh order as local as they can be).
  const std::size_t count = bound.size();
  const std::size_t spans = station_t_.size() - 1;
  std::vector<std::uint32_t> span_of(count);
  for (std::size_t v = 0; v < count; ++v) {
    const double t = bound.t[v];
    const auto it = std::upper_bound(station_t_.begin(), station_t_.end(), t);
    const std::size_t p = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - station_t_.begin() - 1, 0), spans - 1);
    span_of[v] = static_cast<std::uint32_t>(p);
  }
  group_begin_.assign(spans + 1, 0);
  for (std::uint32_t p : span_of) ++group_begin_[p + 1];
  for (std::size_t p = 0; p < spans; ++p) group_begin_[p + 1] += group_begin_[p];
  std::vector<std::uint32_t> fill(group_begin_.begin(), group_begin_.end() - 1);

  vertex_.resize(count);
  u_.resize(count);
  a_.resize(count);
  b_.resize(count);
  z_.resize(count);
  c0_.resize(count);
  c1_.resize(count);
  c2_.resize(count);
  c3_.resize(count);
  j_.resize(count);
  for (std::size_t v = 0; v < count; ++v) {
    const std::uint32_t p = span_of[v];
    const std::uint32_t o = fill[p]++;
    const SweepCoords c = bound.coords(v);
    vertex_[o] = bound.vertices[v];
    const double t0 = station_t_[p], t1 = station_t_[p + 1];
    u_[o] = static_cast<float>(std::clamp((c.t - t0) / (t1 - t0), 0.0, 1.0));
    a_[o] = static_cast<float>(c.s * std::cos(c.theta));
    b_[o] = static_cast<float>(c.s * std::sin(c.theta));
    z_[o] = static_cast<float>(c.z);
    // Periodic Catmull-Rom through samples j-1, j, j+1, j+2 at local coordinate w, as weights.
    const AngleCoord ac = locate_angle(n_, c.theta);
    const double w = ac.w, w2 = w * w, w3 = w2 * w;
    const double h00 = 2 * w3 - 3 * w2 + 1, h10 = w3 - 2 * w2 + w, h01 = -2 * w3 + 3 * w2, h11 = w3 - w2;
    c0_[o] = static_cast<float>(-0.5 * h10);
    c1_[o] = static_cast<float>(h00 - 0.5 * h11);
    c2_[o] = static_cast<float>(0.5 * h10 + h01);
    c3_[o] = static_cast<float>(0.5 * h11);
    j_[o] = static_cast<std::uint16_t>(ac.j);  // padded row: sample j-1 sits at j
    if (!bound.weight.empty() && bound.weight[v] < 1.0f) {
      blend_index_.push_back(o);
      blend_weight_.push_back(bound.weight[v]);
      blend_rest_.push_back(rest_positions[bound.vertices[v]]);
    }
  }
}

void FastDeformer::tabulate(const SweepShape& shape) {
  double lowest = shape.radii.empty() ? 0.0 : *std::min_element(shape.radii.begin(), shape.radii.end());
  radius_floor_ = static_cast<float>(kMinRadiusFraction * lowest);
  for (std::size_t q = 0; q < station_t_.size(); ++q) {
    float* row = stations_.data() + q * row_;
    const Frame f = frame_at(shape, station_t_[q]);
    const Mat3 r = f.matrix();
    for (int c = 0; c < 3; ++c) {
      row[kCenter + c] = static_cast<float>(f.center[c]);
      row[kAxisX + c] = static_cast<float>(r(c, 0));
      row[kAxisY + c] = static_cast<float>(r(c, 1));
      row[kAxisZ + c] = static_cast<float>(r(c, 2));
    }
    radii_at_samples(shape, station_t_[q], radii_scratch_);
    float* radii = row + kRadii;
    radii[0] = static_cast<float>(radii_scratch_[n_ - 1]);
    for (int j = 0; j < n_; ++j) radii[j + 1] = static_cast<float>(radii_scratch_[j]);
    radii[n_ + 1] = static_cast<float>(radii_scratch_[0]);
    radii[n_ + 2] = static_cast<float>(radii_scratch_[1 % n_]);
  }
}

void FastDeformer::deform(const SweepShape& deformed, std::span<Vec3f> out) {
  tabulate(deformed);
  const std::ptrdiff_t groups = static_cast<std::ptrdiff_t>(group_begin_.size()) - 1;
  const float floor = radius_floor_;
  float* const dst = out.data()->data();
#pragma omp parallel for schedule(dynamic, 4) if (vertex_.size() >= kParallelVertexThreshold)
  for (std::ptrdiff_t g = 0; g < groups; ++g) {
    const float* A = stations_.data() + g * row_;
    const float* B = A + row_;
    const float* ra = A + kRadii;
    const float* rb = B + kRadii;
    // Loop invariants of the group: station A and the difference to station B.
    float ca[12], cd[12];
    for (int c = 0; c < 12; ++c) {
      ca[c] = A[c];
      cd[c] = B[c] - A[c];
    }
    for (std::uint32_t i = group_begin_[g]; i < group_begin_[g + 1]; ++i) {
      const float u = u_[i];
      const int j = j_[i];
      const float r0 = c0_[i] * ra[j] + c1_[i] * ra[j + 1] + c2_[i] * ra[j + 2] + c3_[i] * ra[j + 3];
      const float r1 = c0_[i] * rb[j] + c1_[i] * rb[j + 1] + c2_[i] * rb[j + 2] + c3_[i] * rb[j + 3];
      const float r = std::max(r0 + u * (r1 - r0), floor);
      const float x = r * a_[i], y = r * b_[i], z = z_[i];
      float* o = dst + 3 * static_cast<std::size_t>(vertex_[i]);
      for (int c = 0; c < 3; ++c) {
        o[c] = (ca[kCenter + c] + u * cd[kCenter + c]) + (ca[kAxisX + c] + u * cd[kAxisX + c]) * x +
               (ca[kAxisY + c] + u * cd[kAxisY + c]) * y + (ca[kAxisZ + c] + u * cd[kAxisZ + c]) * z;
      }
    }
  }
  for (std::size_t b = 0; b < blend_index_.size(); ++b) {
    Vec3f& o = out[vertex_[blend_index_[b]]];
    o = blend_rest_[b] + blend_weight_[b] * (o - blend_rest_[b]);
  }
}

}  // namespace sweep::sim
