#pragma once
// Closed tube meshes along any curve, with a known axis: the shape classes sweep-fit must follow
// (a curl, an elbow next to the body, a helix, a taper to a point, a tube leaving a big body).
// The surface is a sweep of circles along the curve (rotation-minimizing frames), radius r(s) at
// arc length s; the start is closed by a flat fan and the end by a hemisphere of the end radius
// (a point where the radius ends at 0). A "body" is a bulb in the radius profile at the start:
// an ellipsoid of revolution around the same curve, blended into the tube smoothly, so the part
// leaves a broad body the way a tail leaves a rump.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "sweep/core/mesh.h"

namespace sweep::test {

struct CurveTube {
  std::function<Vec3(double)> curve;     // any parameter u in [0, 1]
  std::function<double(double)> radius;  // r at arc length s
  int samples = 2000;                    // of the curve, for arc length and frames
  double ring_spacing = 0;               // along s; 0: a third of the smallest radius
  int segments = 32;

  // The curve resampled by arc length: points[i] at s = i · step.
  std::vector<Vec3> points;
  std::vector<Vec3> tangents;
  double step = 0;
  double length() const { return step * static_cast<double>(points.size() - 1); }

  void resample() {
    std::vector<Vec3> dense(static_cast<std::size_t>(samples) + 1);
    std::vector<double> s(dense.size(), 0.0);
    for (int i = 0; i <= samples; ++i) dense[i] = curve(static_cast<double>(i) / samples);
    for (std::size_t i = 1; i < dense.size(); ++i) s[i] = s[i - 1] + (dense[i] - dense[i - 1]).norm();
    const int n = samples;
    step = s.back() / n;
    points.assign(static_cast<std::size_t>(n) + 1, Vec3::Zero());
    std::size_t k = 0;
    for (int i = 0; i <= n; ++i) {
      const double x = step * i;
      while (k + 2 < s.size() && s[k + 1] < x) ++k;
      const double u = std::clamp((x - s[k]) / std::max(s[k + 1] - s[k], 1e-300), 0.0, 1.0);
      points[static_cast<std::size_t>(i)] = (1 - u) * dense[k] + u * dense[k + 1];
    }
    tangents.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, points.size() - 1);
      tangents[i] = (points[b] - points[a]).normalized();
    }
  }

  Vec3 axis_at(double s) const {
    const double x = std::clamp(s / step, 0.0, static_cast<double>(points.size() - 1));
    const auto i = static_cast<std::size_t>(std::min(x, static_cast<double>(points.size() - 2)));
    const double u = x - static_cast<double>(i);
    return (1 - u) * points[i] + u * points[i + 1];
  }
  Vec3 tangent_at(double s) const {
    const double x = std::clamp(s / step, 0.0, static_cast<double>(points.size() - 1));
    return tangents[static_cast<std::size_t>(std::lround(x))];
  }

  // Distance from p to the axis (the curve, and its straight continuation into the end's
  // hemisphere), and the arc length of the nearest point.
  double distance_to_axis(const Vec3& p, double* at = nullptr) const {
    double best = 1e300;
    const double r_end = std::max(radius(length()), 0.0);
    const Vec3 into_cap = p - points.back();
    const double u_cap = std::clamp(into_cap.dot(tangents.back()), 0.0, r_end);
    if (u_cap > 0) {
      best = (into_cap - u_cap * tangents.back()).norm();
      if (at) *at = length() + u_cap;
    }
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const Vec3 ab = points[i + 1] - points[i];
      const double u = std::clamp((p - points[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double d = (points[i] + u * ab - p).norm();
      if (d < best) {
        best = d;
        if (at) *at = step * (static_cast<double>(i) + u);
      }
    }
    return best;
  }

  Mesh mesh() {
    if (points.empty()) resample();
    const double len = length();
    double smallest = 1e300;
    for (int i = 0; i <= 200; ++i) smallest = std::min(smallest, std::max(radius(len * i / 200), 1e-9));
    const double spacing = ring_spacing > 0 ? ring_spacing : std::max(smallest, 0.05 * radius(0)) / 3;
    const int rings = std::max(2, static_cast<int>(std::ceil(len / spacing)) + 1);
    Mesh m;
    // Rotation-minimizing frames by double reflection along the resampled curve.
    std::vector<Vec3> normals(points.size());
    Vec3 t0 = tangents[0];
    Vec3 n0 = (std::abs(t0.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(t0).normalized();
    normals[0] = n0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const Vec3 v1 = points[i + 1] - points[i];
      const double c1 = v1.squaredNorm();
      const Vec3 rl = normals[i] - (2 / c1) * v1.dot(normals[i]) * v1;
      const Vec3 tl = tangents[i] - (2 / c1) * v1.dot(tangents[i]) * v1;
      const Vec3 v2 = tangents[i + 1] - tl;
      const double c2 = v2.squaredNorm();
      normals[i + 1] = (c2 > 0 ? rl - (2 / c2) * v2.dot(rl) * v2 : rl).normalized();
    }
    const auto frame_at = [&](double s, Vec3& c, Vec3& u, Vec3& v) {
      const double x = std::clamp(s / step, 0.0, static_cast<double>(points.size() - 1));
      const auto i = static_cast<std::size_t>(std::lround(x));
      c = axis_at(s);
      const Vec3 t = tangents[i];
      u = (normals[i] - normals[i].dot(t) * t).normalized();
      v = t.cross(u);
    };
    const auto ring_vertex = [&](double s, double r, int j) {
      Vec3 c, u, v;
      frame_at(s, c, u, v);
      const double th = 2 * std::numbers::pi * j / segments;
      return Vec3(c + r * (std::cos(th) * u + std::sin(th) * v));
    };
    const double r_end = radius(len);
    // The hemisphere at the end: rings on a quarter circle beyond s = len.
    const int cap_rings =
        r_end > 0 ? std::max(3, static_cast<int>(std::ceil(r_end * std::numbers::pi / 2 / spacing))) : 0;
    for (int i = 0; i < rings; ++i) {
      const double s = len * i / (rings - 1);
      for (int j = 0; j < segments; ++j) m.positions.push_back(ring_vertex(s, std::max(radius(s), 0.0), j));
    }
    Vec3 c_end, u_end, v_end;
    frame_at(len, c_end, u_end, v_end);
    const Vec3 t_end = tangents.back();
    for (int i = 1; i < cap_rings; ++i) {
      const double a = std::numbers::pi / 2 * i / cap_rings;
      for (int j = 0; j < segments; ++j) {
        const double th = 2 * std::numbers::pi * j / segments;
        m.positions.push_back(c_end + r_end * std::sin(a) * t_end +
                              r_end * std::cos(a) * (std::cos(th) * u_end + std::sin(th) * v_end));
      }
    }
    const int all_rings = rings + std::max(cap_rings - 1, 0);
    const auto id = [&](int i, int j) {
      return static_cast<std::uint32_t>(i * segments + ((j % segments) + segments) % segments);
    };
    const auto start = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(points.front());
    m.positions.push_back(r_end > 0 ? Vec3(c_end + r_end * t_end) : points.back());
    for (int i = 0; i + 1 < all_rings; ++i) {
      for (int j = 0; j < segments; ++j) {
        m.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
        m.add_face({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      }
    }
    for (int j = 0; j < segments; ++j) {
      m.add_face({start, id(0, j + 1), id(0, j)});
      m.add_face({start + 1, id(all_rings - 1, j), id(all_rings - 1, j + 1)});
    }
    return m;
  }
};

// A radius profile with a body: an ellipsoid of revolution of radius `body` over arc length
// [0, body_length] around the curve, smoothly merged (a soft maximum) with the tube's own
// profile `tube`.
inline std::function<double(double)> with_body(double body, double body_length, std::function<double(double)> tube) {
  return [=](double s) {
    const double x = (s - body_length / 2) / (body_length / 2);
    const double bulb = x < 1 ? body * std::sqrt(std::max(0.0, 1 - x * x)) : 0.0;
    const double r = tube(s);
    constexpr double p = 8;
    return std::pow(std::pow(bulb, p) + std::pow(r, p), 1 / p);
  };
}

}  // namespace sweep::test
