#pragma once
// Private to lib/assets: where assimp's vertices go in world space, computed once for the mesh reader
// (mesh_import.cpp) and the skin reader (assimp_skin.cpp), which must agree to the bit: the skin
// reader finds each vertex the mesh reader read by its exact position.
#include <assimp/matrix4x4.h>
#include <assimp/vector3.h>

#include <Eigen/Core>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "sweep/core/frame.h"
#include "sweep/core/hash.h"

namespace sweep::assets::detail {

using Transform = Eigen::Matrix4d;

inline Transform to_transform(const aiMatrix4x4& m) {
  Transform t;
  t << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return t;
}

// A vertex placed by a node's world transform (`t`: the product of the node transforms from the root).
inline Vec3 apply(const Transform& t, const aiVector3D& v) {
  if (t.isIdentity(0.0)) return Vec3(v.x, v.y, v.z);  // exact: no arithmetic at all
  const Eigen::Vector4d h = t * Eigen::Vector4d(v.x, v.y, v.z, 1.0);
  return h.head<3>();
}

// Key for welding and matching by exact position: the bit patterns, with -0 and +0 counted as one.
struct PositionKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = kFnvOffset;  // FNV-1a's constants, a 64-bit word at a time: a table key, not a file's hash
    for (std::uint64_t b : k.bits) h = (h ^ b) * kFnvPrime;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
inline PositionKey key_of(const Vec3& p) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) key.bits[k] = std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k]);
  return key;
}

}  // namespace sweep::assets::detail
