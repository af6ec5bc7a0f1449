#include "sweep/core/chain_dynamics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

namespace sweep {
namespace {

// A step's Newton iteration stops once it moves no joint by more than this (radians over the step).
constexpr double kNewtonTolerance = 1e-10;
constexpr int kMaxNewtonIterations = 24;
// A Newton change larger than this (radians over a step) is a diverging iteration.
constexpr double kLargestTurn = 1.0;
// An iteration that shrinks the change by less than this factor: the step is halved.
constexpr double kDivergence = 0.9;
// How many times a step that does not settle is halved, at most: the schema's longest step (1 s)
// down to 15 µs. (8, a 1 s step's 4 ms, left a limp rope's whipping steps unsettled.)
constexpr int kMaxHalvings = 16;
// C's lowest modes kept in the structured Newton matrix (the rest left out, see build_structured).
constexpr int kStructuredModes = 8;
// A structured iteration that shrinks the change by less than this factor: the step goes on with
// the dense S.
constexpr double kSlowContraction = 0.5;
// Below this many joint coordinates the dense S is the cheaper (its Cholesky small, the r modes a
// large share of C): sweep-bench-chain, S̃ against S, 0.66× as fast at K = 8 (21), 1.05× at
// K = 16 (45), 1.37× at K = 32 (93).
constexpr int kStructuredFrom = 48;

// J_l⁻ᵀ(φ) = I + ½[φ]× + β [φ]×², the transpose of the left Jacobian's inverse of exp (the map from a
// small turn applied on the left to the change of φ), β = (1 − (θ/2) cot(θ/2)) / θ².
Mat3 inverse_jacobian_transpose(const Vec3& phi) {
  const double theta2 = phi.squaredNorm();
  double beta;
  if (theta2 < 1e-8) {
    beta = 1.0 / 12 + theta2 / 720;
  } else {
    const double theta = std::sqrt(theta2);
    beta = (1 - 0.5 * theta / std::tan(0.5 * theta)) / theta2;
  }
  const Mat3 s = skew(phi);
  return Mat3::Identity() + 0.5 * s + beta * s * s;
}

// exp(turn) exp(φ) as a rotation vector.
Vec3 turned(const Vec3& turn, const Vec3& phi) {
  return vector_from_rotation(rotation_from_vector(turn) * rotation_from_vector(phi));
}

}  // namespace

Vec3 vector_from_rotation(const Quat& q) {
  const double w = q.w() < 0 ? -q.w() : q.w();
  const Vec3 v = q.w() < 0 ? Vec3(-q.vec()) : Vec3(q.vec());
  const double s = v.norm();
  if (s < 1e-8) return (2.0 / w) * v;  // angle/s = 2 atan2(s, w)/s → 2/w (error ~ s²)
  return (2 * std::atan2(s, w) / s) * v;
}

ChainDynamics::ChainDynamics(std::shared_ptr<const ChainModel> model, const SweepShape& rest)
    : model_(std::move(model)), joints_(model_->joints) {
  const int k = rest.section_count();
  assert(k == joints_ + 1);
  const double s = model_->metres_per_unit;
  const int dim = 3 * joints_;
  relative_rotation_.assign(k, Quat::Identity());
  relative_offset_.assign(k, Vec3::Zero());
  for (int i = 1; i < k; ++i) {
    const Frame rel = rest.frames[i - 1].inverse() * rest.frames[i];
    relative_rotation_[i] = rel.rotation;
    relative_offset_[i] = s * rel.center;
  }
  root_centre_ = s * rest.frames[0].center;
  root_rotation_ = rest.frames[0].rotation;
  stiffness_.assign(k, Vec3::Zero());
  for (int i = 1; i < k; ++i) stiffness_[i] = model_->stiffness.block<3, 3>(3 * (i - 1), 3 * (i - 1)).diagonal();

  // C = M₀ Φ diag(2ζω) Φᵀ M₀: in the modes (Φᵀ M₀ Φ = I) each is damped by its own ratio.
  Eigen::VectorXd rate(dim);
  for (int c = 0; c < dim; ++c) rate[c] = 2 * model_->damping_ratio[c] * std::sqrt(std::max(model_->omega2[c], 0.0));
  const Eigen::MatrixXd mphi = model_->mass * model_->modes;
  damping_ = mphi * rate.asDiagonal() * mphi.transpose();
  damping_ = 0.5 * (damping_ + damping_.transpose()).eval();
  damping_factor_ = mphi * rate.cwiseSqrt().asDiagonal();
  joint_term_.assign(k, Mat3::Zero());
  set_structured_size(std::min(kStructuredModes, dim));

  phi_ = w_ = rest_load_ = last_change_ = previous_change_ = Eigen::VectorXd::Zero(dim);
  phi_saved_.assign(kMaxHalvings + 1, phi_);
  w_saved_.assign(kMaxHalvings + 1, w_);
  for (Eigen::VectorXd* v : {&phi_mid_, &w_mid_, &w_end_, &wdot_, &residual_, &scratch_})
    *v = Eigen::VectorXd::Zero(dim);
  mass_ = newton_ = Eigen::MatrixXd::Zero(dim, dim);
  // Sized by a first factorisation (later ones reuse its storage): Eigen's LLT(size) leaves its
  // status unset, and moving such an object reads it (undefined behaviour, caught by UBSan).
  llt_.compute(Eigen::MatrixXd::Identity(dim, dim));
  centre_.assign(k, Vec3::Zero());
  rotation_.assign(k, Quat::Identity());
  pre_.assign(k, Mat3::Identity());
  inertia_.assign(k, Mat3::Zero());
  for (std::vector<Vec3>* v : {&omega_, &alpha_, &accel_, &force_, &moment_, &composite_first_})
    v->assign(k + 1, Vec3::Zero());
  composite_inertia_.assign(k + 1, Mat3::Zero());
  for (std::vector<Mat3>* m : {&crba_x_, &crba_y_, &crba_w_}) m->assign(k + 1, Mat3::Zero());
  u_.assign(k, Mat63::Zero());
  d_inverse_.assign(k, Mat3::Zero());
  y_.assign(k, Vec3::Zero());
  factored_axes_.assign(k, Mat3::Identity());
  factored_lever_.assign(k + 1, Vec3::Zero());
  set_pose(phi_);
}

void ChainDynamics::set_joint(int i, const Vec3& phi, const Vec3& w) {
  assert(i >= 1 && i <= joints_);
  phi_.segment<3>(3 * (i - 1)) = phi;
  w_.segment<3>(3 * (i - 1)) = w;
  set_pose(phi_);
}

void ChainDynamics::set_rest_load(std::span<const double> load) {
  const Eigen::Index dim = 3 * joints_;
  if (load.empty()) {
    rest_load_.setZero();
    return;
  }
  assert(static_cast<Eigen::Index>(load.size()) == dim);
  rest_load_ = Eigen::Map<const Eigen::VectorXd>(load.data(), dim);
}

void ChainDynamics::set_state(std::span<const double> phi, std::span<const double> w) {
  const Eigen::Index dim = 3 * joints_;
  assert(static_cast<Eigen::Index>(phi.size()) == dim && static_cast<Eigen::Index>(w.size()) == dim);
  phi_ = Eigen::Map<const Eigen::VectorXd>(phi.data(), dim);
  w_ = Eigen::Map<const Eigen::VectorXd>(w.data(), dim);
  set_pose(phi_);
}

void ChainDynamics::get_state(std::span<double> phi, std::span<double> w) const {
  const Eigen::Index dim = 3 * joints_;
  Eigen::Map<Eigen::VectorXd>(phi.data(), dim) = phi_;
  Eigen::Map<Eigen::VectorXd>(w.data(), dim) = w_;
}

void ChainDynamics::set_pose(const Eigen::VectorXd& phi) {
  const std::size_t bytes = static_cast<std::size_t>(phi.size()) * sizeof(double);
  if (posed_ && std::memcmp(phi.data(), posed_phi_.data(), bytes) == 0) return;
  posed_phi_ = phi;  // sized once, by the constructor's first pose
  posed_ = true;
  centre_[0] = root_centre_;
  rotation_[0] = root_rotation_;
  for (int i = 1; i <= joints_; ++i) {
    const Quat a = (rotation_[i - 1] * relative_rotation_[i]).normalized();
    pre_[i] = a.toRotationMatrix();
    centre_[i] = centre_[i - 1] + rotation_[i - 1] * relative_offset_[i];
    rotation_[i] = (a * rotation_from_vector(phi.segment<3>(3 * (i - 1)))).normalized();
    const Mat3 r = rotation_[i].toRotationMatrix();
    inertia_[i] = r * model_->node_inertia[i].asDiagonal() * r.transpose();
  }
}

// Recursive Newton–Euler: out to the tip for each section's angular velocity Ω, angular
// acceleration α and centre's acceleration a (gravity as the root accelerating up), back to the
// root for the force f and moment n (about the joint's centre) that everything beyond each joint
// needs; the joint's share is n in its own axes.
void ChainDynamics::inverse_dynamics(const Eigen::VectorXd& w, const Eigen::VectorXd& wdot, const Body& body,
                                     Eigen::VectorXd& out) {
  const Vec3& c0 = centre_[0];
  omega_[0] = body.angular_velocity;
  alpha_[0] = body.angular_acceleration;
  accel_[0] = body.acceleration + body.angular_acceleration.cross(c0) +
              body.angular_velocity.cross(body.angular_velocity.cross(c0)) - body.gravity;
  for (int i = 1; i <= joints_; ++i) {
    const Vec3 u = pre_[i] * w.segment<3>(3 * (i - 1));
    const Vec3 d = centre_[i] - centre_[i - 1];
    const Vec3& o = omega_[i - 1];
    accel_[i] = accel_[i - 1] + alpha_[i - 1].cross(d) + o.cross(o.cross(d));
    alpha_[i] = alpha_[i - 1] + o.cross(u) + pre_[i] * wdot.segment<3>(3 * (i - 1));
    omega_[i] = o + u;
  }
  Vec3 f = Vec3::Zero(), n = Vec3::Zero();
  for (int i = joints_; i >= 1; --i) {
    if (i < joints_) n += (centre_[i + 1] - centre_[i]).cross(f);
    n += inertia_[i] * alpha_[i] + omega_[i].cross(inertia_[i] * omega_[i]);
    f += model_->node_mass[i] * accel_[i];
    out.segment<3>(3 * (i - 1)).noalias() = pre_[i].transpose() * n;
  }
}

// Composite rigid bodies: block (j, k ≥ j) is the moment about c_j that everything beyond joint k
// needs when joint k alone accelerates, Ic_k − [c_k − c_j]× [h_k]×, with Ic_k the rotary inertia of
// the sections beyond k about c_k and h_k their first moment of mass about it.
void ChainDynamics::build_mass_matrix() {
  double mc = 0;
  Vec3 h = Vec3::Zero();
  Mat3 ic = Mat3::Zero();
  for (int k = joints_; k >= 1; --k) {
    if (k < joints_) {
      const Vec3 d = centre_[k + 1] - centre_[k];
      ic += (2 * h.dot(d)) * Mat3::Identity() - h * d.transpose() - d * h.transpose() +
            mc * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
      h += mc * d;
    }
    ic += inertia_[k];
    mc += model_->node_mass[k];
    composite_first_[k] = h;
    composite_inertia_[k] = ic;
  }
  // Split as P_jᵀ X_k + W_jᵀ Y_k with X_k = (Ic_k − [c_k]× [h_k]×) P_k, Y_k = [h_k]× P_k and
  // W_j = −[c_j]× P_j (so W_jᵀ = P_jᵀ [c_j]×): two 3×3 products a block, the rest once a joint.
  // (Centres from the root's: only their differences count, and the products stay the chain's size.)
  for (int k = 1; k <= joints_; ++k) {
    const Mat3 ck = skew(centre_[k] - centre_[0]);
    crba_y_[k].noalias() = skew(composite_first_[k]) * pre_[k];
    crba_x_[k].noalias() = composite_inertia_[k] * pre_[k];
    crba_x_[k].noalias() -= ck * crba_y_[k];
    crba_w_[k].noalias() = -ck * pre_[k];
  }
  for (int j = 1; j <= joints_; ++j) {
    for (int k = j; k <= joints_; ++k) {
      auto lower = mass_.block<3, 3>(3 * (k - 1), 3 * (j - 1));  // block (k, j) = block (j, k)ᵀ
      lower.noalias() = crba_x_[k].transpose() * pre_[j];
      lower.noalias() += crba_y_[k].transpose() * crba_w_[j];
      if (k != j) mass_.block<3, 3>(3 * (j - 1), 3 * (k - 1)) = lower.transpose();
    }
  }
}

void ChainDynamics::static_residual(const Eigen::VectorXd& phi, const Body& body, Eigen::VectorXd& out) {
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(3 * joints_);
  set_pose(phi);
  inverse_dynamics(still, still, body, out);
  elastic_torque(phi, scratch_);
  out += scratch_;
  set_pose(phi_);
}

const Eigen::MatrixXd& ChainDynamics::mass_matrix() {
  build_mass_matrix();
  return mass_;
}

// The articulated-body recursion (Featherstone's ABA at zero speed) for M(q) x = r. Spatial quantities are taken about
// each joint's centre c_i in body axes: an inertia [[A, B], [Bᵀ, m·1]] maps (angular, linear acceleration of c_i) to
// (moment about c_i, force). Out of the tip: IA_i = section i's own inertia plus what lies beyond, articulated; joint i
// turns about c_i (motion subspace S_i = [P_i; 0], P_i = R_{A_i}), so U_i = IA_i S_i, D_i = S_iᵀ IA_i S_i, and the
// parent sees IA_i − U_i D_i⁻¹ U_iᵀ moved to c_{i−1}.
void ChainDynamics::factor_recursive(bool with_joint_terms) {
  Mat3 a = Mat3::Zero(), b = Mat3::Zero(), m = Mat3::Zero();  // the articulated inertia beyond, about c_i
  for (int i = joints_; i >= 1; --i) {
    if (i < joints_) {
      // Moved from c_{i+1} to c_i (r = c_{i+1} − c_i): A += R Bᵀ − B R − R m R, B += R m.
      const Mat3 r = skew(centre_[i + 1] - centre_[i]);
      const Mat3 rm = r * m;
      a += r * b.transpose() - b * r - rm * r;
      b += rm;
    }
    a += inertia_[i];
    m.diagonal().array() += model_->node_mass[i];
    const Mat3& p = pre_[i];
    factored_axes_[i] = p;
    if (i < joints_) factored_lever_[i] = centre_[i + 1] - centre_[i];
    Mat63& u = u_[i];
    u.topRows<3>().noalias() = a * p;
    u.bottomRows<3>().noalias() = b.transpose() * p;
    Mat3 d = p.transpose() * u.topRows<3>();
    if (with_joint_terms) d += joint_term_[i];  // a term of the joint's own acts as an armature does
    d_inverse_[i] = d.llt().solve(Mat3::Identity());
    // IA − U D⁻¹ Uᵀ.
    const Mat63 ud = u * d_inverse_[i];
    a.noalias() -= ud.topRows<3>() * u.topRows<3>().transpose();
    b.noalias() -= ud.topRows<3>() * u.bottomRows<3>().transpose();
    m.noalias() -= ud.bottomRows<3>() * u.bottomRows<3>().transpose();
  }
}

// Out of the tip, the bias forces (what the joints beyond pass on); back out from the root, the
// accelerations: x_i = D_i⁻¹ (r_i − P_iᵀ n_i − U_iᵀ a'_i).
void ChainDynamics::solve_recursive(Eigen::Ref<Eigen::VectorXd> x) {
  Vec3 n = Vec3::Zero(), f = Vec3::Zero();  // the bias force beyond, about c_i
  for (int i = joints_; i >= 1; --i) {
    if (i < joints_) n += factored_lever_[i].cross(f);
    y_[i] = d_inverse_[i] * (x.segment<3>(3 * (i - 1)) - factored_axes_[i].transpose() * n);
    n.noalias() += u_[i].topRows<3>() * y_[i];
    f.noalias() += u_[i].bottomRows<3>() * y_[i];
  }
  Vec3 alpha = Vec3::Zero(), acc = Vec3::Zero();  // of c_i
  for (int i = 1; i <= joints_; ++i) {
    if (i > 1) acc += alpha.cross(factored_lever_[i - 1]);
    const Vec3 xi =
        y_[i] - d_inverse_[i] * (u_[i].topRows<3>().transpose() * alpha + u_[i].bottomRows<3>().transpose() * acc);
    x.segment<3>(3 * (i - 1)) = xi;
    alpha.noalias() += factored_axes_[i] * xi;
  }
}

void ChainDynamics::solve_mass(Eigen::VectorXd& x) {
  factor_recursive();
  solve_recursive(x);
}

void ChainDynamics::solve_mass_columns(Eigen::MatrixXd& x) {
  assert(x.rows() == 3 * joints_);
  factor_recursive();
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    scratch_ = x.col(c);
    solve_recursive(scratch_);
    x.col(c) = scratch_;
  }
}

void ChainDynamics::elastic_torque(const Eigen::VectorXd& phi, Eigen::VectorXd& out) const {
  for (int i = 1; i <= joints_; ++i) {
    const Vec3 p = phi.segment<3>(3 * (i - 1));
    out.segment<3>(3 * (i - 1)).noalias() =
        inverse_jacobian_transpose(p) * (stiffness_[i].cwiseProduct(p) + rest_load_.segment<3>(3 * (i - 1)));
  }
}

int ChainDynamics::step(double h, const Body& body, std::span<const double> torque) {
  assert(h > 0);
  assert(torque.empty() || static_cast<int>(torque.size()) == 3 * joints_);
  return advance(h, body, torque, 0);
}

// A step the Newton iteration does not settle (a part whipping through a large turn within one
// step) is taken again as two half steps, down to 2^-kMaxHalvings of it: the step stays stable and
// the cost grows only where the motion needs it. The choice depends on the state alone, so the
// motion stays independent of the output rate.
int ChainDynamics::advance(double h, const Body& body, std::span<const double> torque, int depth) {
  phi_saved_[depth] = phi_;
  w_saved_[depth] = w_;
  int iterations = 0;
  if (attempt(h, body, torque, iterations)) return iterations;
  if (depth == kMaxHalvings) {
    ++unsettled_;
    return iterations;
  }
  phi_ = phi_saved_[depth];
  w_ = w_saved_[depth];
  set_pose(phi_);
  iterations += advance(0.5 * h, body, torque, depth + 1);
  return iterations + advance(0.5 * h, body, torque, depth + 1);
}

void ChainDynamics::set_structured_size(int modes) {
  if (modes == low_rank_modes_ && low_rank_.cols() == modes) return;
  const int dim = 3 * joints_;
  low_rank_modes_ = modes;
  low_rank_.setZero(dim, modes);
  low_rank_solved_.setZero(dim, modes);
  capacitance_ = Eigen::MatrixXd::Identity(modes, modes);
  capacitance_llt_.compute(capacitance_);  // sized here (see the constructor's llt_)
  low_rank_scratch_.setZero(modes);
}

// S̃ = A + V Vᵀ: A = M(q_m) + (h²/4) J⁻ᵀ K J⁻¹ by the articulated-body recursion (the springs'
// term is the joint's own, as an armature), V the `modes` lowest modes' share of (h/2) C; solved by
// Woodbury's identity, S̃⁻¹ = A⁻¹ − A⁻¹ V (I + Vᵀ A⁻¹ V)⁻¹ Vᵀ A⁻¹. The rest of C is left out, and
// Newton's iteration (its residual exact) contracts by about the share of S it leaves out. At rest
// that is at most ζ, mode by mode (h/2)·2ζω against 1 + (hω/2)², the most for ω near 2/h; but a
// moved part's M(q) shrinks in directions where the rest pose's M₀ was large, and the low modes,
// whose damping (h/2)·2ζω (M₀φ)(M₀φ)ᵀ grows with M₀² and which have no spring term to bound it,
// then dominate S there. On the soft tube of tools/bench/bench_chain.cpp (K = 32, ζ = 0.05, the
// damping's share as the largest generalized eigenvalue of (h/2)(C − C_r) against S̃, sampled over
// its 2 s): with no mode kept up to 3.4 at 1/480 s and 9.1 at 1/120 s, with the 64 weightiest by
// the rest pose's measure still 3.4 and 9.1, with the 8 lowest 0.054 and 0.118, 16 lowest 0.046
// and 0.081.
void ChainDynamics::build_structured(double h, int modes) {
  const int dim = 3 * joints_;
  set_structured_size(std::clamp(modes, 0, dim));
  for (int i = 1; i <= joints_; ++i) {
    const Mat3 jt = inverse_jacobian_transpose(phi_mid_.segment<3>(3 * (i - 1)));
    joint_term_[i].noalias() = (0.25 * h * h) * (jt * stiffness_[i].asDiagonal() * jt.transpose());
  }
  factor_recursive(true);
  const int r = low_rank_modes_;
  if (r > 0) {
    low_rank_.noalias() = std::sqrt(0.5 * h) * damping_factor_.leftCols(r);
    low_rank_solved_ = low_rank_;
    for (int c = 0; c < r; ++c) solve_recursive(low_rank_solved_.col(c));
    capacitance_.setIdentity();
    capacitance_.noalias() += low_rank_.transpose() * low_rank_solved_;
    capacitance_llt_.compute(capacitance_);
  }
  ++factorizations_;
}

void ChainDynamics::solve_structured(Eigen::VectorXd& x) {
  solve_recursive(x);
  if (low_rank_modes_ == 0) return;
  low_rank_scratch_.noalias() = low_rank_.transpose() * x;
  capacitance_llt_.solveInPlace(low_rank_scratch_);
  x.noalias() -= low_rank_solved_ * low_rank_scratch_;
}

void ChainDynamics::factor_structured(double h, int modes) {
  phi_mid_ = phi_;
  set_pose(phi_);
  build_structured(h, modes);
}

const Eigen::MatrixXd& ChainDynamics::newton_matrix(double h) {
  phi_mid_ = phi_;
  set_pose(phi_);
  build_newton_matrix(h);
  return newton_;
}

void ChainDynamics::build_newton_matrix(double h) {
  build_mass_matrix();
  newton_ = mass_;
  newton_.noalias() += (0.5 * h) * damping_;
  for (int i = 1; i <= joints_; ++i) {
    const Mat3 jt = inverse_jacobian_transpose(phi_mid_.segment<3>(3 * (i - 1)));
    newton_.block<3, 3>(3 * (i - 1), 3 * (i - 1)).noalias() +=
        (0.25 * h * h) * (jt * stiffness_[i].asDiagonal() * jt.transpose());
  }
}

void ChainDynamics::factor_newton_matrix(double h) {
  build_newton_matrix(h);
  llt_.compute(newton_);
  ++factorizations_;
  ++dense_factorizations_;
}

bool ChainDynamics::attempt(double h, const Body& body, std::span<const double> torque, int& iterations) {
  // The first guess: the last two steps' changes of the speeds extrapolated (an O(h³) guess for a
  // smooth motion, where w₁ = w₀ is O(h)); after one step of this length, its change again.
  w_end_ = w_;
  const bool guessed = last_change_step_ == h;
  if (guessed) {
    if (previous_change_step_ == h) {
      w_end_ += 2 * last_change_ - previous_change_;
    } else {
      w_end_ += last_change_;
    }
  }
  bool converged = false;
  // The Newton matrix S is built at the first guess's mid-step pose of every step: one kept from
  // the steps before steers the iteration worse the farther the part has moved since (a light
  // section turning fast changes M within a step, and S⁻¹ magnifies that in the stiff, light
  // directions), and the iterations that costs outweigh the factorization (a soft tube at K = 32,
  // 1/480 s: a kept S took 6.5 iterations a step and was refreshed once a step anyway; a fresh one
  // takes 3.1). The structured S̃ first (build_structured), the dense S where S̃ contracts by less
  // than kSlowContraction. S is exact but for the velocity terms' derivatives (gyroscopic,
  // Coriolis), which only slow the iteration: a step fails only when it no longer contracts at
  // all, and is halved.
  double last = std::numeric_limits<double>::infinity();
  bool factored = false, retried = !guessed,
       structured = newton_kind_ == NewtonMatrix::structured && 3 * joints_ >= kStructuredFrom;
  while (iterations < kMaxNewtonIterations) {
    ++iterations;
    ++iterations_;
    w_mid_ = 0.5 * (w_ + w_end_);
    for (int i = 1; i <= joints_; ++i) {
      phi_mid_.segment<3>(3 * (i - 1)) = turned(0.5 * h * w_mid_.segment<3>(3 * (i - 1)), phi_.segment<3>(3 * (i - 1)));
    }
    set_pose(phi_mid_);
    if (!factored) {
      if (structured) {
        build_structured(h, kStructuredModes);
      } else {
        factor_newton_matrix(h);
      }
      factored = true;
    }
    wdot_ = (w_end_ - w_) / h;
    inverse_dynamics(w_mid_, wdot_, body, residual_);
    elastic_torque(phi_mid_, scratch_);
    residual_ += scratch_;
    residual_.noalias() += damping_ * w_mid_;
    if (!torque.empty()) residual_ -= Eigen::Map<const Eigen::VectorXd>(torque.data(), 3 * joints_);
    if (structured) {
      solve_structured(residual_);
    } else {
      llt_.solveInPlace(residual_);
    }
    const double change = h * h * residual_.lpNorm<Eigen::Infinity>();  // the largest turn it changed
    if (structured && !(change <= kLargestTurn && change <= kSlowContraction * last)) {
      // The structured S steers too slowly here (the part far from the rest pose whose damping
      // it leaves out): on with the dense S at this iterate's pose, or from w₁ = w₀ if this
      // change would overflow.
      structured = false;
      factored = false;
      if (change <= kLargestTurn) {
        w_end_ -= h * residual_;
      } else {
        w_end_ = w_;
      }
      last = std::numeric_limits<double>::infinity();
      continue;
    }
    w_end_ -= h * residual_;
    if (!(change <= kLargestTurn) || change > kDivergence * last) {
      // Diverging (before the change grows out of range: the next iteration's turns would
      // overflow). From an extrapolated guess (the motion changed, an impulse or a new load): once
      // more from w₁ = w₀, with S built at its pose; else the step is halved.
      if (retried) {
        if (change <= kLargestTurn) break;
        set_pose(phi_);
        return false;
      }
      retried = true;
      factored = false;
      w_end_ = w_;
      last = std::numeric_limits<double>::infinity();
      continue;
    }
    if (change <= kNewtonTolerance) {
      converged = true;
      break;
    }
    last = change;
  }
  w_mid_ = 0.5 * (w_ + w_end_);
  for (int i = 1; i <= joints_; ++i) {
    phi_.segment<3>(3 * (i - 1)) = turned(h * w_mid_.segment<3>(3 * (i - 1)), phi_.segment<3>(3 * (i - 1)));
  }
  if (converged) {
    previous_change_.swap(last_change_);
    previous_change_step_ = last_change_step_;
    last_change_ = w_end_ - w_;
    last_change_step_ = h;
  } else {
    last_change_step_ = previous_change_step_ = 0;
  }
  w_ = w_end_;
  set_pose(phi_);
  return converged;
}

void ChainDynamics::apply_impulse(int section, const Vec3& point, const Vec3& impulse) {
  assert(section >= 1 && section <= joints_);
  residual_.setZero();
  for (int j = 1; j <= section; ++j) {
    residual_.segment<3>(3 * (j - 1)) = pre_[j].transpose() * (point - centre_[j]).cross(impulse);
  }
  solve_mass(residual_);  // (the Newton matrix's factorization is kept)
  w_ += residual_;
}

void ChainDynamics::apply_joint_impulse(std::span<const double> impulse) {
  assert(static_cast<int>(impulse.size()) == 3 * joints_);
  residual_ = Eigen::Map<const Eigen::VectorXd>(impulse.data(), 3 * joints_);
  solve_mass(residual_);  // (the Newton matrix's factorization is kept)
  w_ += residual_;
}

double ChainDynamics::kinetic_energy() const {
  Vec3 omega = Vec3::Zero(), v = Vec3::Zero();
  double e = 0;
  for (int i = 1; i <= joints_; ++i) {
    v += omega.cross(centre_[i] - centre_[i - 1]);
    omega += pre_[i] * w_.segment<3>(3 * (i - 1));
    e += 0.5 * (model_->node_mass[i] * v.squaredNorm() + omega.dot(inertia_[i] * omega));
  }
  return e;
}

double ChainDynamics::elastic_energy() const {
  double e = 0;
  for (int i = 1; i <= joints_; ++i) {
    const Vec3 p = phi_.segment<3>(3 * (i - 1));
    e += p.dot(0.5 * stiffness_[i].cwiseProduct(p) + rest_load_.segment<3>(3 * (i - 1)));
  }
  return e;
}

double ChainDynamics::gravity_potential(const Vec3& gravity) const {
  double e = 0;
  for (int i = 1; i <= joints_; ++i) e -= model_->node_mass[i] * gravity.dot(centre_[i]);
  return e;
}

}  // namespace sweep
