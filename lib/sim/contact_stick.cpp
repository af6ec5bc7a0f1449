// Static friction on positions: ContactSolver::hold, called by resolve() once the ends
// are out of the colliders and N is read, before the speeds' friction.
//
// Why positions: friction on the speeds alone holds a stiff part only for the step it kicks it —
// its springs hand the slip back within the next step, and the drag becomes m_eff·v/dt, not μN
// (tests/sim/friction_test.cpp). Here, as in position-based dynamics' friction (Macklin et al.,
// "Unified particle physics", 2014), each touching station has an anchor on its collider — where
// its contact started or where it last slid to — and at the end of every step it is moved back
// there across the normal, through the springs' compliance as the normal move is, when the force
// that takes stays in the cone |F| ≤ μN (stick); else it is moved only as far as leaves the springs
// pressing it with μN against its slip, and the anchor follows it (slide). Neighbouring stations on
// one collider are a patch and share their cones (Σ|F| ≤ Σ μN; see below). The force is the
// quasi-static one, as N's own reading (ContactRows::row_strain): F = W⁺ J (q − C f), W = J C Jᵀ
// over all the held rows together (W⁺ over the modes the springs bend: see below), less what the
// normal forces do across (W_tn N). It depends on
// where the springs are, not on the step: the drag of a steady slide is μN at any step and frame
// rate. Nor may its move stop more of the station's momentum than the cone gives over the step
// (μN·dt; see below). What of the cone the hold spends, the speeds' friction may not.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "sweep/core/sweep_shape.h"
#include "sweep/sim/contact_detail.h"

namespace sweep::sim {
namespace {

// A held row whose compliance is below this share of the largest is one no spring moves (the
// root; the first span in material mode): it is not held on positions, its speeds' friction is.
constexpr double kMovable = 1e-12;
// A mode of the held rows' compliance W is held on positions when its compliance is at least this
// share of the largest (see below).
constexpr double kBends = 1e-2;
// After the hold, a gap below this (× the length) sends the part back through the normal move.
constexpr double kGapSlack = 1e-7;

// A⁺ over the modes of a symmetric positive semi-definite A whose eigenvalue is above `share` of
// its largest (the others left out: see kBends).
Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& a, double share) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> modes(a);
  const Eigen::VectorXd& lambda = modes.eigenvalues();  // ascending
  const Eigen::Index n = lambda.size();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (lambda[i] > share * lambda[n - 1]) inverse[i] = 1 / lambda[i];
  }
  return modes.eigenvectors() * inverse.asDiagonal() * modes.eigenvectors().transpose();
}

// Two unit directions across a normal, the same at every step for the same normal.
std::array<Vec3, 2> across_of(const Vec3& normal) {
  const Vec3 first = normal.unitOrthogonal();
  return {first, normal.cross(first)};
}

}  // namespace

void ContactSolver::hold(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt) {
  const std::size_t n = planes_.size();
  spent_.assign(n, 0.0);
  const std::size_t stations = stations_.size();
  if (anchors_.size() != colliders.size() * stations) anchors_.assign(colliders.size() * stations, Anchor{});

  // One pair per station and collider pressed with friction (its planes are adjacent in planes_:
  // two chords' ends meeting there). The pair's cone is its planes' together; the first plane's
  // speeds take what the hold leaves of it, the others' none (spent_ below).
  held_pairs_.clear();
  for (std::size_t p = 0; p < n; ++p) {
    const double mu = colliders[planes_[p].collider].collider->friction;
    if (!(pressed_[p] > 0) || !(mu > 0)) continue;
    const std::size_t key = planes_[p].collider * stations + static_cast<std::size_t>(planes_[p].station);
    if (!held_pairs_.empty() && held_pairs_.back().anchor == key) {
      held_pairs_.back().cone += mu * pressed_[p] / dt;
      spent_[p] = mu * pressed_[p];
      spent_[held_pairs_.back().plane] -= mu * pressed_[p];
      continue;
    }
    held_pairs_.push_back({p, key, mu * pressed_[p] / dt});
  }
  const auto here_local = [&](const Held& h) {
    const Plane& pl = planes_[h.plane];
    return colliders[pl.collider].to_mesh.to_local(center_at(sweep.deformed(), stations_[pl.station]));
  };
  // A pair that touched at the last step too is held; a new one is anchored where it is now (its
  // first step's slip is the speeds' friction's).
  const auto held_before = [&](const Held& h) { return anchors_[h.anchor].step == step_ - 1; };
  const auto fresh = std::stable_partition(held_pairs_.begin(), held_pairs_.end(), held_before);
  for (auto h = fresh; h != held_pairs_.end(); ++h) anchors_[h->anchor] = {here_local(*h), step_};
  const std::size_t m = static_cast<std::size_t>(fresh - held_pairs_.begin());
  if (m == 0) return;

  // Two rows across each held pair's normal (fixed in the collider: the same at every step), then
  // the normal rows, for W_tn. With their modal part: the momentum check below reads J M⁻¹ Jᵀ.
  work_->stick.resize(2 * m + n);
  Eigen::VectorXd offset(2 * m);  // how far each held station is off its anchor along its rows
  for (std::size_t k = 0; k < m; ++k) {
    const Held& h = held_pairs_[k];
    const Plane& pl = planes_[h.plane];
    const PlacedCollider& placed = colliders[pl.collider];
    const std::array<Vec3, 2> across = across_of(pl.normal);
    const Vec3 off = here_local(h) - anchors_[h.anchor].local;
    for (int r = 0; r < 2; ++r) {
      ContactRows::contact_row(sweep, stations_[pl.station], placed.to_mesh.rotation * across[r],
                               work_->stick[2 * k + r]);
      offset[static_cast<Eigen::Index>(2 * k + r)] = across[r].dot(off);
    }
  }
  std::copy(work_->normal.begin(), work_->normal.end(), work_->stick.begin() + static_cast<std::ptrdiff_t>(2 * m));
  work_->ops.row_couplings(sweep, work_->stick, work_->stick_by_mass, work_->stick_by_compliance);
  const Eigen::Index t = static_cast<Eigen::Index>(2 * m);
  const Eigen::MatrixXd& w = work_->stick_by_compliance;

  // The rows held: both of each pair where some spring moves its station.
  double largest = 0;
  for (Eigen::Index r = 0; r < t; ++r) largest = std::max(largest, w(r, r));
  std::vector<Eigen::Index> kept;
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Index a = static_cast<Eigen::Index>(2 * k);
    if (w(a, a) + w(a + 1, a + 1) > kMovable * largest) kept.insert(kept.end(), {a, a + 1});
  }
  if (kept.empty()) return;
  const Eigen::Index h = static_cast<Eigen::Index>(kept.size());
  Eigen::MatrixXd wtt(h, h);
  Eigen::VectorXd strain(h), off(h);
  const Eigen::Map<const Eigen::VectorXd> normal_force(held_.data(), static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < h; ++i) {
    for (Eigen::Index j = 0; j < h; ++j) wtt(i, j) = w(kept[i], kept[j]);
    strain[i] = ContactRows::row_strain(sweep, work_->stick[static_cast<std::size_t>(kept[i])]) -
                w.row(kept[i]).segment(t, static_cast<Eigen::Index>(n)).dot(normal_force);
    off[i] = offset[kept[i]];
  }
  // F = W⁺ s over W's modes the springs move by bending, the others left to the speeds' friction.
  // Two reasons for modes they barely move: across a part lying along the floor, its own axis
  // (moved only through the sag's lever: ~(sag/L)² of the bend's compliance), where J (q − C f)
  // reads the curve's second-order shortening, not a force — over that compliance, tens of μN;
  // and two stations close on a stiff chain pushed apart (nearly the same rows), where W⁻¹ reads
  // two huge opposite forces out of rounding.
  const Eigen::MatrixXd pinv = pseudo_inverse(wtt, kBends);
  // The force across the normal the springs press each station with now, and once moved back
  // onto its anchor (a move of amount a changes J q by W a, so the force by a).
  const Eigen::VectorXd now = pinv * strain;
  const Eigen::VectorXd back = pinv * (strain - off);
  stick_amount_.assign(2 * m, 0.0);
  std::vector<char> slid(m, 0);
  std::vector<double> taken(m, 0.0);  // N·s of each pair's cone the hold takes
  // The held pairs in patches: neighbouring stations on one collider. A patch shares its cones
  // (friction per patch, as game engines' patch friction: the normal force along a stiff part lying
  // on the ground is the solver's choice among many that hold it — a statically indeterminate
  // contact — and a station it leaves lightly pressed would slide under the load its neighbours
  // hold).
  struct Patch {
    Eigen::Index from = 0, to = 0;  // kept rows [from, to)
    double cone = 0;                // Σ μN, N
    double held = 0;                // N·s of it the springs' force takes over the step
  };
  const auto pair_at = [&](Eigen::Index row) { return static_cast<std::size_t>(kept[row] / 2); };
  std::vector<Patch> patches;
  for (Eigen::Index i = 0; i < h; i += 2) {
    const Plane& pl = planes_[held_pairs_[pair_at(i)].plane];
    bool joins = false;
    if (i > 0) {
      const Plane& before = planes_[held_pairs_[pair_at(i - 2)].plane];
      joins = before.collider == pl.collider && pl.station - before.station <= 2 * per_span_;
    }
    if (!joins) patches.push_back({i, i, 0.0, 0.0});
    patches.back().to = i + 2;
    patches.back().cone += held_pairs_[pair_at(i)].cone;
  }
  // Stick while the patch's cone holds its stations' forces; else slide, each pressed by its share
  // of the cone along the same line.
  for (Patch& patch : patches) {
    double force = 0;
    for (Eigen::Index i = patch.from; i < patch.to; i += 2) force += back.segment<2>(i).norm();
    const double scale = force > patch.cone ? patch.cone / force : 1.0;
    patch.held = scale * force * dt;
    for (Eigen::Index i = patch.from; i < patch.to; i += 2) {
      const std::size_t k = pair_at(i);
      slid[k] = scale < 1;
      stick_amount_[2 * k] = scale * back[i] - now[i];
      stick_amount_[2 * k + 1] = scale * back[i + 1] - now[i + 1];
    }
  }
  // The springs' force is not all a hold takes: its move sets the speeds by Δq/dt, stopping
  // whatever the station carried off its anchor over the step — the impulse P that changes the
  // rows' speeds by W a / dt, P = (J M⁻¹ Jᵀ)⁺ W a / dt. A patch stops no more than its cone gives
  // over the step (μN·dt): past that its move is cut to the share that does, and its stations
  // slide. What it takes of the cone is the larger of the force it holds over the step and the
  // momentum it stops (two readings of one friction, as N's), shared by its pairs as their cones
  // are, so that the speeds' friction after it cannot take a second cone. A patch's impulse is
  // its stations' together, as vectors: along a chain the rows' impulses that make a smooth change
  // of speed alternate (20–40× the stations' own m Δv, each alone, on a stiff tube lying on a
  // slope, which let it slide 2.4 units down the slope at μ = 2; together they are its momentum).
  // Unlike the force check's Σ|F|, opposite impulses cancel: a review summed |P| instead — the same
  // wherever the tube sticks, but below tan θ (μ = tan θ / 2) the stiff tube slid 0.29 units rather
  // than 0.38, the rubber one 13.4 rather than 6.2; neither is a closed form, the vector sum is
  // chosen for the reason above.
  // (An approximation, measured rather than derived: in material mode J M⁻¹ Jᵀ includes the
  // stretch and shear shifts' diagonal masses, which the hold's move does not move; with the
  // joints' masses alone P reads 1.2–5× larger, and the rubber tube below was thrown again.) Held
  // by the springs' force alone, a soft tube whipping as it landed on a frictional slope was
  // carried 1.5 to 22 units a step off its anchors, moved back through the compliance and stopped
  // for free, its springs pumped by 5 to 200 J a step: it was thrown 10 units up.
  {
    Eigen::VectorXd amount(h);
    Eigen::MatrixXd wmm(h, h);
    for (Eigen::Index i = 0; i < h; ++i) {
      amount[i] = stick_amount_[static_cast<std::size_t>(kept[i])];
      for (Eigen::Index j = 0; j < h; ++j) wmm(i, j) = work_->stick_by_mass(kept[i], kept[j]);
    }
    const Eigen::VectorXd impulse = pseudo_inverse(wmm, kBends) * (wtt * amount / dt);
    for (const Patch& patch : patches) {
      Vec3 stopped = Vec3::Zero();
      for (Eigen::Index i = patch.from; i < patch.to; i += 2) {
        const std::array<Vec3, 2> across = across_of(planes_[held_pairs_[pair_at(i)].plane].normal);
        stopped += impulse[i] * across[0] + impulse[i + 1] * across[1];  // collider coordinates
      }
      const double cone = patch.cone * dt, size = stopped.norm();
      const double cut = size > cone ? cone / size : 1.0;
      const double take = std::min(cone, std::max(patch.held, size));
      for (Eigen::Index i = patch.from; i < patch.to; i += 2) {
        const std::size_t k = pair_at(i);
        taken[k] = take * held_pairs_[k].cone / patch.cone;
        if (cut == 1.0) continue;
        slid[k] = 1;
        stick_amount_[2 * k] *= cut;
        stick_amount_[2 * k + 1] *= cut;
      }
    }
  }
  for (std::size_t k = 0; k < m; ++k) spent_[held_pairs_[k].plane] += taken[k];
  work_->ops.apply_rows(sweep, {work_->stick.data(), 2 * m}, stick_amount_, false, dt);
  for (std::size_t k = 0; k < m; ++k) {
    anchors_[held_pairs_[k].anchor].step = step_;
    if (slid[k]) anchors_[held_pairs_[k].anchor].local = here_local(held_pairs_[k]);
  }
  // Moving across the normal turns the chain: a station may have sunk into a collider. Back out.
  const double length = sweep.deformed().length();
  bool inside = false;
  for (std::size_t p = 0; p < n && !inside; ++p) {
    inside = gap(sweep, planes_[p], colliders[planes_[p].collider]) < -kGapSlack * length;
  }
  if (!inside) return;
  repush_.assign(n, 0.0);
  move_out(sweep, colliders, dt, repush_, false);
}

}  // namespace sweep::sim
