// The .pc2 bake writer: header fields and every sample, parsed back byte by byte.
#include <bit>
#include <cstring>

#include "bake_test_util.h"

namespace sweep::test {
namespace {

namespace fs = std::filesystem;

std::uint32_t u32_at(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 0; b < 4; ++b) {
    v |= std::uint32_t{static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(b)])} << (8 * b);
  }
  return v;
}

TEST(BakePc2, HeaderAndEverySampleReadBackExactly) {
  const TestBake bake = make_test_bake(10, 7, 6, 0.3);
  const fs::path out = fresh_dir("") / "tube.pc2";
  write_bake(out, bake);
  EXPECT_EQ(list_dir(out.parent_path()), std::vector<std::string>{"tube.pc2"});

  const std::string bytes = slurp(out);
  const std::size_t n = bake.mesh.vertex_count();
  const std::size_t frames = bake.frames.size();
  ASSERT_EQ(bytes.size(), 32 + frames * n * 12);
  EXPECT_EQ(std::memcmp(bytes.data(), "POINTCACHE2\0", 12), 0);
  EXPECT_EQ(u32_at(bytes, 12), 1u);                          // version
  EXPECT_EQ(u32_at(bytes, 16), n);                           // points
  EXPECT_EQ(std::bit_cast<float>(u32_at(bytes, 20)), 0.0f);  // start frame
  EXPECT_EQ(std::bit_cast<float>(u32_at(bytes, 24)), 1.0f);  // sample rate
  EXPECT_EQ(u32_at(bytes, 28), frames);                      // samples
  std::size_t at = 32;
  for (std::size_t k = 0; k < frames; ++k) {
    for (std::size_t v = 0; v < n; ++v) {
      for (int c = 0; c < 3; ++c, at += 4) {
        const float got = std::bit_cast<float>(u32_at(bytes, at));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(got), std::bit_cast<std::uint32_t>(bake.frames[k][v][c]))
            << "frame " << k << " vertex " << v << " component " << c;
      }
    }
  }
}

TEST(BakePc2, SingleFrameWithoutAnimatedListIsTheRestPose) {
  TestBake bake = make_test_bake(3, 4, 1, 0.0, /*list_animated=*/false);
  const fs::path out = fresh_dir("") / "rest.PC2";  // extension case does not matter
  write_bake(out, bake);
  const std::string bytes = slurp(out);
  ASSERT_EQ(bytes.size(), 32 + 12 * bake.mesh.vertex_count());
  EXPECT_EQ(u32_at(bytes, 28), 1u);
  EXPECT_EQ(std::memcmp(bytes.data() + 32, bake.frames[0].data(), 12 * bake.mesh.vertex_count()), 0);
}

}  // namespace
}  // namespace sweep::test
