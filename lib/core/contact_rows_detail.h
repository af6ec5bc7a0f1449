#pragma once
// Contact rows: the contact solver's (sim/contact.h) way into an ElasticSweep's springs. Internal:
// not installed, since a game steps a sweep and reads its pose; only the solver moves it through rows.
//
// A contact row is one direction d at a point of the axis (t its arc length), as the springs see
// it: J = ∂(d·p)/∂q over the offsets and joint turns of the sections up to the point (linearised:
// the point taken between its two sections, which move it), built on the current pose. Through the
// rows the solver moves the part as a force held there over the step would (move_rows: each
// spring by its inertia and compliance), holds it across the normal as a static force would
// (apply_rows: each spring by its compliance 1/k, the least spring energy for the move) and kicks
// it as an impulse there would (each spring by its mass, the chain's mass matrix in material mode:
// with the exact chain, the mass matrix of its current pose, not the rest pose's modes).
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "sweep/core/elastic_sweep.h"

namespace sweep {

struct ContactRow {
  int first = 1, last = 0;                     // sections first..last take part
  std::vector<double> positional, rotational;  // J, index 3·(i − first) + c
  std::vector<double> modal;                   // material mode: Φᵀ Jᵀ over the joints (per metre)
};

// The rows' operations on one sweep at a time, and their scratch (an object reused across steps
// allocates nothing once sized).
class ContactRows {
 public:
  // Without `with_modal`, only good for row_speed (the modal part is what couplings and kicks need).
  static void contact_row(const ElasticSweep& sweep, double t, const Vec3& direction, ContactRow& row,
                          bool with_modal = true);
  // J_a M⁻¹ J_bᵀ (by_mass: the speed along b per N·s of impulse along a; with a == b the point's
  // mobility) or J_a C J_bᵀ (the move along b per N of force along a).
  static double row_coupling(const ElasticSweep& sweep, const ContactRow& a, const ContactRow& b, bool by_mass);
  // Every row_coupling of `rows` at once, by mass and by compliance (n × n), as matrix products.
  void row_couplings(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& by_mass,
                     Eigen::MatrixXd& by_compliance);
  // J C Jᵀ alone (the moves' couplings: rows without their modal part will do).
  void row_compliances(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& by_compliance);
  // J q̇: the point's speed along the row's direction, relative to the body.
  static double row_speed(const ElasticSweep& sweep, const ContactRow& row);
  // J (q − C f): how far the springs hold the point along the row from where the last step's loads
  // alone would hold it (mesh units), by the same compliance as row_coupling(…, false): a collider
  // holding the point there presses it with the force N of J C Jᵀ N = that (a quasi-static read).
  static double row_strain(const ElasticSweep& sweep, const ContactRow& row);
  // Kicks (amounts in N·s: q̇ += M⁻¹ Σ Jᵀ amount) or moves (amounts in N: q += C Σ Jᵀ amount, and
  // the shape is rebuilt).
  // With speeds_too, a move also adds itself over `dt` to the speeds (q̇ += Δq / dt): the step's
  // motion the move took back is taken out of its speeds as well.
  void apply_rows(ElasticSweep& sweep, std::span<const ContactRow> rows, std::span<const double> amounts,
                  bool as_impulses, double speeds_dt = 0);
  // The step's moves (the contact solver's push out of a collider): J G Jᵀ, the move along b per N
  // of force along a, G = (M/dt² + D/dt + K)⁻¹ per spring (per mode in material mode, which moves
  // by bending alone): what the step itself would have done with the force in it had it
  // been an implicit (backward Euler) step — the springs' inertia over a short step, their
  // compliance over a long one. A move shaped by compliance alone swings the whole part about a
  // point pushed near its root (a tube lying on the floor rose off it).
  void row_move_couplings(const ElasticSweep& sweep, std::span<const ContactRow> rows, double dt,
                          Eigen::MatrixXd& by_move);
  // Moves through those couplings (amounts in N: q += G Σ Jᵀ amount, the shape rebuilt), and the
  // speeds by the same move over dt (q̇ += Δq / dt: an impulse's share, by mass, over a short step):
  // the step's motion the move took back leaves the speeds too. Of that change of the speeds only
  // the part α ∈ [0, 1] that leaves the least kinetic energy is kept (all of it when it only stops
  // the step's motion, as under a part resting on the ground).
  void move_rows(ElasticSweep& sweep, std::span<const ContactRow> rows, std::span<const double> amounts, double dt);

 private:
  using Bank = ElasticSweep::Bank;
  // Each row's J as a column of `m` (sections 1..K−1, zero past its point), scaled by √share — the
  // kick's mass share or (kick false) the compliance 1/k — so that mᵀm is J D Jᵀ or J C Jᵀ.
  static void scaled_rows(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& m,
                          bool positional, bool kick);
  // Per coordinate: 1/mass (a kick) or 1/stiffness (a move).
  static double positional_share(const ElasticSweep& sweep, std::size_t m, bool by_mass);
  static double rotational_share(const ElasticSweep& sweep, std::size_t m, bool by_mass);
  // The contact moves' change of the speeds since v0, cut to the part that leaves the least
  // kinetic energy.
  void keep_least_energy_speeds(ElasticSweep& sweep);

  // The exact chain (ElasticSweep::exact_chain): the rows' rotational J over the joints as columns
  // (3(K−1) × n, zero past each row's point), and Σ Jᵀ amount over them.
  static void joint_columns(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& columns);
  void sum_joint_rows(const ElasticSweep& sweep, std::span<const ContactRow> rows, std::span<const double> amounts);
  // Its kinetic energy's change Σ v0ᵀ M Δv and Σ Δvᵀ M Δv (J) over the joints, M at the current pose.
  void exact_energy_change(const ElasticSweep& sweep, double& along, double& square);

  Eigen::MatrixXd jp_, jr_, modal_;  // the rows' J (positional, rotational) and Φᵀ Jᵀ, one column each
  Eigen::MatrixXd move_;             // the rows scaled by √G (row_move_couplings)
  std::vector<double> modal_sum_;    // the modal sum of apply_rows and move_rows
  // The exact chain's: M⁻¹ Jᵀ (or L⁻¹ Jᵀ) columns, Σ Jᵀ amount (N·m, SI), the step's move matrix
  // M(q)/dt² + C/dt + K factored at the pose and step row_move_couplings saw (move_dt_).
  Eigen::MatrixXd joint_solved_, move_matrix_;
  Eigen::VectorXd joint_sum_, joint_change_;
  Eigen::LLT<Eigen::MatrixXd> move_llt_;
  double move_dt_ = 0;
};

}  // namespace sweep
