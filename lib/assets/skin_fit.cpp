// The skin's joints, weights and per-frame poses (skin_fit.h).
#include "sweep/assets/skin_fit.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "sweep/core/error.h"

namespace sweep::assets {

bool JointKey::operator==(const JointKey& o) const {
  return std::memcmp(this, &o, sizeof(JointKey)) == 0;
}

Eigen::Matrix4d key_matrix(const JointKey& k) {
  Eigen::Quaterniond q(k.r[3], k.r[0], k.r[1], k.r[2]);
  q.normalize();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = q.toRotationMatrix() * Eigen::Vector3d(k.s[0], k.s[1], k.s[2]).asDiagonal();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(k.t[0], k.t[1], k.t[2]);
  return m;
}

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

// The cross-section's change at a station as one joint carries it (no ring): in the station's
// plane, a scale along each of its axes and a shift, x' = a·x + c_x and y' = b·y + c_y, fitted by
// least squares to the sample points (r_j cos θ_j, r_j sin θ_j) → (r'_j cos θ_j, r'_j sin θ_j). A
// section that swells evenly gives a = b (its mean radius ratio) and no shift; one squeezed from a
// side, a smaller scale across the squeeze and a shift away from it.
struct InPlane {
  double a = 1, b = 1, cx = 0, cy = 0;
};
InPlane fit_in_plane(const SweepShape& shape, std::span<const double> rest, std::span<const double> now) {
  InPlane f;
  const std::size_t n = rest.size();
  for (int axis = 0; axis < 2; ++axis) {
    double mx = 0, my = 0;
    std::vector<double> x(n), y(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double angle = shape.sample_angle(static_cast<int>(j));
      const double c = axis == 0 ? std::cos(angle) : std::sin(angle);
      x[j] = rest[j] * c;
      y[j] = now[j] * c;
      mx += x[j];
      my += y[j];
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxx = 0, sxy = 0;
    for (std::size_t j = 0; j < n; ++j) {
      sxx += (x[j] - mx) * (x[j] - mx);
      sxy += (x[j] - mx) * (y[j] - my);
    }
    const double scale = sxx > 0 && std::isfinite(sxy / sxx) ? sxy / sxx : 1.0;
    (axis == 0 ? f.a : f.b) = scale;
    (axis == 0 ? f.cx : f.cy) = my - scale * mx;
  }
  return f;
}

JointKey key_of(const Frame& f, const InPlane& in_plane) {
  JointKey k{};
  const Vec3 t = f.center + f.rotation * Vec3(in_plane.cx, in_plane.cy, 0);
  for (int c = 0; c < 3; ++c) k.t[c] = static_cast<float>(t[c]);
  const Quat q = f.rotation.normalized();
  k.r[0] = static_cast<float>(q.x());
  k.r[1] = static_cast<float>(q.y());
  k.r[2] = static_cast<float>(q.z());
  k.r[3] = static_cast<float>(q.w());
  k.s[0] = static_cast<float>(in_plane.a);
  k.s[1] = static_cast<float>(in_plane.b);
  k.s[2] = 1.0f;
  return k;
}

std::string padded(int value, int largest) {
  std::string digits = std::to_string(value);
  const std::size_t width = std::max<std::size_t>(2, std::to_string(largest).size());
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  return digits;
}

}  // namespace

// One vertex's influence as the fit sees it.
struct Slot {
  int joint = 0;              // skin joint
  float weight = 0;           // as written
  int station = -1;           // -1: the body
  int unknown = -1;           // the ring joint's index among the sweep's ring unknowns; -1: none
  Vec3 local = Vec3::Zero();  // the rest vertex in the station's rest frame
};

struct SkinFit::SweepData {
  double length = 0;
  int first_station = 0;  // skin index of station 0
  int first_ring = 0;     // skin index of ring joint (station 1, angle 0); (j, m) is first_ring + (j−1)·M + m
  std::vector<double> station_t;
  std::vector<Frame> rest_frames;
  std::vector<std::vector<double>> rest_radii;  // per station (no ring: the in-plane fit)
  std::vector<double> ring_rest_radius;         // per ring unknown: r(φ_m, t_j) at rest
  std::vector<std::uint32_t> vertices;          // bound, in binding order
  std::vector<std::array<Slot, 4>> slots;       // per bound vertex
  // The ring fit: normal equations over the ring unknowns, their pattern fixed at construction.
  Eigen::SparseMatrix<double> normal;
  std::vector<std::array<int, 16>> value_index;  // per bound vertex: slot pair → index in normal's values
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  Eigen::VectorXd rhs, sampled, solved, pull;
  std::vector<Frame> frames;  // this frame's station frames (scratch)
  std::vector<double> radii;  // scratch
};

SkinFit::~SkinFit() = default;

SkinFit::SkinFit(std::vector<SkinSweep> sweeps, const SkinLayout& layout, std::span<const Eigen::Vector3f> rest,
                 const std::string& body_name)
    : sweeps_(std::move(sweeps)), layout_(layout), rest_(rest.begin(), rest.end()) {
  const int N = layout_.stations, M = layout_.ring;
  const bool ring = M > 1;
  const std::size_t n = rest_.size();
  joints_.push_back({body_name + "_root", -1, -1, -1, -1, 0, 0});
  rest_keys_.push_back(kIdentityKey);
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    auto d = std::make_unique<SweepData>();
    const SkinSweep& sw = sweeps_[s];
    d->length = sw.rest->length();
    d->first_station = static_cast<int>(joints_.size());
    for (int j = 0; j < N; ++j) {
      const double t = j == N - 1 ? d->length : d->length * j / (N - 1);
      d->station_t.push_back(t);
      d->rest_frames.push_back(frame_at(*sw.rest, t));
      std::vector<double> radii(static_cast<std::size_t>(sw.rest->radial_count));
      radii_at_samples(*sw.rest, t, radii);
      d->rest_radii.push_back(std::move(radii));
      joints_.push_back({sw.name + "." + padded(j, N - 1), 0, static_cast<int>(s), j, -1, t, 0});
      rest_keys_.push_back(key_of(d->rest_frames.back(), InPlane{}));
    }
    d->first_ring = static_cast<int>(joints_.size());
    if (ring) {
      for (int j = 1; j < N; ++j) {
        for (int m = 0; m < M; ++m) {
          const double angle = kTwoPi * m / M;
          joints_.push_back({sw.name + "." + padded(j, N - 1) + ".r" + padded(m, M - 1), d->first_station + j,
                             static_cast<int>(s), j, m, d->station_t[static_cast<std::size_t>(j)], angle});
          rest_keys_.push_back(kIdentityKey);
          d->ring_rest_radius.push_back(radius_at(*sw.rest, angle, d->station_t[static_cast<std::size_t>(j)]));
        }
      }
    }
    data_.push_back(std::move(d));
  }
  // Inverse bind matrices: the rest poses in the body's frame, from the keys as written.
  std::vector<Eigen::Matrix4d> rest_global(joints_.size());
  for (std::size_t k = 0; k < joints_.size(); ++k) {
    const Eigen::Matrix4d local = key_matrix(rest_keys_[k]);
    rest_global[k] = joints_[k].parent < 0 ? local : rest_global[static_cast<std::size_t>(joints_[k].parent)] * local;
    inverse_bind_.push_back(rest_global[k].inverse().cast<float>());
  }

  // Weights: the body joint alone for every vertex no sweep binds.
  vertex_joints_.assign(n, {0, 0, 0, 0});
  vertex_weights_.assign(n, {1.0f, 0.0f, 0.0f, 0.0f});
  std::vector<char> seen(n, 0);
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    SweepData& d = *data_[s];
    const bind::SweepBinding& b = *sweeps_[s].binding;
    const double h = d.length / (N - 1);
    for (std::size_t i = 0; i < b.size(); ++i) {
      const std::uint32_t v = b.vertices[i];
      if (v >= n || seen[v]) {
        fail(ErrorCategory::internal, "skin: vertex " + std::to_string(v) + " bound twice or not in the mesh");
      }
      seen[v] = 1;
      const double x = std::clamp(static_cast<double>(b.t[i]) / h, 0.0, double(N - 1));
      const int j = std::min(static_cast<int>(std::floor(x)), N - 2);
      const double u = x - j;
      const double blend = std::clamp(static_cast<double>(b.weight[i]), 0.0, 1.0);
      std::array<Slot, 5> c;
      std::array<double, 5> cw{};
      int count = 0;
      auto add = [&](int joint, double w, int station, int unknown) {
        if (!(w > 0)) return;
        c[static_cast<std::size_t>(count)] = Slot{joint, 0.0f, station, unknown, Vec3::Zero()};
        cw[static_cast<std::size_t>(count)] = w;
        ++count;
      };
      // A station's share: on its station joint, or split over the two ring joints around θ.
      const AngleCoord cell = locate_angle(std::max(M, 1), b.theta[i]);
      auto station_share = [&](int st, double share, bool split) {
        if (!ring || st == 0 || !split) {
          add(d.first_station + st, share, st, -1);
          return;
        }
        const int m0 = cell.j, m1 = (cell.j + 1) % M;
        const int k0 = (st - 1) * M + m0, k1 = (st - 1) * M + m1;
        add(d.first_ring + k0, share * (1 - cell.w), st, k0);
        add(d.first_ring + k1, share * cell.w, st, k1);
      };
      const bool five = ring && j > 0 && blend < 1;  // both stations split, and the body
      station_share(j, (1 - u) * blend, !five || u < 0.5);
      station_share(j + 1, u * blend, !five || u >= 0.5);
      add(0, 1 - blend, -1, -1);
      if (count == 0 || count > 4) {
        fail(ErrorCategory::internal,
             "skin: vertex " + std::to_string(v) + " has " + std::to_string(count) + " influences");
      }
      // Heaviest first; in float the heaviest takes what rounding left over, so they sum to 1.
      std::array<int, 5> order{0, 1, 2, 3, 4};
      std::stable_sort(order.begin(), order.begin() + count, [&](int a, int bb) {
        return cw[static_cast<std::size_t>(a)] > cw[static_cast<std::size_t>(bb)];
      });
      std::array<Slot, 4> slots{};
      float rest_sum = 0;
      for (int k = 0; k < count; ++k) {
        Slot sl = c[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
        sl.weight = static_cast<float>(cw[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]);
        if (k > 0) rest_sum += sl.weight;
        if (sl.station >= 0) {
          sl.local = d.rest_frames[static_cast<std::size_t>(sl.station)].to_local(rest_[v].cast<double>());
        }
        slots[static_cast<std::size_t>(k)] = sl;
      }
      slots[0].weight = std::max(0.0f, 1.0f - rest_sum);
      for (int k = 0; k < 4; ++k) {
        vertex_joints_[v][static_cast<std::size_t>(k)] =
            static_cast<std::uint16_t>(k < count ? slots[static_cast<std::size_t>(k)].joint : 0);
        vertex_weights_[v][static_cast<std::size_t>(k)] = k < count ? slots[static_cast<std::size_t>(k)].weight : 0.0f;
      }
      d.vertices.push_back(v);
      d.slots.push_back(slots);
    }
  }

  // The ring fit's pattern: every pair of ring joints some vertex weighs both of, and the diagonal.
  if (ring && layout_.fit) {
    for (auto& dp : data_) {
      SweepData& d = *dp;
      const int unknowns = (N - 1) * M;
      std::vector<Eigen::Triplet<double>> pattern;
      for (int k = 0; k < unknowns; ++k) pattern.emplace_back(k, k, 0.0);
      for (const auto& slots : d.slots)
        for (const Slot& a : slots)
          for (const Slot& bb : slots)
            if (a.weight > 0 && bb.weight > 0 && a.unknown >= 0 && bb.unknown >= 0)
              pattern.emplace_back(a.unknown, bb.unknown, 0.0);
      d.normal.resize(unknowns, unknowns);
      d.normal.setFromTriplets(pattern.begin(), pattern.end());
      d.normal.makeCompressed();
      auto index_of = [&](int row, int col) {
        const int* begin = d.normal.innerIndexPtr() + d.normal.outerIndexPtr()[col];
        const int* end = d.normal.innerIndexPtr() + d.normal.outerIndexPtr()[col + 1];
        return static_cast<int>(std::lower_bound(begin, end, row) - d.normal.innerIndexPtr());
      };
      d.value_index.resize(d.slots.size());
      for (std::size_t i = 0; i < d.slots.size(); ++i) {
        d.value_index[i].fill(-1);
        for (std::size_t a = 0; a < 4; ++a)
          for (std::size_t bb = 0; bb < 4; ++bb) {
            const Slot& sa = d.slots[i][a];
            const Slot& sb = d.slots[i][bb];
            if (sa.weight > 0 && sb.weight > 0 && sa.unknown >= 0 && sb.unknown >= 0)
              d.value_index[i][4 * a + bb] = index_of(sa.unknown, sb.unknown);
          }
      }
      d.solver.analyzePattern(d.normal);
      d.rhs.resize(unknowns);
      d.solved.resize(unknowns);
      d.pull.resize(unknowns);
      for (int k = 0; k < unknowns; ++k) {
        const double r = d.ring_rest_radius[static_cast<std::size_t>(k)];
        d.pull[k] = kRingFitPull * (layout_.motion == RingMotion::scale ? r * r : 1.0);
      }
    }
  }
  for (auto& dp : data_) dp->sampled.resize((N - 1) * std::max(M, 1));
  skinning_.resize(joints_.size());
  global_.resize(joints_.size());
}

void SkinFit::pose(std::span<const SweepShape* const> shapes, std::span<const Eigen::Vector3f> positions, int frame,
                   std::span<JointKey> keys) {
  const int N = layout_.stations, M = layout_.ring;
  const bool ring = M > 1;
  const bool scale = layout_.motion == RingMotion::scale;
  keys[0] = kIdentityKey;
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    SweepData& d = *data_[s];
    const SweepShape& shape = *shapes[s];
    d.frames.resize(static_cast<std::size_t>(N));
    for (int j = 0; j < N; ++j) {
      const std::size_t js = static_cast<std::size_t>(j);
      d.frames[js] = frame_at(shape, d.station_t[js]);
      InPlane in_plane;
      if (!ring) {
        d.radii.resize(static_cast<std::size_t>(shape.radial_count));
        radii_at_samples(shape, d.station_t[js], d.radii);
        in_plane = fit_in_plane(shape, d.rest_radii[js], d.radii);
      }
      keys[static_cast<std::size_t>(d.first_station + j)] = key_of(d.frames[js], in_plane);
    }
    if (!ring) continue;
    // The change sampled at each ring joint's angle.
    for (int j = 1; j < N; ++j) {
      for (int m = 0; m < M; ++m) {
        const int k = (j - 1) * M + m;
        const double r0 = d.ring_rest_radius[static_cast<std::size_t>(k)];
        const double r1 = radius_at(shape, kTwoPi * m / M, d.station_t[static_cast<std::size_t>(j)]);
        d.sampled[k] = scale ? r1 / r0 : r1 - r0;
      }
    }
    Eigen::VectorXd* value = &d.sampled;
    if (layout_.fit) {
      // Least squares over the vertices: the skinned vertex is q = q0 + Σ x_k·B_k, linear in the
      // ring joints' values x_k (the station frames fixed); minimise Σ |q − bake|² + pull·(x − x̂)².
      std::fill(d.normal.valuePtr(), d.normal.valuePtr() + d.normal.nonZeros(), 0.0);
      d.rhs.setZero();
      for (std::size_t i = 0; i < d.slots.size(); ++i) {
        const Eigen::Vector3f& rv = rest_[d.vertices[i]];
        Vec3 q0 = Vec3::Zero();
        std::array<Vec3, 4> B;
        for (std::size_t a = 0; a < 4; ++a) {
          const Slot& sl = d.slots[i][a];
          B[a].setZero();
          if (sl.weight == 0) continue;
          const double w = sl.weight;
          if (sl.station < 0) {
            q0 += w * rv.cast<double>();
            continue;
          }
          const Frame& f = d.frames[static_cast<std::size_t>(sl.station)];
          if (sl.unknown < 0) {
            q0 += w * f.to_world(sl.local);
          } else if (scale) {
            q0 += w * f.to_world(Vec3(0, 0, sl.local.z()));
            B[a] = w * (f.rotation * Vec3(sl.local.x(), sl.local.y(), 0));
          } else {
            const double angle = kTwoPi * (sl.unknown % M) / M;
            q0 += w * f.to_world(sl.local);
            B[a] = w * (f.rotation * Vec3(std::cos(angle), std::sin(angle), 0));
          }
        }
        const Vec3 r0 = q0 - positions[d.vertices[i]].cast<double>();
        for (std::size_t a = 0; a < 4; ++a) {
          const int ka = d.slots[i][a].unknown;
          if (ka < 0 || d.slots[i][a].weight == 0) continue;
          d.rhs[ka] -= B[a].dot(r0);
          for (std::size_t bb = 0; bb < 4; ++bb) {
            const int at = d.value_index[i][4 * a + bb];
            if (at >= 0) d.normal.valuePtr()[at] += B[a].dot(B[bb]);
          }
        }
      }
      for (int k = 0; k < d.normal.rows(); ++k) {
        d.normal.coeffRef(k, k) += d.pull[k];
        d.rhs[k] += d.pull[k] * d.sampled[k];
      }
      d.solver.factorize(d.normal);
      if (d.solver.info() == Eigen::Success) {
        d.solved = d.solver.solve(d.rhs);
        if (d.solved.allFinite()) value = &d.solved;
      }
    }
    for (int k = 0; k < (N - 1) * M; ++k) {
      JointKey key = kIdentityKey;
      const double x = (*value)[k];
      if (scale) {
        // Never flat or mirrored, as the sweep's own radii (kMinRadiusFraction).
        const float rho = static_cast<float>(std::max(x, kMinRadiusFraction));
        key.s[0] = key.s[1] = rho;
      } else {
        const double angle = kTwoPi * (k % M) / M;
        key.t[0] = static_cast<float>(x * std::cos(angle));
        key.t[1] = static_cast<float>(x * std::sin(angle));
      }
      keys[static_cast<std::size_t>(d.first_ring + k)] = key;
    }
  }

  // The skinned bound vertices, from the keys as written, against the bake.
  for (std::size_t k = 0; k < joints_.size(); ++k) {
    const Eigen::Matrix4d local = key_matrix(keys[k]);
    global_[k] = joints_[k].parent < 0 ? local : global_[static_cast<std::size_t>(joints_[k].parent)] * local;
    skinning_[k] = global_[k] * inverse_bind_[k].cast<double>();
  }
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    const SweepData& d = *data_[s];
    for (const std::uint32_t v : d.vertices) {
      const Eigen::Vector4d p(rest_[v].x(), rest_[v].y(), rest_[v].z(), 1.0);
      Eigen::Vector4d q = Eigen::Vector4d::Zero();
      for (std::size_t k = 0; k < 4; ++k) {
        const float w = vertex_weights_[v][k];
        if (w != 0) q += static_cast<double>(w) * (skinning_[vertex_joints_[v][k]] * p);
      }
      const double e = (q.head<3>() - positions[v].cast<double>()).norm() / d.length;
      sum_squares_ += e * e;
      if (e > error_.max_relative) {
        error_.max_relative = e;
        error_.max_frame = frame;
        error_.max_vertex = v;
      }
    }
    error_.samples += d.vertices.size();
  }
  error_.rms_relative = error_.samples ? std::sqrt(sum_squares_ / static_cast<double>(error_.samples)) : 0.0;
}

}  // namespace sweep::assets
