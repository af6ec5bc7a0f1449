#pragma once
// Shared by tests/assets/bake_*_test.cpp: a tube-like mesh, a made-up bake over it, and file helpers.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "scratch_dir.h"
#include "sweep/assets/bake.h"
#include "sweep/core/mesh.h"

namespace sweep::test {

// A tube along +z: `rings` rings of `segments` vertices (ring i at z = 0.25 i, radius 1 growing
// slightly), quads between rings, and the first ring closed by one polygon of `segments` corners
// (so OBJ must keep polygons as they are). Vertex v = ring * segments + segment.
inline Mesh make_tube(int rings, int segments) {
  Mesh mesh;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const double a = 2 * std::numbers::pi * j / segments;
      const double r = 1.0 + 0.01 * i;
      mesh.positions.emplace_back(r * std::cos(a), r * std::sin(a), 0.25 * i);
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * segments + (j % segments)); };
  std::vector<std::uint32_t> cap;
  for (int j = segments - 1; j >= 0; --j) cap.push_back(id(0, j));
  mesh.face_vertices.insert(mesh.face_vertices.end(), cap.begin(), cap.end());
  mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      mesh.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
    }
  }
  return mesh;
}

// A bake of that tube: the last `moving_fraction` of the rings bend, swell and twist; everything
// else stays exactly at rest. Frame 0 is the rest pose (all deltas zero).
struct TestBake {
  Mesh mesh;
  assets::BakeInfo info;
  std::vector<std::vector<Eigen::Vector3f>> frames;
};

inline std::vector<Eigen::Vector3f> rest_floats(const Mesh& mesh) {
  std::vector<Eigen::Vector3f> out;
  for (const Vec3& p : mesh.positions) out.push_back(p.cast<float>());
  return out;
}

// Positions of frame k: vertices of rings >= first_moving move, the others stay at rest.
inline void bend_frame(const Mesh& mesh, int segments, int first_moving, int k, std::vector<Eigen::Vector3f>& out) {
  out.resize(mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3& p = mesh.positions[v];
    const int ring = static_cast<int>(v) / segments;
    Eigen::Vector3f q = p.cast<float>();
    if (ring >= first_moving && k > 0) {
      const float s = static_cast<float>(ring - first_moving + 1) * 0.1f;
      const float phase = 0.3f * static_cast<float>(k);
      q.x() += s * s * std::sin(phase);
      q.y() += 0.05f * s * std::cos(phase + 0.1f * static_cast<float>(ring));
      q.z() += 0.01f * std::sin(2 * phase) * s;
    }
    out[v] = q;
  }
}

inline TestBake make_test_bake(int rings = 12, int segments = 8, int frames = 5, double moving_fraction = 0.3,
                               bool list_animated = true) {
  TestBake bake;
  bake.mesh = make_tube(rings, segments);
  const int first_moving = rings - static_cast<int>(std::lround(rings * moving_fraction));
  bake.info.frame_count = frames;
  bake.info.fps = 24;
  if (list_animated) {
    std::vector<std::uint32_t> animated;
    // Listed in descending order: the writers must sort.
    for (int v = rings * segments - 1; v >= first_moving * segments; --v) {
      animated.push_back(static_cast<std::uint32_t>(v));
    }
    bake.info.animated_vertices = animated;
  }
  bake.frames.resize(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    bend_frame(bake.mesh, segments, first_moving, k, bake.frames[static_cast<std::size_t>(k)]);
  }
  return bake;
}

inline void write_bake(const std::filesystem::path& out, const TestBake& bake) {
  auto writer = assets::make_bake_writer(out);
  writer->begin(bake.mesh, bake.info);
  for (std::size_t k = 0; k < bake.frames.size(); ++k) {
    writer->frame(static_cast<int>(k), bake.frames[k]);
  }
  writer->finish();
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A fresh, empty directory for one test, under the build tree.
inline std::filesystem::path fresh_dir(const std::string& name) {
  return scratch_dir_of_this_test("bake", name);
}

inline std::vector<std::string> list_dir(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace sweep::test
