// The skinned export's joints posed live (skin_joints.h).
#include "sweep/sim/skin_joints.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "sweep/core/error.h"
#include "sweep/core/locate.h"

namespace sweep::sim {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
// The export's ranges (assets::kMinSkinJoints … kMaxSkinJoints, 1 … kMaxRingJoints).
constexpr int kMinStations = 2, kMaxStations = 255, kMaxRing = 64;

// A joint's world matrix [R·S | t] into 16 column-major floats.
void store(const Mat3& rs, const Vec3& t, float* out) {
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) out[4 * c + r] = static_cast<float>(rs(r, c));
    out[4 * c + 3] = 0.0f;
  }
  for (int r = 0; r < 3; ++r) out[12 + r] = static_cast<float>(t[r]);
  out[15] = 1.0f;
}

}  // namespace

SkinJoints::SkinJoints(std::span<const SweepShape* const> rests, const SkinJointLayout& layout)
    : layout_(layout), rests_(rests.begin(), rests.end()) {
  const int N = layout.stations, M = layout.ring;
  if (N < kMinStations || N > kMaxStations)
    fail(ErrorCategory::usage, "joints a sweep: expected " + std::to_string(kMinStations) + " to " +
                                   std::to_string(kMaxStations) + ", got " + std::to_string(N));
  if (M < 1 || M > kMaxRing)
    fail(ErrorCategory::usage,
         "ring joints a station: expected 1 to " + std::to_string(kMaxRing) + ", got " + std::to_string(M));
  const bool ring = M > 1;
  for (const SweepShape* rest : rests_) {
    Sweep s;
    const int n = rest->radial_count, k = rest->section_count();
    s.length = rest->length();
    for (int j = 0; j < N; ++j) {
      Station st;
      st.t = j == N - 1 ? s.length : s.length * j / (N - 1);  // as the export places them
      const SpanCoord sc = locate_span(*rest, st.t);
      st.span = sc.span;
      st.u = sc.u;
      const HermiteBasis b(sc.u);
      st.h00 = b.h00, st.h10 = b.h10, st.h01 = b.h01, st.h11 = b.h11;
      s.stations.push_back(st);
    }
    s.frames.assign(static_cast<std::size_t>(N), Frame{});
    s.radii.assign(static_cast<std::size_t>(n), 0.0);
    for (int j = 0; j < n; ++j) {
      s.cos_sample.push_back(std::cos(rest->sample_angle(j)));
      s.sin_sample.push_back(std::sin(rest->sample_angle(j)));
    }
    if (ring) {
      for (int m = 0; m < M; ++m) {
        const AngleCoord ac = locate_angle(n, kTwoPi * m / M);
        s.rings.push_back({ac.j, ac.w});
      }
      for (int j = 1; j < N; ++j)
        for (int m = 0; m < M; ++m) s.rest_ring.push_back(radius_at(*rest, kTwoPi * m / M, s.stations[j].t));
      s.ring_scale.assign(s.rest_ring.size(), 1.0);
      s.cell_value.assign(static_cast<std::size_t>(k) * M, 0.0);
      s.cell_floor.assign(static_cast<std::size_t>(k) * M, 0.0);
    } else {
      s.rest_radii.resize(static_cast<std::size_t>(N) * n);
      for (int j = 0; j < N; ++j)
        radii_at_samples(*rest, s.stations[j].t,
                         std::span<double>(s.rest_radii.data() + static_cast<std::size_t>(j) * n, n));
      s.in_plane.assign(static_cast<std::size_t>(N) * 4, 0.0);
      for (int j = 0; j < N; ++j) s.in_plane[4 * j] = s.in_plane[4 * j + 1] = 1.0;
    }
    joint_count_ += N + (ring ? (N - 1) * M : 0);
    sweeps_.push_back(std::move(s));
  }
  for (std::size_t i = 0; i < sweeps_.size(); ++i) {
    for (int j = 0; j < N; ++j) sweeps_[i].frames[j] = frame_at(*rests_[i], sweeps_[i].stations[j].t);
  }
}

void SkinJoints::pose(int sweep, const SweepShape& shape, bool radii_moved) {
  Sweep& s = sweeps_[static_cast<std::size_t>(sweep)];
  const int N = layout_.stations, M = layout_.ring;
  for (int j = 0; j < N; ++j) s.frames[j] = frame_at(shape, s.stations[j].t);
  if (M > 1) {
    if (!radii_moved) {
      std::fill(s.ring_scale.begin(), s.ring_scale.end(), 1.0);
      return;
    }
    // radius_at(shape, φ_m, t_j) for every ring joint, with the same operations in the same order,
    // its angular cells evaluated once a section and angle rather than six times a joint.
    const int k = shape.section_count();
    for (int i = 0; i < k; ++i) {
      for (int m = 0; m < M; ++m) {
        const CatmullRomCell cell(shape.section_radii(i), s.rings[m].cell);
        s.cell_value[static_cast<std::size_t>(i) * M + m] = cell.at(s.rings[m].w);
        s.cell_floor[static_cast<std::size_t>(i) * M + m] = cell.min_sample();
      }
    }
    const auto value = [&](int i, int m) { return s.cell_value[static_cast<std::size_t>(i) * M + m]; };
    for (int j = 1; j < N; ++j) {
      const Station& st = s.stations[j];
      const int i0 = st.span, i1 = st.span + 1;
      const double h = shape.t[i1] - shape.t[i0];
      const int lo0 = std::max(i0 - 1, 0), hi0 = std::min(i0 + 1, k - 1);
      const int lo1 = std::max(i1 - 1, 0), hi1 = std::min(i1 + 1, k - 1);
      const double d0 = shape.t[hi0] - shape.t[lo0], d1 = shape.t[hi1] - shape.t[lo1];
      for (int m = 0; m < M; ++m) {
        const double r0 = value(i0, m), r1 = value(i1, m);
        double r;
        if (st.u == 0.0) {
          r = r0;
        } else if (st.u == 1.0) {
          r = r1;
        } else {
          const double slope0 = (value(hi0, m) - value(lo0, m)) / d0;
          const double slope1 = (value(hi1, m) - value(lo1, m)) / d1;
          r = st.h00 * r0 + st.h10 * h * slope0 + st.h01 * r1 + st.h11 * h * slope1;
          const double floor = kMinRadiusFraction * std::min(s.cell_floor[static_cast<std::size_t>(i0) * M + m],
                                                             s.cell_floor[static_cast<std::size_t>(i1) * M + m]);
          r = std::max(r, floor);
        }
        const std::size_t at = static_cast<std::size_t>(j - 1) * M + m;
        s.ring_scale[at] = std::max(r / s.rest_ring[at], kMinRadiusFraction);
      }
    }
    return;
  }
  // No ring: each station's in-plane scale and shift, fitted by least squares to its radii (the
  // export's fit): x' = a·x + c_x, y' = b·y + c_y over the samples (r_j cos θ_j, r_j sin θ_j).
  const int n = shape.radial_count;
  for (int j = 0; j < N; ++j) {
    double* f = s.in_plane.data() + 4 * j;
    if (!radii_moved) {
      f[0] = f[1] = 1.0;
      f[2] = f[3] = 0.0;
      continue;
    }
    radii_at_samples(shape, s.stations[j].t, s.radii);
    const double* rest = s.rest_radii.data() + static_cast<std::size_t>(j) * n;
    for (int axis = 0; axis < 2; ++axis) {
      const std::vector<double>& trig = axis == 0 ? s.cos_sample : s.sin_sample;
      double mx = 0, my = 0;
      for (int q = 0; q < n; ++q) {
        mx += rest[q] * trig[q];
        my += s.radii[q] * trig[q];
      }
      mx /= n;
      my /= n;
      double sxx = 0, sxy = 0;
      for (int q = 0; q < n; ++q) {
        const double x = rest[q] * trig[q] - mx, y = s.radii[q] * trig[q] - my;
        sxx += x * x;
        sxy += x * y;
      }
      const double scale = sxx > 0 && std::isfinite(sxy / sxx) ? sxy / sxx : 1.0;
      f[axis] = scale;
      f[2 + axis] = my - scale * mx;
    }
  }
}

void SkinJoints::world_matrices(const Frame& body, std::span<float> out) const {
  const Mat3 body_r = body.rotation.normalized().toRotationMatrix();
  store(body_r, body.center, out.data());
  float* o = out.data() + 16;
  const int N = layout_.stations, M = layout_.ring;
  for (const Sweep& s : sweeps_) {
    // Station joints, then (with a ring) the ring joints station by station.
    for (int j = 0; j < N; ++j) {
      const Frame& f = s.frames[j];
      const Mat3 r = body_r * f.rotation.normalized().toRotationMatrix();
      if (M > 1) {
        store(r, body_r * f.center + body.center, o);
      } else {
        const double* p = s.in_plane.data() + 4 * j;
        Mat3 rs = r;
        rs.col(0) *= p[0];
        rs.col(1) *= p[1];
        store(rs, body_r * (f.center + f.rotation * Vec3(p[2], p[3], 0)) + body.center, o);
      }
      o += 16;
    }
    if (M <= 1) continue;
    const float* stations = o - 16 * N;
    for (int j = 1; j < N; ++j) {
      // A ring joint scales its station's axes in-plane. The station copied out of the output
      // first: read through a pointer into the array being written, the loops below stayed scalar
      // (they might alias), and these 1100 joints took most of the read.
      float station[16];
      std::copy_n(stations + 16 * j, 16, station);
      const double* scale = s.ring_scale.data() + static_cast<std::size_t>(j - 1) * M;
      for (int m = 0; m < M; ++m, o += 16) {
        const float rho = static_cast<float>(scale[m]);
        for (int e = 0; e < 8; ++e) o[e] = station[e] * rho;
        for (int e = 8; e < 16; ++e) o[e] = station[e];
      }
    }
  }
}

}  // namespace sweep::sim
