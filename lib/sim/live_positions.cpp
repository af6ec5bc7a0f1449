// The world-space vertices of a live frame (live_positions.h).
#include "sweep/sim/live_positions.h"

#include <limits>
#include <memory>
#include <string>

#include "sweep/core/error.h"

namespace sweep::sim {

namespace {

constexpr std::uint32_t kUnbound = std::numeric_limits<std::uint32_t>::max();

// out = R · p + t, with the operations of sim::transform_positions in its order (the same bits),
// compiled as it is (-O3, AVX2 or baseline x86-64, no FMA): for `count` points, into out in their
// order (target null) or into out's vertex target[i].
__attribute__((target_clones("avx2", "default"))) void transform(const float* points, const std::uint32_t* target,
                                                                 std::size_t count, const float* m, float* out) {
  const float r00 = m[0], r10 = m[1], r20 = m[2], r01 = m[3], r11 = m[4], r21 = m[5];
  const float r02 = m[6], r12 = m[7], r22 = m[8], t0 = m[9], t1 = m[10], t2 = m[11];
  if (target == nullptr) {
    for (std::size_t v = 0; v < count; ++v) {
      const float x = points[3 * v], y = points[3 * v + 1], z = points[3 * v + 2];
      out[3 * v] = r00 * x + r01 * y + r02 * z + t0;
      out[3 * v + 1] = r10 * x + r11 * y + r12 * z + t1;
      out[3 * v + 2] = r20 * x + r21 * y + r22 * z + t2;
    }
    return;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const float x = points[3 * i], y = points[3 * i + 1], z = points[3 * i + 2];
    float* o = out + 3 * static_cast<std::size_t>(target[i]);
    o[0] = r00 * x + r01 * y + r02 * z + t0;
    o[1] = r10 * x + r11 * y + r12 * z + t1;
    o[2] = r20 * x + r21 * y + r22 * z + t2;
  }
}

}  // namespace

LivePositions::LivePositions(std::span<const Vec3f> rest, std::span<const FastDeformer* const> parts)
    : LivePositions(std::make_shared<const std::vector<Vec3f>>(rest.begin(), rest.end()), parts) {}

LivePositions::LivePositions(std::shared_ptr<const std::vector<Vec3f>> rest, std::span<const FastDeformer* const> parts)
    : rest_(std::move(rest)) {
  const std::vector<Vec3f>& mesh = *rest_;
  std::size_t total = mesh.size();
  for (const FastDeformer* part : parts) total += part->vertex_count();
  if (total >= kUnbound) fail(ErrorCategory::unsupported, "a mesh of " + std::to_string(mesh.size()) + " vertices");
  // Each part's vertices, in its grouped order, starting at their rest.
  std::vector<char> bound(mesh.size(), 0);
  for (const FastDeformer* part : parts) {
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
}

void LivePositions::deform(int part, FastDeformer& fast, const SweepShape& shape) {
  fast.deform_grouped(shape, std::span<Vec3f>(points_.data() + offset_[part], fast.vertex_count()));
}

void LivePositions::world(const Eigen::Matrix3f& rotation, const Vec3f& translation, float* out) const {
  float m[12];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m[3 * c + r] = rotation(r, c);
    m[9 + c] = translation[c];
  }
  transform(rest_->data()->data(), nullptr, rest_->size(), m, out);
  transform(points_.data()->data(), target_.data(), target_.size(), m, out);
}

}  // namespace sweep::sim
