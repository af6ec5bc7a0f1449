// Key sections along a traced axis: where to cut them and their radius samples (fit.h,
// sections_along).
//
// A section is the plane slice normal to the axis, and most planes cut only the part. Some do
// not: at the root a plane tilted against the body cuts into it; at a sharp elbow (a bend tighter
// than the tube's radius) or where the part lies against the body, the plane also cuts the body,
// the leg beyond the knee or a neighbouring part, and its loop is several times the tube's size.
// Such a section is moved along the axis, within its share of the spacing, to where the plane
// cuts the part alone (the end sections inwards, by up to a quarter of the length); where no
// plane nearby does, its radii are interpolated from the nearest good sections on either side.
// A plane through the part and another tube fused to it side by side (homer's thighs) cuts one
// loop around both, pinched between them: loop_around keeps the part's piece, a section of the
// part, which an interior section takes. An end section does not stay there but moves as above
// (keeping the piece if no plane nearby is clean): on the part's side of that plane its surface
// passes to the other tube (through the crotch), around the root disc, and the part's walk would
// take the other tube (homer's right leg, its root section cut to the leg's piece but left there,
// took 444 vertices of the left leg; moved 0.0042 towards the tip, none).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sweep/core/text.h"
#include "sweep/fit/fit.h"
#include "sweep/fit/loop.h"

namespace sweep::fit {
namespace {

// A section loop larger than this many local radii (the axis' own slices, which are checked
// against the rings) also cuts another surface.
constexpr double kMaxSectionRadii = 1.5;
// An interior section may move up to this many eighths of the spacing either way (so that the
// sections stay in order).
constexpr int kMaxShiftEighths = 3;
// An end section may move inwards by up to this share of the axis length, in quarter spacings.
constexpr double kMaxEndShiftShare = 0.25;
// A section plane that passes through vertices of the mesh (a ring of a generated tube, an end cap
// lying in it) gets a degenerate slice from the slicer: polylines that double back on
// themselves, or a flat cap's fan cut along its spokes, so rays cross the loop twice or miss it.
// Such a section is cut again this share of its radius off its plane, along the axis (inwards
// first), where the plane meets edges, not vertices: far below any change of the shape.
constexpr double kSectionNudge = 1e-6;

// Position, tangent and local radius on the axis polyline at arc length t.
struct AxisSample {
  Vec3 point;
  Vec3 tangent;
  double radius;
};

AxisSample sample_axis(const AxisTrace& axis, const std::vector<double>& radii, const std::vector<double>& s,
                       double t) {
  const std::size_t m = axis.points.size();
  std::size_t k = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), t) - s.begin());
  k = std::clamp<std::size_t>(k, 1, m - 1) - 1;  // segment k → k+1
  const double span = s[k + 1] - s[k];
  const double u = span > 0 ? std::clamp((t - s[k]) / span, 0.0, 1.0) : 0.0;
  return {(1 - u) * axis.points[k] + u * axis.points[k + 1],
          ((1 - u) * axis.tangents[k] + u * axis.tangents[k + 1]).normalized(), (1 - u) * radii[k] + u * radii[k + 1]};
}

// The axis' local radii with the gaps (0: no slice there) filled from the nearest measured
// points on either side, linearly in arc length.
std::vector<double> filled_radii(const std::vector<double>& radii, const std::vector<double>& s) {
  std::vector<double> out = radii;
  const std::size_t m = radii.size();
  for (std::size_t i = 0; i < m; ++i) {
    if (out[i] > 0) continue;
    std::size_t lo = i, hi = i;
    while (lo > 0 && !(radii[lo] > 0)) --lo;
    while (hi + 1 < m && !(radii[hi] > 0)) ++hi;
    const bool has_lo = radii[lo] > 0, has_hi = radii[hi] > 0;
    if (has_lo && has_hi && s[hi] > s[lo]) {
      const double u = (s[i] - s[lo]) / (s[hi] - s[lo]);
      out[i] = (1 - u) * radii[lo] + u * radii[hi];
    } else if (has_lo || has_hi) {
      out[i] = has_lo ? radii[lo] : radii[hi];
    }
  }
  return out;
}

// One candidate section: its frame, its loop, its radius samples and whether the plane cuts the
// part alone.
struct Cut {
  double t = 0;
  Frame frame;
  std::optional<Loop> loop;
  RaySamples rays;
  double reach = 0;    // the local radius of the axis
  bool good = false;   // the loop is a section of the part (around the axis, not too wide)
  bool alone = false;  // ... and the plane cuts the part alone (no neck was cut: an end may go)
  bool star_shaped() const { return rays.multi_crossing_rays == 0 && rays.missed_rays == 0; }
};

class SectionCutter {
 public:
  SectionCutter(const MeshSlicer& slicer, const AxisTrace& axis, int radial)
      : slicer_(slicer),
        radial_(radial),
        axis_(axis),
        s_(arc_lengths(axis.points)),
        radii_(filled_radii(axis.radii, s_)),
        rmf_(rotation_minimizing_frames(axis.points, axis.tangents)) {}

  double length() const { return s_.back(); }

  Cut at(double t) const {
    Cut c;
    c.t = t;
    const AxisSample a = sample_axis(axis_, radii_, s_, t);
    // Carry the frame of the axis point at or before t to t by one double-reflection step.
    const std::size_t k = static_cast<std::size_t>(
        std::max<std::ptrdiff_t>(0, std::upper_bound(s_.begin(), s_.end(), t) - s_.begin() - 1));
    const Vec3 x_k = rmf_[k] * Vec3::UnitX();
    c.frame =
        Frame{rotation_minimizing_frames({axis_.points[k], a.point}, {axis_.tangents[k], a.tangent}, x_k)[1], a.point};
    c.reach = std::max(a.radius, 1e-9 * length());
    const auto slice = [&](double offset) {
      const Vec3 plane = a.point + offset * a.tangent;  // the rays still start at the centre
      std::optional<Loop> loop = loop_around(slicer_.slice(plane, a.tangent), plane, a.tangent, c.reach, Necks::cut);
      RaySamples rays;
      if (loop) rays = sample_radii(c.frame, loop->points, radial_);
      return std::make_pair(std::move(loop), std::move(rays));
    };
    std::tie(c.loop, c.rays) = slice(0);
    if (c.loop && !c.star_shaped()) {  // through vertices? (see kSectionNudge)
      const double inwards = t < length() / 2 ? 1 : -1;
      for (const double side : {inwards, -inwards}) {
        auto [loop, rays] = slice(side * kSectionNudge * c.reach);
        if (loop && rays.multi_crossing_rays == 0 && rays.missed_rays == 0) {
          c.loop = std::move(loop);
          c.rays = std::move(rays);
          break;
        }
      }
    }
    // Without a measured radius there is nothing to compare with: any loop around the axis does.
    c.good = c.loop && c.loop->around && (!(a.radius > 0) || c.loop->radius <= kMaxSectionRadii * a.radius);
    c.alone = c.good && c.loop->necks_cut == 0;
    return c;
  }

  // The first cut of the part alone from `from` towards `to` in steps of `step` (nullopt: none).
  std::optional<Cut> first_alone(double from, double to, double step) const {
    const int steps = static_cast<int>(std::floor(std::abs(to - from) / step + 1e-9));
    const double dir = to >= from ? 1 : -1;
    for (int k = 0; k <= steps; ++k) {
      Cut c = at(from + dir * k * step);
      if (c.alone) return c;
    }
    return std::nullopt;
  }

 private:
  const MeshSlicer& slicer_;
  int radial_;
  const AxisTrace& axis_;
  std::vector<double> s_;
  std::vector<double> radii_;
  std::vector<Quat> rmf_;
};

}  // namespace

SweepShape sections_along(const MeshSlicer& slicer, const AxisTrace& axis, int sections, int radial,
                          std::vector<StarViolation>* violations, std::vector<std::string>* warnings) {
  const SectionCutter cutter(slicer, axis, radial);
  const double length = cutter.length();
  const auto note = [&](const std::string& what) {
    if (warnings) warnings->push_back(what);
  };

  // The ends: moved inwards while their planes cut more than the part.
  const double quarter = length / (sections - 1) / 4;
  double start = 0, end = length;
  if (const Cut c0 = cutter.at(0); !c0.alone) {
    if (const std::optional<Cut> c = cutter.first_alone(quarter, kMaxEndShiftShare * length, quarter)) {
      start = c->t;
      note("section 0 moved " + format_number(start) + " along the axis from the root: the plane there also cut " +
           (c0.good ? "another tube fused to the part" : "the body"));
    }
  }
  if (const Cut c1 = cutter.at(length); !c1.alone) {
    if (const std::optional<Cut> c =
            cutter.first_alone(length - quarter, std::max(start, (1 - kMaxEndShiftShare) * length), quarter)) {
      if (c->t > start) {
        end = c->t;
        note("the last section moved " + format_number(length - end) +
             " along the axis from the tip: the plane there also cut " +
             (c1.good ? "another tube fused to the part" : "another surface"));
      }
    }
  }

  // The interior: each section moved within its share of the spacing to a plane that cuts the
  // part alone, nearest first.
  const double spacing = (end - start) / (sections - 1);
  std::vector<Cut> cuts(static_cast<std::size_t>(sections));
  int moved = 0;
  for (int i = 0; i < sections; ++i) {
    const double nominal = i == sections - 1 ? end : start + spacing * i;
    Cut c = cutter.at(nominal);
    if (!c.good && i > 0 && i < sections - 1) {
      for (int e = 1; e <= kMaxShiftEighths && !c.good; ++e) {
        for (const double sign : {1.0, -1.0}) {
          Cut shifted = cutter.at(nominal + sign * e * spacing / 8);
          if (shifted.good) {
            c = std::move(shifted);
            ++moved;
            break;
          }
        }
      }
    }
    cuts[static_cast<std::size_t>(i)] = std::move(c);
  }
  if (moved > 0) {
    note(std::to_string(moved) + " sections moved along the axis (by at most " + format_number(kMaxShiftEighths / 8.0) +
         " of the spacing) where their planes also cut another surface");
  }

  SweepShape shape;
  shape.radial_count = radial;
  shape.t.resize(static_cast<std::size_t>(sections));
  shape.frames.resize(static_cast<std::size_t>(sections));
  shape.radii.resize(static_cast<std::size_t>(sections) * radial);
  std::vector<char> sampled(static_cast<std::size_t>(sections), 0);
  for (int i = 0; i < sections; ++i) {
    const Cut& c = cuts[static_cast<std::size_t>(i)];
    shape.t[static_cast<std::size_t>(i)] = i == 0 ? 0.0 : c.t - start;
    shape.frames[static_cast<std::size_t>(i)] = c.frame;
    double* out = shape.radii.data() + static_cast<std::size_t>(i) * radial;
    std::fill(out, out + radial, c.reach);  // a circle of the axis' radius unless sampled
    // An end section keeps whatever its plane cuts (there is no neighbour beyond it); an
    // interior one only a section of the part (alone, or its piece of a pinched loop).
    const bool end_section = i == 0 || i == sections - 1;
    if (!c.loop || !(c.good || end_section)) continue;
    const RaySamples& rays = c.rays;
    std::copy(rays.radii.begin(), rays.radii.end(), out);
    sampled[static_cast<std::size_t>(i)] = 1;
    if ((rays.multi_crossing_rays > 0 || rays.missed_rays > 0) && violations) {
      violations->push_back({i, rays.multi_crossing_rays, rays.missed_rays});
    }
    if (c.loop->was_open) {
      note("section " + std::to_string(i) + ": the slice is an open polyline (a hole in the mesh), closed by its gap");
    }
  }

  // Sections no plane nearby cuts cleanly: radii interpolated from the nearest sampled sections
  // on either side (the frames are rotation-minimizing, so sample j points the same way).
  std::vector<int> filled;
  for (int i = 0; i < sections; ++i) {
    if (sampled[static_cast<std::size_t>(i)]) continue;
    int lo = i, hi = i;
    while (lo >= 0 && !sampled[static_cast<std::size_t>(lo)]) --lo;
    while (hi < sections && !sampled[static_cast<std::size_t>(hi)]) ++hi;
    if (lo < 0 && hi >= sections) break;  // nothing sampled: the circles stay
    const double u = lo < 0 ? 1.0
                     : hi >= sections
                         ? 0.0
                         : (shape.t[static_cast<std::size_t>(i)] - shape.t[static_cast<std::size_t>(lo)]) /
                               (shape.t[static_cast<std::size_t>(hi)] - shape.t[static_cast<std::size_t>(lo)]);
    for (int j = 0; j < radial; ++j) {
      const double a = lo < 0 ? 0.0 : shape.radius_sample(lo, j);
      const double b = hi >= sections ? 0.0 : shape.radius_sample(hi, j);
      shape.radii[static_cast<std::size_t>(i) * radial + static_cast<std::size_t>(j)] = (1 - u) * a + u * b;
    }
    filled.push_back(i);
  }
  if (!filled.empty()) {
    std::string which;
    for (const int i : filled) which += (which.empty() ? "" : ", ") + std::to_string(i);
    note("section" + std::string(filled.size() > 1 ? "s " : " ") + which +
         ": no plane near there cuts the part alone (a bend tighter than the tube, or another "
         "surface against it); radii interpolated from the neighbouring sections");
  }
  return shape;
}

}  // namespace sweep::fit
