#pragma once
// Smooth vertex normals, the one rule every .glb writer lights a mesh by: area-weighted face
// normals summed per vertex, in double. A vertex on no face (or only on degenerate ones) gets +Y,
// so every normal is a unit vector. A rest's and a frame's come from here alike, so a still
// vertex's normal delta is zero up to the positions' float rounding.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace sweep::assets::detail {

// `positions`: any indexable sequence of Eigen 3-vectors (float or double) with size().
template <typename Points>
std::vector<Eigen::Vector3f> smooth_normals(const Points& positions, const std::vector<std::uint32_t>& triangles) {
  std::vector<Eigen::Vector3d> sum(positions.size(), Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Eigen::Vector3d a = positions[triangles[t]].template cast<double>();
    const Eigen::Vector3d b = positions[triangles[t + 1]].template cast<double>();
    const Eigen::Vector3d c = positions[triangles[t + 2]].template cast<double>();
    const Eigen::Vector3d face = (b - a).cross(c - a);
    for (std::size_t k = 0; k < 3; ++k) sum[triangles[t + k]] += face;
  }
  std::vector<Eigen::Vector3f> normals(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const double length = sum[v].norm();
    normals[v] = length > 0 && std::isfinite(length) ? Eigen::Vector3f((sum[v] / length).cast<float>())
                                                     : Eigen::Vector3f::UnitY();
  }
  return normals;
}

}  // namespace sweep::assets::detail
