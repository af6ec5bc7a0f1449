#include "sweep/sim/body_path.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sweep::sim {
namespace {

// The rotation vector of q (angle ≤ π), the inverse of rotation_from_vector.
Vec3 log_of(Quat q) {
  if (q.w() < 0) q.coeffs() *= -1;
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-300) return 2.0 * v;  // (angle ≈ 2 s)
  return (2.0 * std::atan2(s, q.w()) / s) * v;
}

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

// The right Jacobian of SO(3): the body angular velocity of exp(ρ(t)) is J_r(ρ) ρ̇.
Mat3 right_jacobian(const Vec3& rho) {
  const double a = rho.norm();
  const Mat3 k = skew(rho);
  if (a < 1e-6) return Mat3::Identity() - 0.5 * k + (1.0 / 6.0) * k * k;
  return Mat3::Identity() - ((1 - std::cos(a)) / (a * a)) * k + ((a - std::sin(a)) / (a * a * a)) * k * k;
}

// Cubic Hermite on [0, 1] with end values p0, p1 and end tangents m0, m1 (per unit of s): value,
// first and second derivatives in s.
template <class V>
void hermite(double s, const V& p0, const V& p1, const V& m0, const V& m1, V& p, V& dp, V& ddp) {
  const double s2 = s * s, s3 = s2 * s;
  p = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
  dp = (6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * m1;
  ddp = (12 * s - 6) * p0 + (6 * s - 4) * m0 + (-12 * s + 6) * p1 + (6 * s - 2) * m1;
}

// Catmull-Rom tangents (per second) of values x at times t, zero at both ends.
std::vector<Vec3> tangents(const std::vector<double>& t, const std::vector<Vec3>& x) {
  std::vector<Vec3> m(x.size(), Vec3::Zero());
  for (std::size_t k = 1; k + 1 < x.size(); ++k) m[k] = (x[k + 1] - x[k - 1]) / (t[k + 1] - t[k - 1]);
  return m;
}

}  // namespace

BodyPath::BodyPath(std::vector<BodyKey> keys, BodyInterpolation interpolation, const Vec3& pivot)
    : keys_(std::move(keys)), interpolation_(interpolation), pivot_(pivot) {
  prepare();
}

void BodyPath::swap_keys(std::vector<BodyKey>& keys, BodyInterpolation interpolation, const Vec3& pivot) {
  keys_.swap(keys);
  interpolation_ = interpolation;
  pivot_ = pivot;
  moves_ = false;
  rho_.clear();
  rho_tangent_.clear();
  tangent_.clear();
  prepare();
}

void BodyPath::prepare() {
  for (BodyKey& k : keys_) k.rotation.normalize();
  for (std::size_t k = 1; k < keys_.size(); ++k) {
    if (keys_[k].translation != keys_[0].translation || keys_[k].rotation.angularDistance(keys_[0].rotation) > 0)
      moves_ = true;
  }
  if (interpolation_ != BodyInterpolation::cubic || keys_.empty()) return;
  std::vector<double> times;
  std::vector<Vec3> positions;
  for (const BodyKey& k : keys_) {
    times.push_back(k.time);
    positions.push_back(k.translation);
    Vec3 rho = log_of(keys_[0].rotation.conjugate() * k.rotation);
    // Unwrap: of the rotation vectors of this rotation (ρ + 2πn along its axis), the one nearest
    // the previous key's, so that a turn of more than half a revolution keeps turning.
    if (!rho_.empty() && rho.norm() > 0) {
      const Vec3 axis = rho.normalized();
      Vec3 best = rho;
      for (int n = -3; n <= 3; ++n) {
        const Vec3 candidate = rho + (2 * std::numbers::pi * n) * axis;
        if ((candidate - rho_.back()).norm() < (best - rho_.back()).norm()) best = candidate;
      }
      rho = best;
    }
    rho_.push_back(rho);
  }
  tangent_ = tangents(times, positions);
  rho_tangent_ = tangents(times, rho_);
}

std::size_t BodyPath::piece(double t) const {
  const auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double x, const BodyKey& k) { return x < k.time; });
  return static_cast<std::size_t>(it - keys_.begin()) - 1;
}

BodyState BodyPath::at(double t) const {
  BodyState s = about_pivot(t);
  if (pivot_ == Vec3::Zero()) return s;
  // The origin of the mesh is at p − R c: it moves with the pivot and swings about it,
  //   v_O = ṗ − ω_w × (R c),   a_O = p̈ − α_w × (R c) − ω_w × (ω_w × (R c))   (world axes),
  // and the accelerations are kept in body axes, where R c becomes c.
  const Vec3 arm = s.rotation * pivot_;
  const Vec3 w = s.rotation * s.angular_velocity;
  s.translation -= arm;
  s.velocity -= w.cross(arm);
  s.acceleration -= s.angular_acceleration.cross(pivot_) + s.angular_velocity.cross(s.angular_velocity.cross(pivot_));
  return s;
}

// The path of the pivot (the origin when there is none): translation p, velocity ṗ, acceleration
// p̈ in body axes, and the rotation with its angular velocity and acceleration.
BodyState BodyPath::about_pivot(double t) const {
  BodyState s;
  if (keys_.empty()) return s;
  if (t <= keys_.front().time || t >= keys_.back().time || keys_.size() == 1) {
    const BodyKey& k = t <= keys_.front().time ? keys_.front() : keys_.back();
    s.rotation = k.rotation;
    s.translation = k.translation;
    return s;
  }
  const std::size_t p = piece(t);
  const BodyKey& a = keys_[p];
  const BodyKey& b = keys_[p + 1];
  const double span = b.time - a.time;
  const double u = (t - a.time) / span;
  if (interpolation_ == BodyInterpolation::linear) {
    s.translation = a.translation + u * (b.translation - a.translation);
    s.velocity = (b.translation - a.translation) / span;
    const Vec3 turn = log_of(a.rotation.conjugate() * b.rotation);  // body axes, over the piece
    s.rotation = (a.rotation * rotation_from_vector(u * turn)).normalized();
    s.angular_velocity = turn / span;
    return s;
  }
  Vec3 dp, ddp;
  hermite(u, a.translation, b.translation, Vec3(span * tangent_[p]), Vec3(span * tangent_[p + 1]), s.translation, dp,
          ddp);
  s.velocity = dp / span;
  Vec3 rho, drho, ddrho;
  hermite(u, rho_[p], rho_[p + 1], Vec3(span * rho_tangent_[p]), Vec3(span * rho_tangent_[p + 1]), rho, drho, ddrho);
  drho /= span;
  ddrho /= span * span;
  s.rotation = (keys_[0].rotation * rotation_from_vector(rho)).normalized();
  s.acceleration = s.rotation.conjugate() * (ddp / (span * span));
  const Mat3 jr = right_jacobian(rho);
  s.angular_velocity = jr * drho;
  // α = J_r ρ̈ + (d/dt J_r) ρ̇, the second term by a central difference of J_r along the path.
  const double h = 1e-6 * std::max(1.0, rho.norm());
  const Mat3 djr = (right_jacobian(rho + h * drho) - right_jacobian(rho - h * drho)) / (2 * h);
  s.angular_acceleration = jr * ddrho + djr * drho;
  return s;
}

void BodyPath::kink_keys(std::vector<std::size_t>& out) const {
  out.clear();
  if (interpolation_ != BodyInterpolation::linear || !moves_) return;
  // A key at time 0 or before: the scene starts with the body already in motion, its parts at rest
  // in it (no kick).
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    if (keys_[k].time > 0) out.push_back(k);
  }
}

void BodyPath::jump_at(std::size_t key, Vec3& dv, Vec3& dw) const {
  // Velocity (world) and angular velocity (body axes) of the piece before and after the key.
  Vec3 v[2] = {Vec3::Zero(), Vec3::Zero()}, w[2] = {Vec3::Zero(), Vec3::Zero()};
  for (int side = 0; side < 2; ++side) {
    const std::size_t first = side == 0 ? key - 1 : key;
    if ((side == 0 && key == 0) || first + 1 >= keys_.size()) continue;
    const BodyKey& a = keys_[first];
    const BodyKey& b = keys_[first + 1];
    const double span = b.time - a.time;
    v[side] = (b.translation - a.translation) / span;
    w[side] = log_of(a.rotation.conjugate() * b.rotation) / span;
    // The angular velocity of the piece before, in the axes at its end (the key's): the same
    // vector (a rotation about its own axis leaves it unchanged).
  }
  const Quat& at = keys_[key].rotation;
  dw = w[1] - w[0];
  // The origin's jump: the pivot's, less the jump of the swing about it (ω × c, body axes).
  dv = at.conjugate() * (v[1] - v[0]) - dw.cross(pivot_);
}

bool BodyPath::loads_between(double from, double to) const {
  if (!moves_ || keys_.empty()) return false;
  if (to < keys_.front().time || from > keys_.back().time) return false;
  if (interpolation_ == BodyInterpolation::cubic) return true;
  // Linear: a kink inside, or a piece that turns.
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    if (keys_[k].time >= from && keys_[k].time <= to) return true;
    if (k + 1 < keys_.size() && keys_[k].time < to && keys_[k + 1].time > from &&
        keys_[k].rotation.angularDistance(keys_[k + 1].rotation) > 0)
      return true;
  }
  return false;
}

}  // namespace sweep::sim
