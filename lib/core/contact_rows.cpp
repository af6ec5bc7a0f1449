// Contact rows (contact_rows_detail.h): how a point of a sweep's axis moves with its springs, and
// moving or kicking the part through them. The contact solver (sim/contact.cpp) decides where.
#include <algorithm>
#include <cassert>
#include <cmath>

#include "sweep/core/contact_rows_detail.h"

namespace sweep {

// The axis point at t, between sections j and j+1 at u, taken as (1−u)·c_j + u·c_{j+1}: the
// Hermite curve between them moves with both ends, and the solver re-measures the true curve after
// every move, so this linearisation sets how fast the solver converges, not where it ends. Section
// i's offset x_i moves every section from i on by A_i x_i; its joint turn φ_i turns every section
// from i on about c_i, in A_i's axes.
void ContactRows::contact_row(const ElasticSweep& sweep, double t, const Vec3& direction, ContactRow& row,
                              bool with_modal) {
  const SpanCoord sc = locate_span(sweep.deformed_, t);
  const int j = sc.span;
  const double w[2] = {1.0 - sc.u, sc.u};
  row.first = 1;
  row.last = sc.u > 0 ? j + 1 : j;
  const std::size_t count = static_cast<std::size_t>(3) * std::max(row.last - row.first + 1, 0);
  row.positional.resize(count);
  row.rotational.resize(count);
  for (int i = row.first; i <= row.last; ++i) {
    double share = 0;
    Vec3 lever = Vec3::Zero();
    for (int e = 0; e < 2; ++e) {
      const int k = j + e;
      if (k < i || k > row.last) continue;
      share += w[e];
      lever += w[e] * (sweep.deformed_.frames[k].center - sweep.deformed_.frames[i].center);
    }
    for (int c = 0; c < 3; ++c) {
      const Vec3 axis = sweep.pre_[i].rotation * Vec3::Unit(c);
      const std::size_t q = static_cast<std::size_t>(3) * (i - row.first) + c;
      row.positional[q] = share * direction.dot(axis);
      row.rotational[q] = direction.dot(axis.cross(lever));
    }
  }
  // The exact chain's couplings come from its current pose (joint_columns), not the modes.
  if (!sweep.chain_ || !with_modal || sweep.exact_chain()) return;
  // Φᵀ Jᵀ, J zero past the point: only the first 3·last rows of Φ take part.
  const Eigen::Index dim = static_cast<Eigen::Index>(sweep.modal_.x.size());
  const Eigen::Index used = static_cast<Eigen::Index>(count);
  row.modal.resize(static_cast<std::size_t>(dim));
  Eigen::Map<Eigen::VectorXd>(row.modal.data(), dim).noalias() =
      sweep.chain_->modes.topRows(used).transpose() * Eigen::Map<const Eigen::VectorXd>(row.rotational.data(), used);
}

double ContactRows::row_coupling(const ElasticSweep& sweep, const ContactRow& a, const ContactRow& b, bool by_mass) {
  // Both rows start at section 1: they share the shorter one's coordinates.
  const std::size_t shared = std::min(a.positional.size(), b.positional.size());
  double sum = 0;
  for (std::size_t q = 0; q < shared; ++q) {
    sum += a.positional[q] * b.positional[q] * positional_share(sweep, 3 + q, by_mass);
    if (!sweep.chain_ || !by_mass) sum += a.rotational[q] * b.rotational[q] * rotational_share(sweep, 3 + q, by_mass);
  }
  if (!sweep.chain_ || !by_mass) return sum;
  if (sweep.exact_chain()) {
    // J_a M(q)⁻¹ J_bᵀ with the mass matrix of the current pose (lever arms in mesh units).
    const Eigen::Index dim = static_cast<Eigen::Index>(sweep.exact_torque_.size());
    Eigen::VectorXd ja = Eigen::VectorXd::Zero(dim), jb = Eigen::VectorXd::Zero(dim);
    ja.head(static_cast<Eigen::Index>(a.rotational.size())) =
        Eigen::Map<const Eigen::VectorXd>(a.rotational.data(), static_cast<Eigen::Index>(a.rotational.size()));
    jb.head(static_cast<Eigen::Index>(b.rotational.size())) =
        Eigen::Map<const Eigen::VectorXd>(b.rotational.data(), static_cast<Eigen::Index>(b.rotational.size()));
    sweep.sync_exact();
    sweep.exact_->solve_mass(jb);
    return sum + sweep.chain_->metres_per_unit * ja.dot(jb);
  }
  // J_a Φ Φᵀ J_bᵀ (M⁻¹ = Φ Φᵀ, SI) with the lever arms in mesh units: × metres per unit.
  const Eigen::Index dim = static_cast<Eigen::Index>(a.modal.size());
  return sum + sweep.chain_->metres_per_unit * Eigen::Map<const Eigen::VectorXd>(a.modal.data(), dim)
                                                   .dot(Eigen::Map<const Eigen::VectorXd>(b.modal.data(), dim));
}

void ContactRows::scaled_rows(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& m,
                              bool positional, bool kick) {
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index coords = static_cast<Eigen::Index>(sweep.positional_.x.size()) - 3;  // sections 1..K−1
  m.setZero(coords, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::vector<double>& j = positional ? rows[k].positional : rows[k].rotational;
    for (std::size_t q = 0; q < j.size(); ++q) {
      const double share = positional ? positional_share(sweep, 3 + q, kick) : rotational_share(sweep, 3 + q, kick);
      m(static_cast<Eigen::Index>(q), k) = j[q] * std::sqrt(share);
    }
  }
}

void ContactRows::row_couplings(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& by_mass,
                                Eigen::MatrixXd& by_compliance) {
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  const auto fill = [&](Eigen::MatrixXd& m, bool positional, bool kick) {
    scaled_rows(sweep, rows, m, positional, kick);
  };
  row_compliances(sweep, rows, by_compliance);
  fill(jp_, true, true);
  by_mass.noalias() = jp_.transpose() * jp_;
  if (!sweep.chain_) {
    fill(jr_, false, true);
    by_mass.noalias() += jr_.transpose() * jr_;
    return;
  }
  if (sweep.exact_chain()) {
    // J M(q)⁻¹ Jᵀ × metres per unit, M⁻¹ by the articulated-body recursion at the current pose.
    joint_columns(sweep, rows, jr_);
    joint_solved_ = jr_;
    sweep.sync_exact();
    sweep.exact_->solve_mass_columns(joint_solved_);
    by_mass.noalias() += sweep.chain_->metres_per_unit * (jr_.transpose() * joint_solved_);
    return;
  }
  // J Φ Φᵀ Jᵀ × metres per unit: the modal columns.
  const Eigen::Index dim = static_cast<Eigen::Index>(sweep.modal_.x.size());
  modal_.resize(dim, n);
  for (Eigen::Index k = 0; k < n; ++k) modal_.col(k) = Eigen::Map<const Eigen::VectorXd>(rows[k].modal.data(), dim);
  by_mass.noalias() += sweep.chain_->metres_per_unit * (modal_.transpose() * modal_);
}

void ContactRows::row_compliances(const ElasticSweep& sweep, std::span<const ContactRow> rows,
                                  Eigen::MatrixXd& by_compliance) {
  const auto fill = [&](Eigen::MatrixXd& m, bool positional) { scaled_rows(sweep, rows, m, positional, false); };
  fill(jp_, true);
  fill(jr_, false);
  by_compliance.noalias() = jp_.transpose() * jp_;
  by_compliance.noalias() += jr_.transpose() * jr_;
}

// Per coordinate: 1/mass (a kick) or 1/stiffness (a move). A material joint's stiffness is the
// chain's (N·m/rad; the diagonal of its block), its lever arms in mesh units: × metres per unit.
double ContactRows::positional_share(const ElasticSweep& sweep, std::size_t m, bool by_mass) {
  if (by_mass) return 1.0 / sweep.positional_.params[m].mass;
  // Material mode moves by bending alone: its stretch and shear springs are stiff and carry
  // whatever fast oscillation a kick gave them, so moving one, however little, can hand the part
  // that spring's energy (tried in move_rows: a kicked tube gained 24 kJ in one move and went
  // through a thin plate). So no move relieves them of a load a collider takes: a soft part lying
  // along the floor keeps its whole weight on its first span's shear springs.
  return sweep.chain_ ? 0.0 : 1.0 / sweep.positional_.params[m].stiffness;
}
double ContactRows::rotational_share(const ElasticSweep& sweep, std::size_t m, bool by_mass) {
  if (!sweep.chain_)
    return by_mass ? 1.0 / sweep.rotational_.params[m].mass : 1.0 / sweep.rotational_.params[m].stiffness;
  assert(!by_mass);  // the chain's masses are coupled: the modal part of the row carries them
  const Eigen::Index q = static_cast<Eigen::Index>(m) - 3;
  return sweep.chain_->metres_per_unit / sweep.chain_->stiffness(q, q);
}

double ContactRows::row_speed(const ElasticSweep& sweep, const ContactRow& row) {
  double v = 0;
  for (std::size_t q = 0; q < row.positional.size(); ++q) {
    v += row.positional[q] * sweep.positional_.v[3 + q] + row.rotational[q] * sweep.rotational_.v[3 + q];
  }
  return v;
}

double ContactRows::row_strain(const ElasticSweep& sweep, const ContactRow& row) {
  double d = 0;
  for (std::size_t q = 0; q < row.positional.size(); ++q) {
    const double cp = positional_share(sweep, 3 + q, false), cr = rotational_share(sweep, 3 + q, false);
    if (cp > 0) d += row.positional[q] * (sweep.positional_.x[3 + q] - cp * sweep.positional_.f[3 + q]);
    if (cr > 0) d += row.rotational[q] * (sweep.rotational_.x[3 + q] - cr * sweep.rotational_.f[3 + q]);
  }
  return d;
}

void ContactRows::apply_rows(ElasticSweep& sweep, std::span<const ContactRow> rows, std::span<const double> amounts,
                             bool as_impulses, double speeds_dt) {
  assert(rows.size() == amounts.size());
  sweep.modes_from_joints_if_due();  // read and changed below
  const bool speeds_too = !as_impulses && speeds_dt > 0;
  if (speeds_too) {
    // The speeds before, to take the move's share of them back out below.
    for (Bank* b : {&sweep.positional_, &sweep.rotational_, &sweep.modal_})
      std::copy(b->v.begin(), b->v.end(), b->v0.begin());
  }
  std::vector<double>& pos = as_impulses ? sweep.positional_.v : sweep.positional_.x;
  std::vector<double>& rot = as_impulses ? sweep.rotational_.v : sweep.rotational_.x;
  const bool exact = sweep.exact_chain() && as_impulses;
  const bool modal = sweep.chain_ && as_impulses && !exact;
  const Eigen::Index dim = static_cast<Eigen::Index>(sweep.modal_.x.size());
  if (modal) modal_sum_.assign(static_cast<std::size_t>(dim), 0.0);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double s = amounts[k];
    if (s == 0) continue;
    const ContactRow& row = rows[k];
    for (std::size_t q = 0; q < row.positional.size(); ++q) {
      const double dp = s * row.positional[q] * positional_share(sweep, 3 + q, as_impulses);
      pos[3 + q] += dp;
      if (speeds_dt > 0) sweep.positional_.v[3 + q] += dp / speeds_dt;
      if (!modal && !exact) {
        const double dr = s * row.rotational[q] * rotational_share(sweep, 3 + q, as_impulses);
        rot[3 + q] += dr;
        if (speeds_dt > 0) sweep.rotational_.v[3 + q] += dr / speeds_dt;
      }
    }
    if (modal) {
      Eigen::Map<Eigen::VectorXd>(modal_sum_.data(), dim) +=
          (s * sweep.chain_->metres_per_unit) * Eigen::Map<const Eigen::VectorXd>(row.modal.data(), dim);
    }
  }
  sweep.positional_.active = sweep.rotational_.active = true;
  if (exact) {
    // Δw = M(q)⁻¹ Σ Jᵀ s (× metres per unit) at the current pose, as ElasticSweep::kick.
    sum_joint_rows(sweep, rows, amounts);
    sweep.sync_exact();
    sweep.exact_->apply_joint_impulse({joint_sum_.data(), static_cast<std::size_t>(joint_sum_.size())});
    sweep.exact_->get_state(std::span<double>(sweep.rotational_.x).subspan(3, static_cast<std::size_t>(dim)),
                            std::span<double>(sweep.rotational_.v).subspan(3, static_cast<std::size_t>(dim)));
  }
  if (sweep.chain_) {
    sweep.modal_.active = true;
    if (modal) {
      // Δη̇ = Φᵀ Jᵀ s (per metre × metres per unit), then the joints follow the modes.
      Eigen::Map<Eigen::VectorXd>(sweep.modal_.v.data(), dim) +=
          Eigen::Map<const Eigen::VectorXd>(modal_sum_.data(), dim);
      sweep.joints_from_modes();
    } else {
      sweep.modes_from_joints();  // the joints moved: the modes follow them
    }
  }
  if (!as_impulses) sweep.rebuild();
  // Δq / dt is a change of speed not made by an impulse (the move shares itself by compliance, an
  // impulse by mass), so it could add kinetic energy where it does not only cancel the step's own
  // motion.
  if (speeds_too) keep_least_energy_speeds(sweep);
}

void ContactRows::keep_least_energy_speeds(ElasticSweep& sweep) {
  // Take the part α ∈ [0, 1] of the change since v0 that leaves the least kinetic energy: all of
  // it when it only cancels motion (a part resting on the ground), never more energy than before.
  const bool exact = sweep.exact_chain();
  Bank* moving = sweep.chain_ ? &sweep.modal_ : &sweep.rotational_;
  double along = 0, square = 0;  // Σ m v0 Δv and Σ m Δv², over the coordinates that carry energy
  if (exact) exact_energy_change(sweep, along, square);
  for (const Bank* b : {static_cast<const Bank*>(&sweep.positional_), static_cast<const Bank*>(moving)}) {
    if (exact && b == moving) continue;  // the joints' share is the exact chain's, above
    const double unit = sweep.energy_unit(*b);
    for (std::size_t m = static_cast<std::size_t>(b->width); m < b->v.size(); ++m) {
      const double dv = b->v[m] - b->v0[m];
      along += unit * b->params[m].mass * b->v0[m] * dv;
      square += unit * b->params[m].mass * dv * dv;
    }
  }
  const double alpha = square > 0 ? std::clamp(-along / square, 0.0, 1.0) : 0.0;
  for (Bank* b : {&sweep.positional_, &sweep.rotational_, &sweep.modal_}) {
    for (std::size_t m = 0; m < b->v.size(); ++m) b->v[m] = b->v0[m] + alpha * (b->v[m] - b->v0[m]);
  }
}

void ContactRows::joint_columns(const ElasticSweep& sweep, std::span<const ContactRow> rows, Eigen::MatrixXd& columns) {
  const Eigen::Index dim = static_cast<Eigen::Index>(sweep.exact_torque_.size());
  columns.setZero(dim, static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double>& j = rows[k].rotational;
    columns.col(static_cast<Eigen::Index>(k)).head(static_cast<Eigen::Index>(j.size())) =
        Eigen::Map<const Eigen::VectorXd>(j.data(), static_cast<Eigen::Index>(j.size()));
  }
}

void ContactRows::sum_joint_rows(const ElasticSweep& sweep, std::span<const ContactRow> rows,
                                 std::span<const double> amounts) {
  // Amounts in N (or N·s) at lever arms in mesh units: × metres per unit for N·m (N·m·s).
  joint_sum_.setZero(static_cast<Eigen::Index>(sweep.exact_torque_.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (amounts[k] == 0) continue;
    const std::vector<double>& j = rows[k].rotational;
    joint_sum_.head(static_cast<Eigen::Index>(j.size())) +=
        (amounts[k] * sweep.chain_->metres_per_unit) *
        Eigen::Map<const Eigen::VectorXd>(j.data(), static_cast<Eigen::Index>(j.size()));
  }
}

void ContactRows::exact_energy_change(const ElasticSweep& sweep, double& along, double& square) {
  const Eigen::Index dim = static_cast<Eigen::Index>(sweep.exact_torque_.size());
  const Eigen::Map<const Eigen::VectorXd> v0(sweep.rotational_.v0.data() + 3, dim);
  joint_change_ = Eigen::Map<const Eigen::VectorXd>(sweep.rotational_.v.data() + 3, dim) - v0;
  sweep.sync_exact();
  joint_sum_.noalias() = sweep.exact_->mass_matrix() * joint_change_;
  along += v0.dot(joint_sum_);
  square += joint_change_.dot(joint_sum_);
}

// 1 / (m/dt² + c/dt + k): one spring's move per unit of force held over a step dt.
namespace {
// exp(turn) exp(φ) as a rotation vector: a joint turned on the left, in its own A_i axes.
Vec3 turned_by(const Vec3& turn, const Vec3& phi) {
  return vector_from_rotation(rotation_from_vector(turn) * rotation_from_vector(phi));
}

double step_compliance(const OscillatorParams& p, double dt) {
  assert(dt > 0);  // an undamped spring over no time would be 0/0
  return 1.0 / (p.mass / (dt * dt) + p.damping / dt + p.stiffness);
}
}  // namespace

void ContactRows::row_move_couplings(const ElasticSweep& sweep, std::span<const ContactRow> rows, double dt,
                                     Eigen::MatrixXd& by_move) {
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index coords = static_cast<Eigen::Index>(sweep.positional_.x.size()) - 3;  // sections 1..K−1
  if (sweep.exact_chain()) {
    // The exact chain's implicit step to a force held over it, linearised at the current pose:
    // G = (M(q)/dt² + C/dt + K)⁻¹ over the joints (bending alone, as the modes'), J G Jᵀ × metres
    // per unit through G's Cholesky factor.
    sweep.sync_exact();
    const ChainDynamics& chain = *sweep.exact_;
    move_matrix_ = sweep.exact_->mass_matrix();
    move_matrix_ *= 1.0 / (dt * dt);
    move_matrix_.noalias() += (1.0 / dt) * chain.damping();
    move_matrix_.diagonal() += sweep.chain_->stiffness.diagonal();
    move_llt_.compute(move_matrix_);
    move_dt_ = dt;
    joint_columns(sweep, rows, joint_solved_);
    move_llt_.matrixL().solveInPlace(joint_solved_);
    by_move.noalias() = sweep.chain_->metres_per_unit * (joint_solved_.transpose() * joint_solved_);
    return;
  }
  // Each row as a column, scaled by √G: the modes' part (Φᵀ Jᵀ, × metres per unit as the kicks';
  // material mode moves by bending alone, as its static moves: see positional_share), or the
  // paper's rotational and positional springs'.
  const Eigen::Index dim = sweep.chain_ ? static_cast<Eigen::Index>(sweep.modal_.x.size()) : 2 * coords;
  move_.setZero(dim, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const ContactRow& row = rows[static_cast<std::size_t>(k)];
    if (sweep.chain_) {
      assert(static_cast<Eigen::Index>(row.modal.size()) == dim);
      for (Eigen::Index c = 0; c < dim; ++c) {
        const std::size_t m = static_cast<std::size_t>(c);
        move_(c, k) =
            row.modal[m] * std::sqrt(sweep.chain_->metres_per_unit * step_compliance(sweep.modal_.params[m], dt));
      }
      continue;
    }
    for (std::size_t q = 0; q < row.positional.size(); ++q) {
      const Eigen::Index i = static_cast<Eigen::Index>(q);
      move_(i, k) = row.rotational[q] * std::sqrt(step_compliance(sweep.rotational_.params[3 + q], dt));
      move_(coords + i, k) = row.positional[q] * std::sqrt(step_compliance(sweep.positional_.params[3 + q], dt));
    }
  }
  by_move.noalias() = move_.transpose() * move_;
}

void ContactRows::move_rows(ElasticSweep& sweep, std::span<const ContactRow> rows, std::span<const double> amounts,
                            double dt) {
  assert(rows.size() == amounts.size());
  sweep.modes_from_joints_if_due();  // read and changed below
  for (Bank* b : {&sweep.positional_, &sweep.rotational_, &sweep.modal_})
    std::copy(b->v.begin(), b->v.end(), b->v0.begin());
  const auto move = [&](Bank& b, std::size_t m, double load) {
    const double dx = load * step_compliance(b.params[m], dt);
    b.x[m] += dx;
    b.v[m] += dx / dt;
  };
  if (sweep.exact_chain()) {
    // Δ = G Jᵀ Σ amount (row_move_couplings' G; built again if the step changed), each joint
    // turned by it on the left as its speed w turns it, and w += Δ / dt.
    if (move_dt_ != dt) {
      Eigen::MatrixXd unused;
      row_move_couplings(sweep, rows, dt, unused);
    }
    sum_joint_rows(sweep, rows, amounts);
    move_llt_.solveInPlace(joint_sum_);
    for (int i = 1; i <= sweep.chain_->joints; ++i) {
      const Vec3 turn = joint_sum_.segment<3>(3 * (i - 1));
      const Vec3 phi = turned_by(turn, sweep.rotation_vector(i));
      for (int c = 0; c < 3; ++c) {
        sweep.rotational_.x[3 * i + c] = phi[c];
        sweep.rotational_.v[3 * i + c] += turn[c] / dt;
      }
    }
    sweep.modal_.active = sweep.rotational_.active = true;
    sweep.modes_from_joints();
  } else if (sweep.chain_) {
    // The modal load Φᵀ Jᵀ Σ amount (per metre × metres per unit), as a kick's; the joints follow.
    const Eigen::Index dim = static_cast<Eigen::Index>(sweep.modal_.x.size());
    modal_sum_.assign(static_cast<std::size_t>(dim), 0.0);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (amounts[k] == 0) continue;
      Eigen::Map<Eigen::VectorXd>(modal_sum_.data(), dim) +=
          (amounts[k] * sweep.chain_->metres_per_unit) * Eigen::Map<const Eigen::VectorXd>(rows[k].modal.data(), dim);
    }
    for (std::size_t m = 0; m < modal_sum_.size(); ++m) move(sweep.modal_, m, modal_sum_[m]);
    sweep.modal_.active = sweep.rotational_.active = true;
    sweep.joints_from_modes();
  } else {
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const double s = amounts[k];
      if (s == 0) continue;
      const ContactRow& row = rows[k];
      for (std::size_t q = 0; q < row.positional.size(); ++q) {
        move(sweep.positional_, 3 + q, s * row.positional[q]);
        move(sweep.rotational_, 3 + q, s * row.rotational[q]);
      }
    }
    sweep.positional_.active = sweep.rotational_.active = true;
  }
  sweep.rebuild();
  keep_least_energy_speeds(sweep);
}

}  // namespace sweep
