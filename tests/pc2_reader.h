#pragma once
// A .pc2 point cache (Blender's Mesh Cache format: a 32-byte header, then every frame's points as
// float triples) read back whole by the tests that check a bake's motion.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

namespace sweep::test {

struct Pc2 {
  int points = 0, frames = 0;
  std::vector<Eigen::Vector3f> samples;  // frame-major: frame k's point v at k * points + v
  explicit Pc2(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char header[32] = {};
    in.read(header, 32);
    std::memcpy(&points, header + 16, 4);
    std::memcpy(&frames, header + 28, 4);
    samples.resize(static_cast<std::size_t>(points) * static_cast<std::size_t>(frames));
    in.read(reinterpret_cast<char*>(samples.data()), static_cast<std::streamsize>(12 * samples.size()));
    EXPECT_TRUE(in.good()) << path << ": shorter than its header says";
  }
  Eigen::Vector3d at(int frame, std::size_t v) const {
    return samples[static_cast<std::size_t>(frame) * static_cast<std::size_t>(points) + v].cast<double>();
  }
  // Every frame's points, frame by frame.
  std::vector<std::vector<Eigen::Vector3f>> by_frame() const {
    std::vector<std::vector<Eigen::Vector3f>> out;
    for (int k = 0; k < frames; ++k)
      out.emplace_back(samples.begin() + static_cast<std::ptrdiff_t>(k) * points,
                       samples.begin() + static_cast<std::ptrdiff_t>(k + 1) * points);
    return out;
  }
};

inline std::vector<std::vector<Eigen::Vector3f>> read_pc2(const std::filesystem::path& path) {
  return Pc2(path).by_frame();
}

}  // namespace sweep::test
