#include "tube.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "sweep/core/error.h"

namespace sweep::tube {
namespace {

[[noreturn]] void usage(const std::string& message) {
  fail(ErrorCategory::usage, message);
}

std::string num(double x) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s << x;
  return s.str();
}

double shape_factor(const TubeParams& p, double theta) {
  switch (p.shape) {
    case CrossSection::circle:
      return 1.0;
    case CrossSection::ellipse: {
      const double q = p.ellipse_ratio, c = std::cos(theta), s = std::sin(theta);
      return q / std::sqrt(q * q * c * c + s * s);
    }
    case CrossSection::lobed:
      return 1.0 + p.lobe_amplitude * std::cos(p.lobes * theta);
  }
  return 1.0;
}

// Largest value of shape_factor over theta.
double max_shape_factor(const TubeParams& p) {
  switch (p.shape) {
    case CrossSection::circle:
      return 1.0;
    case CrossSection::ellipse:
      return std::max(1.0, p.ellipse_ratio);
    case CrossSection::lobed:
      return 1.0 + p.lobe_amplitude;
  }
  return 1.0;
}

}  // namespace

void check_params(const TubeParams& p) {
  if (!(p.length > 0) || !std::isfinite(p.length)) usage("--length must be positive (got " + num(p.length) + ")");
  if (!(p.radius > 0) || !std::isfinite(p.radius)) usage("--radius must be positive (got " + num(p.radius) + ")");
  if (!(p.taper > 0) || !std::isfinite(p.taper)) usage("--taper must be positive (got " + num(p.taper) + ")");
  if (!(std::abs(p.bend) <= 2 * std::numbers::pi)) {
    usage("--bend must be between -2pi and 2pi radians (got " + num(p.bend) + ")");
  }
  if (p.rings < 2) usage("--rings must be at least 2 (got " + std::to_string(p.rings) + ")");
  if (p.segments < 3) usage("--segments must be at least 3 (got " + std::to_string(p.segments) + ")");
  if (p.shape == CrossSection::ellipse && (!(p.ellipse_ratio > 0) || !std::isfinite(p.ellipse_ratio))) {
    usage("--ellipse-ratio must be positive (got " + num(p.ellipse_ratio) + ")");
  }
  if (p.shape == CrossSection::lobed) {
    if (p.lobes < 1) usage("--lobes must be at least 1 (got " + std::to_string(p.lobes) + ")");
    if (!(p.lobe_amplitude >= 0 && p.lobe_amplitude < 1)) {
      usage("--lobe-amplitude must be in [0, 1) (got " + num(p.lobe_amplitude) + ")");
    }
  }
  // Only the bend plane's inner side can fold: the widest section must stay inside the axis's
  // radius of curvature L / |bend|.
  if (p.bend != 0) {
    const double widest = p.radius * std::max(1.0, p.taper) * max_shape_factor(p);
    const double curvature_radius = p.length / std::abs(p.bend);
    if (widest >= curvature_radius) {
      usage("--bend " + num(p.bend) + " over --length " + num(p.length) + " curves the axis with radius " +
            num(curvature_radius) + ", no larger than the tube's widest section " + num(widest) +
            ": the tube would fold through itself");
    }
  }
}

Vec3 tube_axis_point(const TubeParams& p, double s) {
  if (p.bend == 0) return Vec3(0, 0, s);
  const double kappa = p.bend / p.length, a = kappa * s, h = std::sin(a / 2);
  return Vec3(2 * h * h / kappa, 0, std::sin(a) / kappa);
}

Vec3 tube_axis_tangent(const TubeParams& p, double s) {
  const double a = p.bend / p.length * s;
  return Vec3(std::sin(a), 0, std::cos(a));
}

AxisFrame tube_frame(const TubeParams& p, double s) {
  const double a = p.bend / p.length * s, c = std::cos(a), sn = std::sin(a);
  return AxisFrame{tube_axis_point(p, s), Vec3(sn, 0, c), Vec3(c, 0, -sn), Vec3(0, 1, 0)};
}

double tube_radius(const TubeParams& p, double theta, double s) {
  return p.radius * (1 + (p.taper - 1) * s / p.length) * shape_factor(p, theta);
}

Vec3 tube_surface_point(const TubeParams& p, double theta, double s) {
  const AxisFrame f = tube_frame(p, s);
  return f.point + tube_radius(p, theta, s) * (std::cos(theta) * f.u + std::sin(theta) * f.v);
}

double tube_ring_s(const TubeParams& p, int ring) {
  return ring == p.rings - 1 ? p.length : p.length * ring / (p.rings - 1);
}

double tube_segment_theta(const TubeParams& p, int segment) {
  return 2 * std::numbers::pi * segment / p.segments;
}

std::size_t tube_vertex_count(const TubeParams& p) {
  return static_cast<std::size_t>(p.rings) * static_cast<std::size_t>(p.segments) + (p.caps ? 2 : 0);
}

std::size_t tube_face_count(const TubeParams& p) {
  const std::size_t side = static_cast<std::size_t>(p.rings - 1) * static_cast<std::size_t>(p.segments);
  return side * (p.triangulate ? 2 : 1) + (p.caps ? 2 * static_cast<std::size_t>(p.segments) : 0);
}

Mesh make_tube(const TubeParams& p) {
  check_params(p);
  Mesh mesh;
  mesh.positions.reserve(tube_vertex_count(p));
  for (int i = 0; i < p.rings; ++i) {
    const double s = tube_ring_s(p, i);
    for (int j = 0; j < p.segments; ++j) {
      mesh.positions.push_back(tube_surface_point(p, tube_segment_theta(p, j), s));
    }
  }
  const auto n = static_cast<std::uint32_t>(p.segments);
  auto at = [n](int i, std::uint32_t j) { return static_cast<std::uint32_t>(i) * n + j % n; };
  for (int i = 0; i + 1 < p.rings; ++i) {
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t a = at(i, j), b = at(i, j + 1), c = at(i + 1, j + 1), d = at(i + 1, j);
      if (p.triangulate) {
        mesh.add_face({a, b, c});
        mesh.add_face({a, c, d});
      } else {
        mesh.add_face({a, b, c, d});
      }
    }
  }
  if (p.caps) {
    const auto root = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.push_back(tube_axis_point(p, 0));
    mesh.positions.push_back(tube_axis_point(p, p.length));
    const std::uint32_t tip = root + 1;
    for (std::uint32_t j = 0; j < n; ++j) mesh.add_face({root, at(0, j + 1), at(0, j)});
    for (std::uint32_t j = 0; j < n; ++j) mesh.add_face({tip, at(p.rings - 1, j), at(p.rings - 1, j + 1)});
  }
  return mesh;
}

}  // namespace sweep::tube
