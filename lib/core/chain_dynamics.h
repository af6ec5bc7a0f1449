#pragma once
// Geometrically exact motion of a material-mode chain (the ChainModel's sections, springs and
// damping): the inertia, the velocity terms and gravity of the current pose, however far the part
// turns. ChainModel's modal step freezes the mass matrix at the rest pose; that is right for small
// motion only, and a soft part that turns far there gains energy it was never given.
//
// Coordinates. Joint i (sections 1 .. K−1) keeps its rotation vector φ_i in the axes of A_i, the
// frame its section hangs from (ElasticSweep's kinematics: R_i = R_{A_i} exp(φ_i), turning about
// the section's own centre), and as its speed the relative angular velocity w_i in the same axes
// (d/dt exp(φ) = [w]× exp(φ)): the speed a torque does work on, so a joint torque in A_i's axes is
// w_i's generalized force as it stands. The elastic energy ½ φᵀ K φ then gives the joint the
// torque −J⁻ᵀ(φ) K φ (J the left Jacobian of exp), which for a bend in one plane is −K φ: the
// statics of the planar elastica are those of the modal model.
//
// Dynamics. M(q) ẇ + c(q, w) + J⁻ᵀ K φ + C w = τ_gravity(q) + τ, with M and c by recursive
// Newton–Euler (inverse dynamics: one pass out for the sections' accelerations, one back for the
// moments they need; gravity as an acceleration of the root), and M itself by the composite-rigid-
// body algorithm for the Newton matrix. C is the model's modal damping at rest, M₀ Φ diag(2ζω) Φᵀ M₀,
// acting on the relative speeds w (so a part turning rigidly with its root is not damped).
//
// Step: implicit midpoint on the Lie group, w₁ solves
//   M(q_m)(w₁ − w₀)/h + c(q_m, w_m) + J⁻ᵀ(φ_m) K φ_m + C w_m = τ_gravity(q_m) + τ,
//   w_m = (w₀ + w₁)/2, exp(φ_m) = exp(h w_m / 2) exp(φ₀), exp(φ₁) = exp(h w_m) exp(φ₀),
// by a Newton iteration with S = M(q_m) + (h/2) C + (h²/4) J⁻ᵀ K J⁻¹ as its matrix, or one close
// to it (the residual is exact, so any matrix close enough converges to the same w₁, only the rate
// changes): S̃ = A + V Vᵀ, A = M(q_m) + (h²/4) J⁻ᵀ K J⁻¹ factored by the articulated-body recursion
// in O(K) (the springs' term is each joint's own 3×3 block, and enters the recursion as an
// armature does in Featherstone's ABA), V = √(h/2) M₀ Φ_r diag(√(2ζω)) the damping of C's r = 8
// lowest modes, added by Woodbury's identity (r solves with A, an r×r Cholesky); the rest of C is
// left out (the .cpp says why these modes). A step whose iteration with S̃ contracts by less than
// half goes on with the dense S, built (composite rigid bodies) and Cholesky-factored. The matrix
// is built once a step at the mid-step pose of the first guess (the last two steps' changes of w
// extrapolated): one kept from the steps before steers the iteration the worse the farther the
// part has moved since (a light section turning fast changes M within a step, and S⁻¹ magnifies
// that in the stiff, light directions), and the iterations that costs outweigh a factorization. A
// step whose iteration does not settle is taken as two halves, and so on down to 2⁻¹⁶ of it
// (15 µs of a 1 s step), the state at each depth kept (no allocation).
// Why this one: implicit midpoint is A-stable for the stiff linear springs at any step (they enter
// S whole: a stiff tube at 1/24 s settles in a few iterations where an explicit or split step
// would blow up), second order, symplectic (its energy error stays bounded and does not drift:
// 0.4 % over 10 s of a whipping soft part, tested), and its damping only removes energy. A
// variational energy-momentum integrator would keep the energy exactly but needs the derivatives
// of M(q); an XPBD rod converges to the rod only with many iterations; a co-rotational modal step
// needs an eigen-solve per step.
// Rest load. A constant generalized load b on φ (the springs pre-loaded so that the rest pose
// holds under gravity: ElasticSweep's "as modelled" rest) enters as the energy bᵀφ, i.e. the
// torque J⁻ᵀ(φ) b: the springs' rest angles shifted, a conservative load (a torque held fixed in
// the joint's axes is not one, and feeds a twisting part energy).
// Cost: an iteration is O(K) (Newton–Euler, the recursive solve, two n×r products) plus one dense
// O(K²) product (the damping C w, exact in the residual); the matrix O(K r²) to build and factor.
// The dense S instead: O(K²) to build, O(K³) to factor (at K = 32 the Cholesky of 93×93 was half
// a step's instructions), two dense products an iteration. At K = 32 on the soft tube of
// tools/bench/bench_chain.cpp (sweep-bench-chain --quick), S̃ against S: a step of 1/480 s takes
// 3.5 iterations (3.1 with S) and no dense factorization, one of 1/120 s 7.4 (7.0) and 0.008;
// 0.57 M instructions a step against S's 1.19 M at 1/480 s, 0.90 M against 1.50 M at 1/120 s
// (callgrind, the chain's steps alone); the whole ElasticSweep step 73 µs against 100 µs and 112
// against 151 µs: 3.5× and 3.8× the modal step, where S gave 5.2× and 6.0× (medians of three runs,
// alternated with S's build). Not yet the modal step's 1.5×: the time left is the recursion (r
// solves a step and one an iteration), the dense C w, and the pose and Newton–Euler each iteration.
// At K ≤ 16 the dense S is as fast or faster, and is kept there (kStructuredFrom).
//
// Units: metres, kilograms, seconds (the model's); the pose starts from the rest shape scaled by
// the model's metres per unit. Allocation-free after construction.
#include <Eigen/Dense>
#include <memory>
#include <span>
#include <vector>

#include "sweep/core/chain_model.h"
#include "sweep/core/frame.h"
#include "sweep/core/sweep_shape.h"

namespace sweep {

class ChainDynamics {
 public:
  ChainDynamics(std::shared_ptr<const ChainModel> model, const SweepShape& rest);

  // The body the chain's root is fixed to, as the part feels it: gravity (m/s²), the acceleration of
  // the body's origin (m/s²), its angular velocity (rad/s) and angular acceleration (rad/s²), all
  // in the body's axes (the rest shape's). Held over a step.
  struct Body {
    Vec3 gravity = Vec3::Zero();
    Vec3 acceleration = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();
    Vec3 angular_acceleration = Vec3::Zero();
  };

  int joints() const { return joints_; }
  const ChainModel& model() const { return *model_; }

  Vec3 angle(int i) const { return phi_.segment<3>(3 * (i - 1)); }  // φ_i, i = 1 .. K−1
  Vec3 speed(int i) const { return w_.segment<3>(3 * (i - 1)); }    // w_i
  void set_joint(int i, const Vec3& phi, const Vec3& w);

  // The springs' pre-load b (N·m, 3 per joint, A_i's axes at rest; empty: none), see above.
  void set_rest_load(std::span<const double> load);

  // The joints' state all at once, as ElasticSweep's rotational springs hold it: φ and w of joints
  // 1 .. K−1, 3 each.
  void set_state(std::span<const double> phi, std::span<const double> w);
  void get_state(std::span<double> phi, std::span<double> w) const;

  // Advances h seconds under `body` and joint torques `torque` (N·m, A_i's axes, 3 per joint, or
  // empty), both held over the step. Returns the Newton iterations it took.
  int step(double h, const Body& body, std::span<const double> torque = {});

  // An impulse P (N·s, body axes) at the point p (metres, body axes) carried by section i: the
  // joints' speeds jump by M⁻¹ Jᵀ P.
  void apply_impulse(int section, const Vec3& point, const Vec3& impulse);
  // A generalized impulse (N·m·s, A_i's axes, 3 per joint): w += M⁻¹ impulse.
  void apply_joint_impulse(std::span<const double> impulse);

  // The current pose: centres (metres) and rotations of sections 0 .. K−1, body axes.
  const std::vector<Vec3>& centres() const { return centre_; }
  const std::vector<Quat>& rotations() const { return rotation_; }

  // Energies (J) relative to the body: kinetic ½ Σ m v² + ½ Ωᵀ I Ω of the sections moving relative
  // to the body, elastic ½ Σ φᵀ K φ + bᵀφ (b the rest load), and gravity's potential −Σ m g · c.
  double kinetic_energy() const;
  double elastic_energy() const;
  double gravity_potential(const Vec3& gravity) const;

  // How many times the Newton matrix was built and factored (once a step, a halved step once a half).
  long long factorizations() const { return factorizations_; }
  // How many of those factorizations were the dense S, taken where the structured one (see above)
  // did not settle a step's iteration fast enough.
  long long dense_factorizations() const { return dense_factorizations_; }
  long long iterations() const { return iterations_; }  // the Newton iterations taken in all
  // Steps taken whose Newton iteration did not settle even at the shortest subdivision.
  long long unsettled() const { return unsettled_; }

  // x ← M(q)⁻¹ x at the current pose by the articulated-body recursion (O(K), no matrix formed).
  void solve_mass(Eigen::VectorXd& x);
  // The same for each column of x (3(K−1) rows), the recursion set up once.
  void solve_mass_columns(Eigen::MatrixXd& x);

  // C, the joints' damping (N·m·s/rad, dense, 3(K−1) square; see above).
  const Eigen::MatrixXd& damping() const { return damping_; }

  // Which Newton matrix a step starts from: the structured one (the default, from 16 joints on;
  // the dense S where it steers too slowly) or the dense S throughout (to measure the one against
  // the other).
  enum class NewtonMatrix { structured, dense };
  void set_newton_matrix(NewtonMatrix kind) { newton_kind_ = kind; }

  // The structured Newton matrix at the current pose for a step of h seconds, with the `modes`
  // lowest modes of C in it (all of them: S exactly), factored; and x ← S̃⁻¹ x by it. For tests.
  void factor_structured(double h, int modes);
  void solve_structured(Eigen::VectorXd& x);
  // The dense S at the current pose (joint angles taken as the mid-step's), for tests.
  const Eigen::MatrixXd& newton_matrix(double h);

  // The chain's mass matrix at the current pose (for tests and contacts), 3(K−1) square.
  const Eigen::MatrixXd& mass_matrix();
  // Inverse dynamics at the current pose: M ẇ + c(w) − τ_gravity, the torques the joints would
  // need for the accelerations `wdot` at the speeds `w` (vectors of 3(K−1)).
  void inverse_dynamics(const Eigen::VectorXd& w, const Eigen::VectorXd& wdot, const Body& body, Eigen::VectorXd& out);
  // The chain's static residual at the joint angles `phi`, at rest under `body`: the springs'
  // torque J⁻ᵀ(φ)(K φ + b) less gravity's and the body's, N·m, 3(K−1) entries (A_i's axes) — zero
  // where φ is an equilibrium. Its derivative there is the tangent stiffness (core/held_rest.h).
  // The state is left as it was.
  void static_residual(const Eigen::VectorXd& phi, const Body& body, Eigen::VectorXd& out);

 private:
  int advance(double h, const Body& body, std::span<const double> torque, int depth);
  // One implicit-midpoint step; false (the state left half-way) when its Newton iteration does
  // not converge.
  bool attempt(double h, const Body& body, std::span<const double> torque, int& iterations);
  // Centres, rotations, A frames from joint angles; nothing to do when they are, to the bit, the
  // angles the pose was last built from (the pose is a function of them alone): a kick and the
  // step after it, or a step after a state read back unchanged, load the same angles again.
  void set_pose(const Eigen::VectorXd& phi);
  void build_mass_matrix();                                                     // into mass_
  void elastic_torque(const Eigen::VectorXd& phi, Eigen::VectorXd& out) const;  // J⁻ᵀ (K φ + b)
  void build_newton_matrix(double h);   // S at the pose set_pose last built (phi_mid_), into newton_
  void factor_newton_matrix(double h);  // and factored, into llt_
  // The structured S̃ at the same pose with C's `modes` lowest modes (see the .cpp), factored.
  void build_structured(double h, int modes);
  void set_structured_size(int modes);  // the scratch for `modes` modes
  // The articulated-body recursion for M at the pose set_pose last built (plus joint_term_ on each
  // joint's own block when asked), and its solve.
  void factor_recursive(bool with_joint_terms = false);
  void solve_recursive(Eigen::Ref<Eigen::VectorXd> x);

  std::shared_ptr<const ChainModel> model_;
  int joints_ = 0;
  std::vector<Quat> relative_rotation_;  // rest T_{i−1,i}
  std::vector<Vec3> relative_offset_;    // metres, in section i−1's axes
  Vec3 root_centre_;
  Quat root_rotation_;
  std::vector<Vec3> stiffness_;  // per joint, diagonal (N·m/rad)
  Eigen::MatrixXd damping_;      // C, dense
  // C's factor M₀ Φ diag(√(2ζω)) (C = F Fᵀ, its columns by growing frequency), and the structured
  // Newton matrix's scratch: the joints' own terms (h²/4) J⁻ᵀ K J⁻¹, the kept modes' columns V
  // (√(h/2) F's), A⁻¹ V, the capacitance I + Vᵀ A⁻¹ V and its factorization.
  Eigen::MatrixXd damping_factor_;
  std::vector<Mat3> joint_term_;
  Eigen::MatrixXd low_rank_, low_rank_solved_, capacitance_;
  Eigen::LLT<Eigen::MatrixXd> capacitance_llt_;
  Eigen::VectorXd low_rank_scratch_;
  int low_rank_modes_ = 0;
  NewtonMatrix newton_kind_ = NewtonMatrix::structured;
  Eigen::VectorXd rest_load_;  // b
  Eigen::VectorXd phi_, w_;
  Eigen::VectorXd posed_phi_;  // the angles the current pose was built from
  bool posed_ = false;
  std::vector<Eigen::VectorXd> phi_saved_, w_saved_;  // the state at each depth of halving
  // The pose set_pose last built.
  std::vector<Vec3> centre_;
  std::vector<Quat> rotation_;
  std::vector<Mat3> pre_;      // R_{A_i}
  std::vector<Mat3> inertia_;  // world rotary inertia of each section
  // Scratch.
  Eigen::MatrixXd mass_, newton_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  // w₁ − w₀ of the last two converged steps, the next one's first guess, and their steps (0: none).
  Eigen::VectorXd last_change_, previous_change_;
  double last_change_step_ = 0, previous_change_step_ = 0;
  long long factorizations_ = 0, dense_factorizations_ = 0, iterations_ = 0, unsettled_ = 0;
  // The recursion: per joint, U_i = IA_i S_i (6×3, IA_i the articulated inertia about c_i) and
  // D_i⁻¹ (3×3), the pose it was set up at (axes P_i, lever c_{i+1} − c_i), and its scratch.
  using Mat63 = Eigen::Matrix<double, 6, 3>;
  std::vector<Mat63, Eigen::aligned_allocator<Mat63>> u_;
  std::vector<Mat3> d_inverse_, factored_axes_;
  std::vector<Vec3> y_, factored_lever_;
  Eigen::VectorXd phi_mid_, w_mid_, w_end_, wdot_, residual_, scratch_;
  std::vector<Vec3> omega_, alpha_, accel_, force_, moment_;
  std::vector<Vec3> composite_first_;
  std::vector<Mat3> composite_inertia_;
  std::vector<Mat3> crba_x_, crba_y_, crba_w_;  // the mass matrix's per-joint factors (build_mass_matrix)
};

// Rotation vector of a unit quaternion (angle in [0, π]); the inverse of rotation_from_vector.
Vec3 vector_from_rotation(const Quat& q);

}  // namespace sweep
