#include "sweep/preview/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "sweep/core/error.h"

namespace sweep::preview {
namespace {

using Rgb = std::array<float, 3>;

constexpr Rgb kBackground{1.0f, 1.0f, 1.0f};
constexpr Rgb kBody{0.80f, 0.80f, 0.78f};
constexpr Rgb kSeparator{0.75f, 0.75f, 0.75f};
constexpr Rgb kAxis{0.80f, 0.05f, 0.05f};
// Part tints by part index (repeating); their key sections are drawn in the tint, darker.
constexpr std::array<Rgb, 6> kTints{{{0.96f, 0.62f, 0.26f},
                                     {0.36f, 0.62f, 0.96f},
                                     {0.46f, 0.80f, 0.40f},
                                     {0.80f, 0.48f, 0.86f},
                                     {0.30f, 0.80f, 0.80f},
                                     {0.96f, 0.46f, 0.46f}}};
constexpr float kRingDarkening = 0.45f;
// Hidden stretches of a key section are blended in this faintly (they show the ring's back).
constexpr float kHiddenBlend = 0.3f;
constexpr double kFill = 0.9;  // share of a view the mesh's largest extent takes

// A view: screen right, screen up, and towards the viewer (right x up = toward).
struct View {
  Vec3 right, up, toward;
};
const std::array<View, 3> kViews{{{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()},
                                  {-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()},
                                  {Vec3::UnitX(), -Vec3::UnitZ(), Vec3::UnitY()}}};

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width),
        height_(height),
        rgb_(3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height)),
        depth_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
               -std::numeric_limits<double>::infinity()) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) set(x, y, kBackground);
  }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  std::size_t at(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  }
  void set(int x, int y, const Rgb& c) {
    for (int k = 0; k < 3; ++k)
      rgb_[3 * at(x, y) + static_cast<std::size_t>(k)] =
          static_cast<float>(std::clamp(c[static_cast<std::size_t>(k)], 0.0f, 1.0f));
  }
  void blend(int x, int y, const Rgb& c, float share) {
    for (std::size_t k = 0; k < 3; ++k) {
      float& v = rgb_[3 * at(x, y) + k];
      v = (1 - share) * v + share * c[k];
    }
  }
  double& depth(int x, int y) { return depth_[at(x, y)]; }
  Image image() const {
    Image out{width_, height_, std::vector<std::uint8_t>(rgb_.size())};
    for (std::size_t i = 0; i < rgb_.size(); ++i) out.rgb[i] = static_cast<std::uint8_t>(std::lround(255.0f * rgb_[i]));
    return out;
  }

 private:
  int width_, height_;
  std::vector<float> rgb_;
  std::vector<double> depth_;
};

// A point on the canvas: pixel coordinates and depth (larger is nearer the viewer).
struct Projected {
  double x, y, z;
};

struct Projection {
  View view;
  Vec3 center;
  double scale;
  double left;  // the view's left edge on the canvas, pixels
  double size;
  Projected operator()(const Vec3& p) const {
    const Vec3 d = p - center;
    return {left + size / 2 + scale * d.dot(view.right), size / 2 - scale * d.dot(view.up), d.dot(view.toward)};
  }
};

void fill_triangle(Canvas& canvas, const Projection& proj, const Projected& a, const Projected& b, const Projected& c,
                   const Rgb& color) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::abs(area) > 1e-12)) return;
  const int x0 = std::max(static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))), static_cast<int>(proj.left));
  const int x1 =
      std::min(static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))), static_cast<int>(proj.left + proj.size) - 1);
  const int y0 = std::max(static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))), 0);
  const int y1 = std::min(static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))), static_cast<int>(proj.size) - 1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      // Barycentric weights by edge functions (either winding).
      const double wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
      const double wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
      const double wc = 1 - wa - wb;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      const double z = wa * a.z + wb * b.z + wc * c.z;
      if (z <= canvas.depth(x, y)) continue;
      canvas.depth(x, y) = z;
      canvas.set(x, y, color);
    }
  }
}

// A segment; where the surface hides it (by more than `tolerance` of depth), blended faintly, or
// drawn whole when `on_top`. `thick` doubles it a pixel to the right and below.
void draw_segment(Canvas& canvas, const Projected& a, const Projected& b, const Rgb& color, double tolerance,
                  bool on_top, bool thick) {
  // Overlays come from fits, which may reach far past the mesh: such a segment is not drawn.
  constexpr double kFar = 1e5;  // pixels
  for (const Projected* p : {&a, &b}) {
    if (!(std::abs(p->x) < kFar && std::abs(p->y) < kFar && std::isfinite(p->z))) return;
  }
  const int steps = static_cast<int>(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))) + 1;
  for (int i = 0; i <= steps; ++i) {
    const double u = static_cast<double>(i) / steps;
    const double x = a.x + u * (b.x - a.x), y = a.y + u * (b.y - a.y), z = a.z + u * (b.z - a.z);
    for (int k = 0; k < (thick ? 4 : 1); ++k) {
      const int px = static_cast<int>(std::floor(x)) + (k & 1), py = static_cast<int>(std::floor(y)) + (k >> 1);
      if (!canvas.inside(px, py)) continue;
      if (on_top || z >= canvas.depth(px, py) - tolerance) {
        canvas.set(px, py, color);
      } else {
        canvas.blend(px, py, color, kHiddenBlend);
      }
    }
  }
}

}  // namespace

std::vector<std::vector<Vec3>> section_outlines(const SweepShape& shape, int samples) {
  std::vector<std::vector<Vec3>> out;
  for (const double t : shape.t) {
    std::vector<Vec3>& loop = out.emplace_back();
    for (int k = 0; k < samples; ++k) {
      loop.push_back(surface_point(shape, 2 * std::numbers::pi * k / samples, t));
    }
  }
  return out;
}

Image render_views(const Mesh& mesh, const std::vector<Overlay>& parts, int view_size) {
  if (view_size < 32 || view_size > 4096) {
    fail(ErrorCategory::usage, "view_size must be 32 to 4096 pixels, got " + std::to_string(view_size));
  }
  if (mesh.positions.empty()) fail(ErrorCategory::bad_input, "render_views: the mesh has no vertices");
  Vec3 low = mesh.positions.front(), high = low;
  for (const Vec3& p : mesh.positions) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double extent = (high - low).maxCoeff();
  const double size = view_size;
  const double scale = extent > 0 ? kFill * size / extent : 1.0;
  Canvas canvas(3 * view_size, view_size);

  // Which part tints each vertex (the last part listing it).
  std::vector<int> part_of(mesh.vertex_count(), -1);
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (const std::uint32_t v : parts[i].vertices)
      if (v < part_of.size()) part_of[v] = static_cast<int>(i);
  const auto tint = [&](int part) { return kTints[static_cast<std::size_t>(part) % kTints.size()]; };

  const std::vector<std::uint32_t> tris = mesh.triangles();
  for (std::size_t v = 0; v < kViews.size(); ++v) {
    const Projection proj{kViews[v], (low + high) / 2, scale, static_cast<double>(v) * size, size};
    const Vec3 light = (0.3 * proj.view.right + 0.5 * proj.view.up + proj.view.toward).normalized();
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      const Vec3& a = mesh.positions[tris[t]];
      const Vec3& b = mesh.positions[tris[t + 1]];
      const Vec3& c = mesh.positions[tris[t + 2]];
      const Vec3 normal = (b - a).cross(c - a);
      const double n = normal.norm();
      const float shade = static_cast<float>(0.3 + 0.7 * (n > 0 ? std::abs(normal.dot(light)) / n : 0.0));
      // A face is the part's when all its corners are.
      const int part = part_of[tris[t]];
      const bool tinted = part >= 0 && part_of[tris[t + 1]] == part && part_of[tris[t + 2]] == part;
      Rgb color = tinted ? tint(part) : kBody;
      for (float& x : color) x *= shade;
      fill_triangle(canvas, proj, proj(a), proj(b), proj(c), color);
    }
    const double tolerance = 2.0 / scale;  // two pixels of depth
    for (std::size_t i = 0; i < parts.size(); ++i) {
      Rgb ring_color = tint(static_cast<int>(i));
      for (float& x : ring_color) x *= kRingDarkening;
      for (const std::vector<Vec3>& ring : parts[i].rings) {
        for (std::size_t k = 0; k < ring.size(); ++k) {
          draw_segment(canvas, proj(ring[k]), proj(ring[(k + 1) % ring.size()]), ring_color, tolerance, false, false);
        }
      }
      // The axis runs inside the part: drawn over it.
      for (std::size_t k = 0; k + 1 < parts[i].axis.size(); ++k) {
        draw_segment(canvas, proj(parts[i].axis[k]), proj(parts[i].axis[k + 1]), kAxis, tolerance, true, true);
      }
    }
    if (v > 0) {
      for (int y = 0; y < view_size; ++y) canvas.set(static_cast<int>(v) * view_size, y, kSeparator);
    }
  }
  return canvas.image();
}

}  // namespace sweep::preview
