// The fit preview's pixels where the geometry says they must be: the tube seen from the side,
// tinted where it is the part, grey where not, the axis red over it, a key section's outline on
// its surface; and the PNG bytes' header.
#include "sweep/preview/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fit/tubes.h"
#include "sweep/core/error.h"
#include "sweep/preview/png.h"

namespace sweep::preview {
namespace {

constexpr int kSize = 200;  // each view's side, pixels

struct Pixel {
  int r, g, b;
};
Pixel pixel(const Image& im, int x, int y) {
  const std::size_t i =
      3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(x));
  return {im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]};
}

// The straight test tube: along +Z from 0 to 1, radius 0.1, so its bounding box's largest extent
// is 1 and the views' scale is 0.9·kSize pixels a unit, centred on (0, 0, 0.5). In the side view
// (the second, looking along -X, screen right = -Z, up = +Y) the axis runs across the middle row.
struct SideView {
  int x_of(double z) const { return static_cast<int>(std::floor(1.5 * kSize - 0.9 * kSize * (z - 0.5))); }
  int y_of(double y) const { return static_cast<int>(std::floor(0.5 * kSize - 0.9 * kSize * y)); }
};

TEST(Preview, SideViewShowsTheTubeTintedWithItsAxisAndSection) {
  const Mesh mesh = test::Tube{}.mesh();
  Overlay part;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) part.vertices.push_back(v);
  part.axis = {Vec3(0, 0, 0), Vec3(0, 0, 1)};
  std::vector<Vec3>& ring = part.rings.emplace_back();
  for (int k = 0; k < 64; ++k) {
    const double a = 2 * std::numbers::pi * k / 64;
    ring.push_back(Vec3(0.1 * std::cos(a), 0.1 * std::sin(a), 0.25));
  }
  const Image tinted = render_views(mesh, {part}, kSize);
  const Image plain = render_views(mesh, {}, kSize);
  ASSERT_EQ(tinted.width, 3 * kSize);
  ASSERT_EQ(tinted.height, kSize);
  const SideView side;

  const Pixel corner = pixel(tinted, 1, 1);
  EXPECT_EQ(corner.r + corner.g + corner.b, 3 * 255) << "white ground";
  // On the axis: red, drawn over the surface.
  const Pixel axis = pixel(tinted, side.x_of(0.6), side.y_of(0));
  EXPECT_GT(axis.r, 150);
  EXPECT_LT(axis.g, 40);
  // Half a radius above the axis: the surface, orange-tinted (R > G > B) as the part, grey without.
  const Pixel surface = pixel(tinted, side.x_of(0.6), side.y_of(0.05));
  EXPECT_GT(surface.r, surface.g + 20);
  EXPECT_GT(surface.g, surface.b + 20);
  const Pixel grey = pixel(plain, side.x_of(0.6), side.y_of(0.05));
  EXPECT_LE(std::abs(grey.r - grey.b), 8);
  EXPECT_GT(grey.r, 80);
  // The key section at z = 0.25: a dark line across the tube there, absent a few pixels away.
  const Pixel section = pixel(tinted, side.x_of(0.25), side.y_of(0.05));
  EXPECT_LT(section.r + section.g + section.b, surface.r + surface.g + surface.b - 150);
  // Beyond the tube's end: ground.
  const Pixel beyond = pixel(tinted, side.x_of(1.05), side.y_of(0));
  EXPECT_EQ(beyond.r + beyond.g + beyond.b, 3 * 255);
}

TEST(Preview, PngBytesCarryTheSignatureAndTheSize) {
  Image im{5, 3, std::vector<std::uint8_t>(45, 200)};
  const std::string png = encode_png(im);
  ASSERT_GT(png.size(), 33u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 5u);
  EXPECT_EQ(be32(20), 3u);
  EXPECT_EQ(png[24], 8) << "bit depth";
  EXPECT_EQ(png[25], 2) << "colour type RGB";
  im.rgb.pop_back();
  EXPECT_THROW(encode_png(im), Error);
}

}  // namespace
}  // namespace sweep::preview
