// The world-space vertices of a live frame (live_positions.h).
#include "sweep/sim/live_positions.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "sweep/core/error.h"

namespace sweep::sim {

namespace {

constexpr std::uint32_t kUnbound = std::numeric_limits<std::uint32_t>::max();

// bind::transform_flat's product over every vertex in order, with the same bits (but for the sign of a zero), in
// half the instructions: output float i (coordinate c = i mod 3 of its vertex) is
//     out[i] = k0[i]·in[i−2] + k1[i]·in[i−1] + k2[i]·in[i] + k3[i]·in[i+1] + k4[i]·in[i+2] + t[c]
// summed in that order, with the coefficients R(c, ·) on the three floats of the same vertex and
// zero on the neighbours'. The coefficients repeat every 3 floats, so over 24 floats (8 vertices,
// three AVX2 vectors) they are constant vectors, and the loop is five shifted loads, products and
// sums a vector — where the x y z interleaving of bind::transform_flat costs shuffles or scalar code. The
// zeros' products add ±0, which changes a sum only if it is zero itself (to +0); the nonzero terms
// are added in bind::transform_flat's order: x, y, z, then t.
__attribute__((target_clones("avx2", "default"))) void transform_banded(const float* in, std::size_t count,
                                                                        const float* m, float* out) {
  constexpr int kWidth = 24;
  alignas(32) float k[5][kWidth];
  alignas(32) float shift[kWidth];
  for (int i = 0; i < kWidth; ++i) {
    const int c = i % 3;
    for (int d = 0; d < 5; ++d) {
      const int from = c + d - 2;  // the coordinate of the same vertex that offset d reaches, if any
      k[d][i] = from >= 0 && from < 3 ? m[3 * from + c] : 0.0f;
    }
    shift[i] = m[9 + c];
  }
  // The first vertex and those after the last whole group of 8 by bind::transform_flat (the band reads two
  // floats either side).
  std::size_t v = 1;
  for (; v + 9 <= count; v += 8) {
    const float* p = in + 3 * v;
    float* o = out + 3 * v;
    for (int i = 0; i < kWidth; ++i) {
      float sum = k[0][i] * p[i - 2];
      sum += k[1][i] * p[i - 1];
      sum += k[2][i] * p[i];
      sum += k[3][i] * p[i + 1];
      sum += k[4][i] * p[i + 2];
      o[i] = sum + shift[i];
    }
  }
  bind::transform_flat(in, std::min<std::size_t>(count, 1), m, out);
  if (v < count) bind::transform_flat(in + 3 * v, count - v, m, out + 3 * v);
}

}  // namespace

LivePositions::LivePositions(std::span<const bind::Vec3f> rest, std::span<const bind::FastDeformer* const> parts)
    : LivePositions(std::make_shared<const std::vector<bind::Vec3f>>(rest.begin(), rest.end()), parts) {}

LivePositions::LivePositions(std::shared_ptr<const std::vector<bind::Vec3f>> rest,
                             std::span<const bind::FastDeformer* const> parts)
    : rest_(std::move(rest)) {
  const std::vector<bind::Vec3f>& mesh = *rest_;
  std::size_t total = mesh.size();
  for (const bind::FastDeformer* part : parts) total += part->vertex_count();
  if (total >= kUnbound) fail(ErrorCategory::unsupported, "a mesh of " + std::to_string(mesh.size()) + " vertices");
  // Each part's vertices, in its grouped order, starting at their rest.
  std::vector<char> bound(mesh.size(), 0);
  for (const bind::FastDeformer* part : parts) {
    offset_.push_back(points_.size());
    for (const std::uint32_t v : part->grouped_vertices()) {
      if (v >= mesh.size() || bound[v])
        fail(ErrorCategory::usage,
             "the parts' vertices must be mesh vertices, each bound by one part (vertex " + std::to_string(v) + ")");
      bound[v] = 1;
      target_.push_back(v);
      points_.push_back(mesh[v]);
    }
  }
  world_points_.resize(points_.size());
}

void LivePositions::deform(int part, bind::FastDeformer& fast, const SweepShape& shape) {
  fast.deform_grouped(shape, std::span<bind::Vec3f>(points_.data() + offset_[part], fast.vertex_count()));
}

void LivePositions::world(const Eigen::Matrix3f& rotation, const bind::Vec3f& translation, float* out) const {
  float m[12];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m[3 * c + r] = rotation(r, c);
    m[9 + c] = translation[c];
  }
  transform_banded(rest_->data()->data(), rest_->size(), m, out);
  // The parts' vertices: carried as a block (the banded product, contiguous), then copied to their
  // places, rather than each product computed on its own at its scattered place (scalar code, ~3x
  // the instructions).
  if (points_.empty()) return;
  transform_banded(points_.data()->data(), points_.size(), m, world_points_.data()->data());
  const bind::Vec3f* from = world_points_.data();
  for (std::size_t i = 0; i < target_.size(); ++i) {
    float* o = out + 3 * static_cast<std::size_t>(target_[i]);
    o[0] = from[i][0];
    o[1] = from[i][1];
    o[2] = from[i][2];
  }
}

void LivePositions::local(float* out) const {
  std::memcpy(out, rest_->data(), rest_->size() * sizeof(bind::Vec3f));
  for (std::size_t i = 0; i < target_.size(); ++i) {
    float* o = out + 3 * static_cast<std::size_t>(target_[i]);
    o[0] = points_[i][0];
    o[1] = points_[i][1];
    o[2] = points_[i][2];
  }
}

}  // namespace sweep::sim
