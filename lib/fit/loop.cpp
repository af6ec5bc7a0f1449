#include "sweep/fit/loop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

namespace sweep::fit {
namespace {

// A ray's radius is floored at this fraction of the loop's largest extent from the centre, so a
// centre lying on the loop still gives a positive radius.
constexpr double kMinRadiusOfExtent = 1e-6;

bool contains(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

double boundary_distance(const std::vector<Vec2>& poly, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 ab = poly[i] - poly[j];
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0 ? std::clamp((p - poly[j]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (poly[j] + u * ab - p).norm());
  }
  return best;
}

// Necks (cut_at_necks). Measured on the loops loop_around picked at every axis point and key
// section of the 26 parts of BENCHMARKS.md's fit-evidence table and of three generated tubes
// (1,940 loops; the score is the chord over the thinner piece's thickness 2·area/perimeter, both
// pieces over a tenth of the loop's area): homer's fused thighs at the right leg's root, 0.36 (a
// figure 8: a chord 0.024 long between two discs of radius 0.065); elephant's trunk where the tusk
// lies against it, 0.155 (the tusk's outline joined to the trunk's by a neck); every other loop
// 0.648 or more (a bulge of an oblique slice through elephant's curled trunk; refined_elephant's
// curled trunk 0.92, dino's leg and foot 0.96); the flat ears 1.7 (bunny00) and 2.2 (armadillo),
// tube_lobed 2.1, tube_ellipse 2.4. A half of an ellipse cut across its middle scores 3.3 for a
// circle down to 4/π ≈ 1.27 however flat (a chord of 2b, a thickness of π b/2 at most).
// A chord is a neck when it is shorter than this share of the thinner piece's thickness: between
// homer's 0.36 and the 0.648 of the curled trunk's bulge, and well below the flat parts' 1.27.
constexpr double kMaxNeckOfThickness = 0.5;
// Each piece must hold at least this share of the loop's area: a sliver is no second tube (and a
// slice through mesh vertices can double back on itself, a chord of length 0 around nothing).
constexpr double kMinNeckPieceShare = 0.1;
// Cuts at most this many necks of one loop (a plane through a leg, the other leg and a hand).
constexpr int kMaxNeckCuts = 4;

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Whether segments pq and rs cross at a point inside both (touching at an end does not count).
bool segments_cross(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const double d1 = cross(q - p, r - p), d2 = cross(q - p, s - p);
  const double d3 = cross(s - r, p - r), d4 = cross(s - r, q - r);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// A neck of the closed polygon q: the chord from q[a] to q[b] (a < b); the inner piece is
// q[a..b], the outer q[b..m-1], q[0..a]. `keep_inner`: the piece that contains the point.
struct Neck {
  std::size_t a = 0, b = 0;
  bool keep_inner = true;
};

std::optional<Neck> find_neck(const std::vector<Vec2>& q, const Vec2& point) {
  const std::size_t m = q.size();
  if (m < 4) return std::nullopt;
  // Prefix sums of the shoelace terms and of the edge lengths: a piece's area and perimeter in
  // O(1). Relative to the point, which lies inside (the basis origin in loop_around).
  std::vector<double> twice_area(m + 1, 0.0), length(m + 1, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    const Vec2 a = q[i] - point, b = q[(i + 1) % m] - point;
    twice_area[i + 1] = twice_area[i] + cross(a, b);
    length[i + 1] = length[i] + (b - a).norm();
  }
  const double total = std::abs(twice_area[m]);
  if (!(total > 0)) return std::nullopt;
  // A piece's thickness 2A/P is at most its equivalent radius (isoperimetric inequality), so a
  // neck is shorter than kMaxNeckOfThickness equivalent radii of the whole loop.
  const double max_chord = kMaxNeckOfThickness * std::sqrt(total / 2 / std::numbers::pi);
  std::vector<std::size_t> by_x(m);
  for (std::size_t i = 0; i < m; ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](std::size_t i, std::size_t j) { return q[i].x() < q[j].x(); });
  struct Candidate {
    double score;
    std::size_t a, b;
  };
  std::vector<Candidate> candidates;
  for (std::size_t u = 0; u < m; ++u) {
    for (std::size_t w = u + 1; w < m && q[by_x[w]].x() - q[by_x[u]].x() < max_chord; ++w) {
      const std::size_t a = std::min(by_x[u], by_x[w]), b = std::max(by_x[u], by_x[w]);
      if (b - a < 2 || (a == 0 && b == m - 1)) continue;  // neighbours along the loop
      const double chord = (q[b] - q[a]).norm();
      if (!(chord < max_chord)) continue;
      const Vec2 qa = q[a] - point, qb = q[b] - point;
      const double inner = std::abs(twice_area[b] - twice_area[a] + cross(qb, qa));
      const double outer = std::abs(twice_area[m] - (twice_area[b] - twice_area[a]) + cross(qa, qb));
      if (inner < kMinNeckPieceShare * total || outer < kMinNeckPieceShare * total) continue;
      const double inner_thickness = inner / (length[b] - length[a] + chord);
      const double outer_thickness = outer / (length[m] - (length[b] - length[a]) + chord);
      const double score = chord / std::min(inner_thickness, outer_thickness);
      if (score < kMaxNeckOfThickness) candidates.push_back({score, a, b});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return x.score < y.score || (x.score == y.score && (x.a < y.a || (x.a == y.a && x.b < y.b)));
  });
  for (const Candidate& c : candidates) {
    // The chord must run inside the loop (across a C's mouth it runs outside): its midpoint
    // inside, and no edge but those at its ends crossing it.
    if (!contains(q, (q[c.a] + q[c.b]) / 2)) continue;
    bool crossed = false;
    for (std::size_t i = 0, j = m - 1; i < m && !crossed; j = i++) {
      crossed = segments_cross(q[c.a], q[c.b], q[j], q[i]);
    }
    if (crossed) continue;
    std::vector<Vec2> inner(q.begin() + static_cast<std::ptrdiff_t>(c.a),
                            q.begin() + static_cast<std::ptrdiff_t>(c.b) + 1);
    if (contains(inner, point)) return Neck{c.a, c.b, true};
    std::vector<Vec2> outer(q.begin() + static_cast<std::ptrdiff_t>(c.b), q.end());
    outer.insert(outer.end(), q.begin(), q.begin() + static_cast<std::ptrdiff_t>(c.a) + 1);
    if (contains(outer, point)) return Neck{c.a, c.b, false};
    return std::nullopt;  // the point lies on the neck: neither piece is its own
  }
  return std::nullopt;
}

// Keeps the piece of `v` (a closed loop, in step with the polygon the neck was found on) that the
// neck says.
template <class T>
void keep_piece(std::vector<T>& v, const Neck& n) {
  std::vector<T> out;
  if (n.keep_inner) {
    out.assign(v.begin() + static_cast<std::ptrdiff_t>(n.a), v.begin() + static_cast<std::ptrdiff_t>(n.b) + 1);
  } else {
    out.assign(v.begin() + static_cast<std::ptrdiff_t>(n.b), v.end());
    out.insert(out.end(), v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n.a) + 1);
  }
  v = std::move(out);
}

// cut_at_necks, keeping `alongside` (the same loop in 3D, point for point, or null) in step.
int cut_necks(std::vector<Vec2>& loop, const Vec2& point, std::vector<Vec3>* alongside) {
  int cuts = 0;
  for (; cuts < kMaxNeckCuts; ++cuts) {
    const std::optional<Neck> neck = find_neck(loop, point);
    if (!neck) break;
    keep_piece(loop, *neck);
    if (alongside) keep_piece(*alongside, *neck);
  }
  return cuts;
}

}  // namespace

int cut_at_necks(std::vector<Vec2>& loop, const Vec2& point) {
  return cut_necks(loop, point, nullptr);
}

PlaneBasis plane_basis(const Vec3& origin, const Vec3& normal) {
  PlaneBasis b;
  b.origin = origin;
  b.n = normal.normalized();
  // The world axis least aligned with n gives a well-conditioned u (deterministic).
  Eigen::Index k = 0;
  b.n.cwiseAbs().minCoeff(&k);
  b.u = (Vec3::Unit(k) - b.n * b.n[k]).normalized();
  b.v = b.n.cross(b.u);
  return b;
}

void measure_loop(const PlaneBasis& basis, Loop& loop) {
  double a2 = 0;  // twice the signed area
  Vec2 moment = Vec2::Zero();
  Vec2 mean = Vec2::Zero();
  const std::size_t m = loop.points.size();
  std::vector<Vec2> q(m);
  for (std::size_t i = 0; i < m; ++i) {
    q[i] = basis.to_plane(loop.points[i]);
    mean += q[i];
  }
  if (m > 0) mean /= static_cast<double>(m);
  for (std::size_t i = 0, j = m - 1; i < m; j = i++) {
    // Relative to the mean, so that loops far from the plane origin lose no precision.
    const Vec2 a = q[j] - mean, b = q[i] - mean;
    const double cross = a.x() * b.y() - a.y() * b.x();
    a2 += cross;
    moment += (a + b) * cross;
  }
  loop.area = std::abs(a2) / 2;
  loop.radius = std::sqrt(loop.area / std::numbers::pi);
  const double tiny = 1e-12 * (q.empty() ? 0.0 : (q[0] - mean).squaredNorm() + 1e-300);
  const Vec2 c = std::abs(a2) > tiny ? Vec2(mean + moment / (3 * a2)) : mean;
  // Put the centroid back in the loop's own plane (the slice plane, which may be offset from
  // the basis origin along n).
  double offset = 0;
  for (const Vec3& p : loop.points) offset += (p - basis.origin).dot(basis.n);
  if (m > 0) offset /= static_cast<double>(m);
  loop.centroid = basis.to_world(c) + offset * basis.n;
}

std::optional<Loop> loop_around(const std::vector<SlicePolyline>& slice, const Vec3& point, const Vec3& normal,
                                double max_distance, Necks necks) {
  const PlaneBasis basis = plane_basis(point, normal);
  const Vec2 p = Vec2::Zero();
  std::optional<std::size_t> best_inside, best_near;
  double best_area = std::numeric_limits<double>::infinity();
  double best_distance = max_distance;
  for (std::size_t i = 0; i < slice.size(); ++i) {
    const SlicePolyline& line = slice[i];
    if (line.points.size() < 3) continue;
    std::vector<Vec2> poly;
    poly.reserve(line.points.size());
    for (const Vec3& x : line.points) poly.push_back(basis.to_plane(x));
    if (contains(poly, p)) {
      double a2 = 0;
      for (std::size_t k = 0, j = poly.size() - 1; k < poly.size(); j = k++) {
        a2 += poly[j].x() * poly[k].y() - poly[j].y() * poly[k].x();
      }
      if (std::abs(a2) < best_area) {
        best_area = std::abs(a2);
        best_inside = i;
      }
    } else if (!best_inside) {
      const double d = boundary_distance(poly, p);
      if (d <= best_distance) {
        best_distance = d;
        best_near = i;
      }
    }
  }
  const std::optional<std::size_t> pick = best_inside ? best_inside : best_near;
  if (!pick) return std::nullopt;
  Loop loop;
  loop.points = slice[*pick].points;
  loop.was_open = !slice[*pick].closed;
  loop.around = best_inside.has_value();
  if (loop.around && necks == Necks::cut) {
    std::vector<Vec2> poly;
    poly.reserve(loop.points.size());
    for (const Vec3& x : loop.points) poly.push_back(basis.to_plane(x));
    loop.necks_cut = cut_necks(poly, p, &loop.points);
  }
  measure_loop(basis, loop);
  return loop;
}

RaySamples sample_radii(const Frame& frame, const std::vector<Vec3>& loop, int n) {
  RaySamples out;
  out.radii.assign(static_cast<std::size_t>(n), 0.0);
  const Mat3 r = frame.matrix();
  const Vec3 ex = r.col(0), ey = r.col(1);
  std::vector<Vec2> q;
  q.reserve(loop.size());
  double extent = 0;
  for (const Vec3& x : loop) {
    const Vec3 d = x - frame.center;
    q.emplace_back(d.dot(ex), d.dot(ey));
    extent = std::max(extent, q.back().norm());
  }
  const double floor = kMinRadiusOfExtent * extent;
  double hit_sum = 0;
  int hits = 0;
  std::vector<bool> missed(static_cast<std::size_t>(n), false);
  for (int j = 0; j < n; ++j) {
    const double theta = 2 * std::numbers::pi * j / n;
    const Vec2 dir(std::cos(theta), std::sin(theta));
    int crossings = 0;
    double outer = -1;
    // A segment crosses the ray's line where its ends lie on opposite sides of it. The side of
    // each vertex is computed once (on the line counts as below), so a ray through a vertex
    // crosses exactly one of the two segments that meet there, whatever the rounding.
    const auto side = [&](const Vec2& x) { return dir.x() * x.y() - dir.y() * x.x() > 0; };
    for (std::size_t i = 0, k = q.size() - 1; !q.empty() && i < q.size(); k = i++) {
      const Vec2 a = q[k], b = q[i];
      if (side(a) == side(b)) continue;
      const double ha = dir.x() * a.y() - dir.y() * a.x(), hb = dir.x() * b.y() - dir.y() * b.x();
      const double u = ha / (ha - hb);              // along the segment, where its height above the line is 0
      const double s = (a + u * (b - a)).dot(dir);  // along the ray
      if (!(s > 0)) continue;
      ++crossings;
      outer = std::max(outer, s);
    }
    if (crossings == 0) {
      missed[static_cast<std::size_t>(j)] = true;
      ++out.missed_rays;
      continue;
    }
    if (crossings > 1) ++out.multi_crossing_rays;
    out.radii[static_cast<std::size_t>(j)] = std::max(outer, floor);
    hit_sum += out.radii[static_cast<std::size_t>(j)];
    ++hits;
  }
  if (out.missed_rays > 0) {
    // The centre lies outside the loop (or on it): fall back to the mean of the rays that hit,
    // or the loop's mean distance when none did.
    double fill = hits > 0 ? hit_sum / hits : 0;
    if (hits == 0) {
      for (const Vec2& x : q) fill += x.norm();
      fill = q.empty() ? 0 : fill / static_cast<double>(q.size());
    }
    for (int j = 0; j < n; ++j) {
      if (missed[static_cast<std::size_t>(j)]) out.radii[static_cast<std::size_t>(j)] = std::max(fill, floor);
    }
  }
  return out;
}

}  // namespace sweep::fit
