#include "sweep/core/elastic_sweep.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <mutex>

#include "sweep/core/locate.h"

namespace sweep {
namespace {

// Spring displacements (mesh units or radians) and speeds below this are set to exactly zero.
constexpr double kRestFlush = 1e-200;

OscillatorParams to_params(const SpringSettings& s) {
  return {s.mass, s.damping(), s.stiffness()};
}

const SpringSettings& pick_positional(const SectionSprings& s, int) {
  return s.positional;
}
const SpringSettings& pick_rotational(const SectionSprings& s, int c) {
  return c == 2 ? s.twist : s.bend;
}
const SpringSettings& pick_radial(const SectionSprings& s, int) {
  return s.radial;
}

bool all_finite(const std::vector<double>& a) {
  return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
}

bool same_shape(const SweepShape& a, const SweepShape& b) {
  if (a.t != b.t || a.radial_count != b.radial_count || a.radii != b.radii || a.frames.size() != b.frames.size())
    return false;
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    if (a.frames[i].rotation.coeffs() != b.frames[i].rotation.coeffs() || a.frames[i].center != b.frames[i].center)
      return false;
  }
  return true;
}

// The chain model of a part, shared by every sweep of the same rest shape and materials while one
// lives: a crowd of one creature (libsweep instances opened from one rig) then reads one set of
// modes, which stays in cache from one creature to the next, where each its own sent them all to
// memory (and each instance spent 0.2 ms building it). The model is a pure function of those
// inputs: shared, it is the same bits.
std::shared_ptr<const ChainModel> shared_chain_model(const SweepShape& rest, const std::vector<Material>& materials) {
  struct Entry {
    SweepShape rest;
    std::vector<Material> materials;
    std::weak_ptr<const ChainModel> model;
  };
  static std::mutex mutex;
  static std::vector<Entry> models;
  const auto find = [&]() -> std::shared_ptr<const ChainModel> {
    std::erase_if(models, [](const Entry& e) { return e.model.expired(); });
    for (const Entry& e : models) {
      if (e.materials == materials && same_shape(e.rest, rest)) {
        if (auto model = e.model.lock()) return model;
      }
    }
    return nullptr;
  };
  {
    const std::lock_guard lock(mutex);
    if (auto model = find()) return model;
  }
  // Built outside the lock: instances opened on several threads build theirs side by side.
  auto built = std::make_shared<const ChainModel>(build_chain_model(rest, materials));
  const std::lock_guard lock(mutex);
  if (auto model = find()) return model;
  models.push_back({rest, materials, built});
  return built;
}

}  // namespace

ElasticSweep::ElasticSweep(SweepDef def) : def_(std::move(def)) {
  const int k = def_.rest.section_count();
  assert(k >= 2 && static_cast<int>(def_.springs.size()) == k);
  relative_.assign(k, Frame{});
  for (int i = 1; i < k; ++i) relative_[i] = def_.rest.frames[i - 1].inverse() * def_.rest.frames[i];
  pre_ = def_.rest.frames;
  deformed_ = def_.rest;
  init_bank(positional_, 3, pick_positional);
  init_bank(rotational_, 3, pick_rotational);
  init_bank(radial_, def_.rest.radial_count, pick_radial);
  loads_.resize(k, def_.rest.radial_count);
  section_velocity_.assign(k, Vec3::Zero());
  shift_velocity_.assign(k, Vec3::Zero());
  locator_.reset(deformed_);  // its table sized now, not in the frame that first places a force
  if (def_.material) {
    chain_ = shared_chain_model(def_.rest, def_.section_materials);
    positional_.params = chain_->positional;
    radial_.params = chain_->radial;
    const std::size_t dim = static_cast<std::size_t>(3) * chain_->joints;
    modal_.width = 0;  // every mode moves
    for (std::vector<double>* v : {&modal_.x, &modal_.v, &modal_.f, &modal_.x0, &modal_.v0}) v->assign(dim, 0.0);
    modal_.params.resize(dim);
    for (std::size_t c = 0; c < dim; ++c) {
      const double w = std::sqrt(std::max(chain_->omega2[static_cast<Eigen::Index>(c)], 0.0));
      modal_.params[c] = {1.0, 2 * chain_->damping_ratio[c] * w, w * w};
    }
    for (auto& maps : modal_.maps) maps.resize(dim);
    moving_modes_ = static_cast<int>(dim);
    joint_scratch_.assign(dim, 0.0);
    exact_.emplace(chain_, def_.rest);
    exact_torque_.assign(dim, 0.0);
  }
}

void ElasticSweep::sync_exact() const {
  const std::size_t dim = exact_torque_.size();
  exact_->set_state(std::span<const double>(rotational_.x).subspan(3, dim),
                    std::span<const double>(rotational_.v).subspan(3, dim));
}

// One step of the exact chain from the state in rotational_: the body's motion as the chain's
// own loads (evaluated at the mid-step pose), the forces' joint torques (split by gather_loads,
// held over the step) and gravity's pre-load as the springs' shifted rest.
void ElasticSweep::step_exact(double dt) {
  const double s = chain_->metres_per_unit;
  const std::size_t dim = exact_torque_.size();
  for (std::size_t m = 0; m < dim; ++m) exact_torque_[m] = s * rotational_.f[3 + m];
  sync_exact();
  ChainDynamics::Body body;
  body.gravity = body_.gravity;
  body.acceleration = s * body_.acceleration;
  body.angular_velocity = body_.angular_velocity;
  body.angular_acceleration = body_.angular_acceleration;
  exact_->step(dt, body, exact_torque_);
  exact_->get_state(std::span<double>(rotational_.x).subspan(3, dim), std::span<double>(rotational_.v).subspan(3, dim));
  modes_due_ = true;  // the modes follow the joints when read (modes_from_joints_if_due)
}

// Rotational loads (N·mesh unit, joint axes) to modal loads Φᵀ τ (τ in N·m): the moving modes'.
void ElasticSweep::project_rotational_loads() {
  const Eigen::Index dim = static_cast<Eigen::Index>(modal_.f.size());
  const Eigen::Map<const Eigen::VectorXd> tau(rotational_.f.data() + 3, dim);
  if (truncated()) {
    const Eigen::Index m = moving_modes_;
    Eigen::Map<Eigen::VectorXd>(modal_.f.data(), m).noalias() =
        chain_->metres_per_unit * (chain_->modes.leftCols(m).transpose() * tau);
  } else {
    Eigen::Map<Eigen::VectorXd>(modal_.f.data(), dim).noalias() =
        chain_->metres_per_unit * (chain_->modes.transpose() * tau);
  }
  modal_.active = modal_.active || rotational_.active;
}

// q = Φ η and q̇ = Φ η̇. Truncated, the dropped modes sit at their static response to the loads of
// the step just taken (modal_.f, rotational_.f): q = Φ_m (η_m − Ω_m⁻² f_m) + K⁻¹ τ, their speeds 0.
void ElasticSweep::joints_from_modes() {
  const Eigen::Index dim = static_cast<Eigen::Index>(modal_.x.size());
  if (!truncated()) {
    Eigen::Map<Eigen::VectorXd>(rotational_.x.data() + 3, dim).noalias() =
        chain_->modes * Eigen::Map<const Eigen::VectorXd>(modal_.x.data(), dim);
    Eigen::Map<Eigen::VectorXd>(rotational_.v.data() + 3, dim).noalias() =
        chain_->modes * Eigen::Map<const Eigen::VectorXd>(modal_.v.data(), dim);
    return;
  }
  const Eigen::Index m = moving_modes_;
  Eigen::Map<Eigen::VectorXd> shifted(joint_scratch_.data(), m);
  shifted = Eigen::Map<const Eigen::VectorXd>(modal_.x.data(), m) -
            Eigen::Map<const Eigen::VectorXd>(modal_.f.data(), m).cwiseQuotient(chain_->omega2.head(m));
  Eigen::Map<Eigen::VectorXd> q(rotational_.x.data() + 3, dim);
  q.noalias() = chain_->metres_per_unit *
                chain_->compliance.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(rotational_.f.data() + 3, dim));
  q.noalias() += chain_->modes.leftCols(m) * shifted;
  joint_speeds_from_modes();
}

void ElasticSweep::joint_speeds_from_modes() {
  const Eigen::Index dim = static_cast<Eigen::Index>(modal_.x.size()), m = moving_modes_;
  Eigen::Map<Eigen::VectorXd>(rotational_.v.data() + 3, dim).noalias() =
      chain_->modes.leftCols(m) * Eigen::Map<const Eigen::VectorXd>(modal_.v.data(), m);
}

// η = Φᵀ M q (Φ is M-orthonormal), and the same for the speeds: of the moving modes.
void ElasticSweep::modes_from_joints() {
  modes_due_ = false;
  const Eigen::Index dim = static_cast<Eigen::Index>(modal_.x.size());
  Eigen::Map<Eigen::VectorXd> scratch(joint_scratch_.data(), dim);
  if (truncated()) {
    const Eigen::Index m = moving_modes_;
    scratch.noalias() = chain_->mass * Eigen::Map<const Eigen::VectorXd>(rotational_.x.data() + 3, dim);
    Eigen::Map<Eigen::VectorXd>(modal_.x.data(), m).noalias() = chain_->modes.leftCols(m).transpose() * scratch;
    scratch.noalias() = chain_->mass * Eigen::Map<const Eigen::VectorXd>(rotational_.v.data() + 3, dim);
    Eigen::Map<Eigen::VectorXd>(modal_.v.data(), m).noalias() = chain_->modes.leftCols(m).transpose() * scratch;
    return;
  }
  scratch.noalias() = chain_->mass * Eigen::Map<const Eigen::VectorXd>(rotational_.x.data() + 3, dim);
  Eigen::Map<Eigen::VectorXd>(modal_.x.data(), dim).noalias() = chain_->modes.transpose() * scratch;
  scratch.noalias() = chain_->mass * Eigen::Map<const Eigen::VectorXd>(rotational_.v.data() + 3, dim);
  Eigen::Map<Eigen::VectorXd>(modal_.v.data(), dim).noalias() = chain_->modes.transpose() * scratch;
}

void ElasticSweep::set_moving_modes(int count) {
  if (!chain_) return;
  const int dim = static_cast<int>(modal_.x.size());
  const int m = std::clamp(count, 1, dim);
  if (m == moving_modes_) return;
  moving_modes_ = m;
  // The modes that stop moving keep no state of their own (quasi-static from the next step on);
  // those that start moving take theirs from the joints as they stand.
  for (std::size_t c = static_cast<std::size_t>(m); c < modal_.x.size(); ++c) {
    modal_.x[c] = modal_.v[c] = modal_.f[c] = 0;
  }
  if (modal_.active || modes_due_) modes_from_joints();
}

int ElasticSweep::resolved_modes(const ChainModel& chain, double step, double bound) {
  int count = 1;
  while (count < chain.omega2.size() && std::sqrt(std::max(chain.omega2[count], 0.0)) * step <= bound) ++count;
  return count;
}

void ElasticSweep::init_bank(Bank& bank, int width, const SpringSettings& (*pick)(const SectionSprings&, int)) {
  const int k = def_.rest.section_count();
  const std::size_t size = static_cast<std::size_t>(k) * width;
  bank.width = width;
  bank.x.assign(size, 0.0);
  bank.v.assign(size, 0.0);
  bank.f.assign(size, 0.0);
  bank.x0.assign(size, 0.0);
  bank.v0.assign(size, 0.0);
  bank.params.resize(size);
  for (auto& maps : bank.maps) maps.resize(size);
  for (int i = 0; i < k; ++i) {
    for (int c = 0; c < width; ++c)
      bank.params[static_cast<std::size_t>(i) * width + c] = to_params(pick(def_.springs[i], c));
  }
}

ElasticSweep::ActiveForce ElasticSweep::placed(const ForceSpec& force, ForceId id) const {
  ActiveForce a{id, force, force.t, force.theta};
  if (force.at_world_point) {
    locator_.reset(deformed_);
    const SweepCoords c = locator_.locate(force.point);
    a.t = c.t;
    a.theta = c.theta;
  }
  a.t = std::clamp(a.t, 0.0, def_.rest.length());
  return a;
}

ForceId ElasticSweep::add_force(const ForceSpec& force) {
  forces_.push_back(placed(force, next_id_++));
  return forces_.back().id;
}

bool ElasticSweep::remove_force(ForceId id) {
  const auto it = std::find_if(forces_.begin(), forces_.end(), [&](const ActiveForce& a) { return a.id == id; });
  if (it == forces_.end()) return false;
  forces_.erase(it);
  return true;
}

void ElasticSweep::clear_forces() {
  forces_.clear();
}

bool ElasticSweep::body_loads() const {
  return (chain_ && (body_.gravity != Vec3::Zero() || body_.drag > 0)) || body_.acceleration != Vec3::Zero() ||
         body_.angular_velocity != Vec3::Zero() || body_.angular_acceleration != Vec3::Zero() ||
         !keyed_acceleration_.empty();
}

// Each section's share of the body's motion at the centres of the current shape, as a field of
// accelerations g_i (per unit mass). In material mode each joint j takes the moment of what lies
// beyond it, Σ_{i>j} (c_i − c_j) × m_i g_i, and each positional spring the force beyond it (the
// chain's mass matrix carries those masses too); with the paper's springs each section's own
// positional spring takes its own share.
void ElasticSweep::add_body_loads(const BodyMotion& motion, bool to_joints, bool keyed) {
  const int k = def_.rest.section_count();
  const double s = chain_ ? chain_->metres_per_unit : 1.0;  // mesh-unit accelerations to m/s²
  const Vec3& w = motion.angular_velocity;
  const bool wind = chain_ && motion.drag > 0;
  if (w != Vec3::Zero() || wind) {
    // Centre velocities relative to the body, from the spring speeds along the chain: joint j
    // turns everything beyond it about c_j (Ω_j) and shifts it (u_j), so
    // v_i = Σ_{j≤i} Ω_j × (c_i − c_j) + u_j = (Σ Ω_j) × c_i − Σ Ω_j × c_j + Σ u_j.
    Vec3 spin = Vec3::Zero(), spin_moment = Vec3::Zero(), shift = Vec3::Zero();
    section_velocity_[0] = Vec3::Zero();
    for (int i = 1; i < k; ++i) {
      const Quat& axes = pre_[i].rotation;
      const Vec3& c = deformed_.frames[i].center;
      const Vec3 omega = axes * Vec3(rotational_.v[3 * i], rotational_.v[3 * i + 1], rotational_.v[3 * i + 2]);
      spin += omega;
      spin_moment += omega.cross(c);
      shift += axes * Vec3(positional_.v[3 * i], positional_.v[3 * i + 1], positional_.v[3 * i + 2]);
      section_velocity_[i] = spin.cross(c) - spin_moment + shift;
      shift_velocity_[i] = shift;
    }
  }
  const Vec3 gravity = chain_ ? motion.gravity : Vec3::Zero();
  // The exact chain takes the body's motion and gravity itself, at its own pose and speeds: only
  // the positional springs (and the wind's share of the joints) are split here.
  const bool exact = !to_joints;
  // Σ F_i over i ≥ j, and Σ F_i, Σ c_i × F_i of the joints' share.
  Vec3 force = Vec3::Zero(), turning_force = Vec3::Zero(), moment = Vec3::Zero();
  for (int j = k - 1; j >= 1; --j) {
    const Vec3& c = deformed_.frames[j].center;
    Vec3 frame_acceleration = motion.acceleration + motion.angular_acceleration.cross(c);
    // (The exact chain takes the Coriolis load of the joints' speeds itself: the positional
    // springs feel that of their own speeds only.)
    if (w != Vec3::Zero())
      frame_acceleration += w.cross(w.cross(c)) + 2.0 * w.cross(to_joints ? section_velocity_[j] : shift_velocity_[j]);
    const double mass = chain_ ? chain_->node_mass[j] : def_.springs[j].positional.mass;
    Vec3 f = mass * (gravity - s * frame_acceleration);
    Vec3 turning = exact ? Vec3::Zero() : f;  // what the joints take (the exact chain: the wind alone)
    if (keyed && !keyed_acceleration_.empty()) {
      // The keyed bend's inertia: the exact chain does not know it, so its joints take it too.
      const Vec3 inertia = -mass * s * keyed_acceleration_[j];
      f += inertia;
      turning += inertia;
    }
    if (wind) {
      // The air against the section (m/s), across the part's axis: cross-flow drag on the span.
      const Vec3 air = motion.wind - s * (motion.velocity + w.cross(c) + section_velocity_[j]);
      const Vec3 axis = deformed_.frames[j].axis();
      const Vec3 across = air - air.dot(axis) * axis;
      const int n = def_.rest.radial_count;
      double radius = 0;
      for (int r = 0; r < n; ++r) radius += deformed_.radii[static_cast<std::size_t>(j) * n + r];
      const double diameter = 2 * s * radius / n;
      const Vec3 drag = motion.drag * diameter * chain_->section_length[j] * across.norm() * across;
      f += drag;
      turning += drag;
    }
    if (!chain_) {
      // The paper's springs are independent, each with its own mass and no other: a section's
      // share loads its own positional spring only. (Carried down the chain, the weight of every
      // later section would load a spring whose mass is one section's: a tenfold, violent lag.)
      loads_.force[j] += f;
      continue;
    }
    force += f;
    turning_force += turning;
    moment += c.cross(turning);
    loads_.force[j] += force;
    loads_.torque[j] += moment - c.cross(turning_force);
  }
}

void ElasticSweep::set_gravity(const Vec3& g, bool preloaded) {
  if (!chain_) return;
  body_.gravity = g;
  gravity_preload_.clear();
  exact_->set_rest_load({});
  if (!preloaded || g == Vec3::Zero()) return;
  // The loads at the rest pose, in the springs' rest axes: subtracted from every later split.
  ElasticSweep at_rest(def_);
  at_rest.dynamics_ = Dynamics::modal;  // the joints' share split too, not left to the exact chain
  at_rest.body_.gravity = g;
  at_rest.gather_loads({});
  const int k = def_.rest.section_count();
  gravity_preload_.assign(static_cast<std::size_t>(6) * k, 0.0);
  for (int m = 0; m < 3 * k; ++m) {
    gravity_preload_[m] = at_rest.positional_.f[m];
    gravity_preload_[3 * k + m] = at_rest.rotational_.f[m];
  }
  // The exact chain: the springs' rest shifted by its own gravity torques at the rest pose (N·m,
  // joints 1 .. K−1), computed as its step computes them, so that they cancel to the last bit and
  // the rest pose stays exactly still (the split above differs from them by rounding: 2e-16).
  ChainDynamics at_rest_chain(chain_, def_.rest);
  ChainDynamics::Body weight;
  weight.gravity = g;
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(exact_torque_.size()));
  Eigen::VectorXd held(still.size());
  at_rest_chain.inverse_dynamics(still, still, weight, held);
  for (std::size_t m = 0; m < exact_torque_.size(); ++m) exact_torque_[m] = -held[static_cast<Eigen::Index>(m)];
  exact_->set_rest_load(exact_torque_);
}

void ElasticSweep::set_body_motion(const BodyMotion& motion) {
  body_ = motion;
  if (!chain_) body_.gravity = Vec3::Zero();
}

void ElasticSweep::set_keyed_acceleration(std::span<const Vec3> acceleration) {
  if (acceleration.empty() ||
      std::all_of(acceleration.begin(), acceleration.end(), [](const Vec3& a) { return a == Vec3::Zero(); })) {
    keyed_acceleration_.clear();  // keeps its capacity: setting it again allocates nothing
    return;
  }
  assert(acceleration.size() == static_cast<std::size_t>(def_.rest.section_count()));
  keyed_acceleration_.assign(acceleration.begin(), acceleration.end());
}

void ElasticSweep::apply_body_kick(const Vec3& dv, const Vec3& dw) {
  if (dv == Vec3::Zero() && dw == Vec3::Zero()) return;
  loads_.clear();
  BodyMotion kick_motion;
  kick_motion.acceleration = dv;
  kick_motion.angular_acceleration = dw;
  add_body_loads(kick_motion, true, false);
  loads_to_springs(false);
  if (chain_) {
    // Material mode takes the kick by bending alone (the joints, through the chain's full mass
    // matrix). Its stretch and shear shifts each carry all the mass beyond them on a mass of their
    // own (a diagonal mass, good for loads that last): each took the whole kick, and a shift moves
    // every section past it, so section i was kicked i times — the tip of a 32-section tube went
    // at 32× the body's jump (Body.AKickLeavesThePartStillInTheWorld), the stiff springs ringing
    // with it and throwing a part's stuck tip off its floor. (So a kick's share along the axis,
    // which only the stretch springs could take, is left out: they are too stiff to show it.)
    // The positional and radial springs then take nothing (the split gives the radial ones no
    // share of a body's motion): the joints alone are kicked, without adding zeros to the others'
    // speeds.
    const int k = def_.rest.section_count();
    for (int m = 3; m < 3 * k; ++m) positional_.f[m] = 0;
    kick_joints();
    return;
  }
  kick();
}

// Splits the given forces and the body's loads on the current shape and writes each spring's
// load, in its own frame.
void ElasticSweep::gather_loads(const std::vector<ActiveForce>& forces) {
  loads_.clear();
  for (const ActiveForce& a : forces) {
    accumulate_force(deformed_, a.spec, a.t, a.theta, def_.rotational_scale, def_.radial_scale, loads_);
  }
  if (body_loads()) add_body_loads(body_, !exact_chain(), true);
  loads_to_springs(true);
}

void ElasticSweep::loads_to_springs(bool subtract_preload) {
  const int k = def_.rest.section_count();
  for (int i = 0; i < k; ++i) {
    const Quat to_local = pre_[i].rotation.conjugate();
    const Vec3 f = to_local * loads_.force[i];
    const Vec3 tau = to_local * loads_.torque[i];
    for (int c = 0; c < 3; ++c) {
      positional_.f[3 * i + c] = f[c];
      rotational_.f[3 * i + c] = tau[c];
    }
  }
  if (subtract_preload && !gravity_preload_.empty()) {
    for (int m = 3; m < 3 * k; ++m) {
      positional_.f[m] -= gravity_preload_[m];
      if (!exact_chain()) rotational_.f[m] -= gravity_preload_[3 * k + m];
    }
  }
  radial_.f = loads_.radial;
  for (Bank* b : {&positional_, &rotational_, &radial_}) {
    if (!b->active) b->active = std::any_of(b->f.begin(), b->f.end(), [](double x) { return x != 0.0; });
  }
}

void ElasticSweep::apply_impulse(const ForceSpec& impulse) {
  const ActiveForce a = placed(impulse, 0);
  // The impulse alone: the body's loads (gravity, motion) are forces over time, not part of it.
  loads_.clear();
  accumulate_force(deformed_, a.spec, a.t, a.theta, def_.rotational_scale, def_.radial_scale, loads_);
  loads_to_springs(false);
  kick();
}

void ElasticSweep::kick() {
  if (chain_) kick_joints();
  // Section 0 is fixed (advance_banks never moves it): a kick there would be a speed that never
  // decays, counted as energy and as motion forever.
  for (Bank* b : {&positional_, &rotational_, &radial_}) {
    if (chain_ && b == &rotational_) continue;
    for (std::size_t m = static_cast<std::size_t>(b->width); m < b->v.size(); ++m)
      b->v[m] += b->f[m] / b->params[m].mass;
  }
}

void ElasticSweep::kick_joints() {
  if (exact_chain()) {
    // Δw = M(q)⁻¹ τ at the current pose.
    const std::size_t dim = exact_torque_.size();
    for (std::size_t m = 0; m < dim; ++m) exact_torque_[m] = chain_->metres_per_unit * rotational_.f[3 + m];
    sync_exact();
    exact_->apply_joint_impulse(exact_torque_);
    exact_->get_state(std::span<double>(rotational_.x).subspan(3, dim),
                      std::span<double>(rotational_.v).subspan(3, dim));
    modes_due_ = true;  // (the step after it moves the joints on before anything reads the modes)
    modal_.active = rotational_.active = true;
  } else {
    // Δq̇ = M⁻¹ τ, i.e. Δη̇ = Φᵀ τ (the moving modes': a truncated sweep's joints keep their pose,
    // the dropped modes' static share of the last step's loads, and take the kept modes' speeds).
    project_rotational_loads();
    for (std::size_t m = 0; m < static_cast<std::size_t>(moving_modes_); ++m) modal_.v[m] += modal_.f[m];
    if (truncated()) {
      joint_speeds_from_modes();
    } else {
      joints_from_modes();
    }
  }
}

int ElasticSweep::map_slot(double dt) {
  ++map_clock_;
  int oldest = 0;
  for (int s = 0; s < kMapSlots; ++s) {
    if (slots_[s].used >= 0 && slots_[s].dt == dt && slots_[s].integrator == integrator_) {
      slots_[s].used = map_clock_;
      return s;
    }
    if (slots_[s].used < slots_[oldest].used) oldest = s;
  }
  for (Bank* b : {&positional_, &rotational_, &radial_, &modal_}) {
    for (std::size_t m = 0; m < b->params.size(); ++m)
      b->maps[oldest][m] = make_step_map(b->params[m], dt, integrator_);
  }
  slots_[oldest] = {dt, integrator_, map_clock_};
  return oldest;
}

void ElasticSweep::advance_banks(int slot) {
  const bool exact = exact_chain();
  if (chain_ && !exact) project_rotational_loads();
  // Section 0 is fixed: start every bank at section 1. In material mode the modes (or the exact
  // chain, stepped by the caller) move instead of the rotational springs.
  Bank* moving = chain_ ? &modal_ : &rotational_;
  for (Bank* b : {&positional_, moving, &radial_}) {
    if (!b->active || (exact && b == moving)) continue;
    const std::vector<StepMap>& maps = b->maps[slot];
    const std::size_t end = b == &modal_ ? static_cast<std::size_t>(moving_modes_) : b->x.size();
    for (std::size_t m = static_cast<std::size_t>(b->width); m < end; ++m) {
      maps[m].apply(b->x[m], b->v[m], b->f[m]);
      // A free spring decays geometrically forever; left alone it reaches subnormal numbers, which
      // x86 computes with many times slower. Far below any visible motion, rest is rest.
      if (std::abs(b->x[m]) < kRestFlush && std::abs(b->v[m]) < kRestFlush) b->x[m] = b->v[m] = 0.0;
    }
  }
  if (chain_ && !exact && modal_.active) joints_from_modes();
}

void ElasticSweep::step(double dt) {
  assert(dt > 0);
  const bool exact = exact_chain();
  gather_loads(forces_);
  if (midpoint_loads_ && (!forces_.empty() || body_loads())) {
    // Midpoint rule for follower loads: predict the pose at dt/2 with the start-of-step loads,
    // re-split the forces there, and take the whole step from the start with those loads. A load
    // that does not depend on the pose is the same at both places, so the step stays exact for it.
    // (The exact chain evaluates the body's loads at its own mid-step pose; for the forces its
    // joints are predicted at their start speeds, exp(dt/2 w) exp(φ): the load's error is O(dt²),
    // the step's O(dt³), as with the closed-form half step.)
    for (Bank* b : {&positional_, &rotational_, &radial_, &modal_}) {
      std::copy(b->x.begin(), b->x.end(), b->x0.begin());
      std::copy(b->v.begin(), b->v.end(), b->v0.begin());
    }
    advance_banks(map_slot(0.5 * dt));
    if (exact) {
      for (int i = 1; i < def_.rest.section_count(); ++i) {
        const Vec3 w(rotational_.v[3 * i], rotational_.v[3 * i + 1], rotational_.v[3 * i + 2]);
        const Vec3 phi(rotational_.x[3 * i], rotational_.x[3 * i + 1], rotational_.x[3 * i + 2]);
        const Vec3 mid = vector_from_rotation(rotation_from_vector(0.5 * dt * w) * rotation_from_vector(phi));
        for (int c = 0; c < 3; ++c) rotational_.x[3 * i + c] = mid[c];
      }
    }
    rebuild();
    gather_loads(forces_);
    for (Bank* b : {&positional_, &rotational_, &radial_, &modal_}) {
      std::copy(b->x0.begin(), b->x0.end(), b->x.begin());
      std::copy(b->v0.begin(), b->v0.end(), b->v.begin());
    }
  }
  advance_banks(map_slot(dt));
  if (exact) {
    // The body's loads move the chain whether or not they split into rotational_.f.
    if (body_loads()) rotational_.active = true;
    if (rotational_.active) step_exact(dt);
  }
  rebuild();
}

void ElasticSweep::copy_state_from(const ElasticSweep& other) {
  assert(other.def_.rest.section_count() == def_.rest.section_count());
  const Bank* from[] = {&other.positional_, &other.rotational_, &other.radial_, &other.modal_};
  Bank* to[] = {&positional_, &rotational_, &radial_, &modal_};
  for (int k = 0; k < 4; ++k) {
    std::copy(from[k]->x.begin(), from[k]->x.end(), to[k]->x.begin());
    std::copy(from[k]->v.begin(), from[k]->v.end(), to[k]->v.begin());
    to[k]->active = from[k]->active;
  }
  std::copy(other.deformed_.frames.begin(), other.deformed_.frames.end(), deformed_.frames.begin());
  std::copy(other.deformed_.radii.begin(), other.deformed_.radii.end(), deformed_.radii.begin());
  std::copy(other.pre_.begin(), other.pre_.end(), pre_.begin());
  forces_ = other.forces_;  // reuses its capacity: allocates only when the force count grows
  next_id_ = other.next_id_;
  integrator_ = other.integrator_;
  dynamics_ = other.dynamics_;
  switched_ = other.switched_;
  modes_due_ = other.modes_due_;
  midpoint_loads_ = other.midpoint_loads_;
  moving_modes_ = other.moving_modes_;
  body_ = other.body_;
  keyed_acceleration_ = other.keyed_acceleration_;  // reuses its capacity
}

void ElasticSweep::rebuild() {
  const int k = def_.rest.section_count();
  const int n = def_.rest.radial_count;
  for (int i = 1; i < k; ++i) {
    pre_[i] = deformed_.frames[i - 1] * relative_[i];
    const Vec3 x(positional_.x[3 * i], positional_.x[3 * i + 1], positional_.x[3 * i + 2]);
    const Vec3 phi(rotational_.x[3 * i], rotational_.x[3 * i + 1], rotational_.x[3 * i + 2]);
    deformed_.frames[i] = pre_[i] * Frame{rotation_from_vector(phi), x};
    for (int j = 0; j < n; ++j) {
      const std::size_t m = static_cast<std::size_t>(i) * n + j;
      const double r = def_.rest.radii[m];
      deformed_.radii[m] = std::max(r + radial_.x[m], kMinRadiusFraction * r);
    }
  }
}

Vec3 ElasticSweep::section_offset(int i) const {
  return {positional_.x[3 * i], positional_.x[3 * i + 1], positional_.x[3 * i + 2]};
}
Vec3 ElasticSweep::rotation_vector(int i) const {
  return {rotational_.x[3 * i], rotational_.x[3 * i + 1], rotational_.x[3 * i + 2]};
}
double ElasticSweep::radial_offset(int i, int j) const {
  return radial_.x[static_cast<std::size_t>(i) * def_.rest.radial_count + j];
}

void ElasticSweep::set_section_pose(int i, const Vec3& offset, const Vec3& rotation_vector) {
  assert(i >= 1 && i < def_.rest.section_count());
  for (int c = 0; c < 3; ++c) {
    positional_.x[3 * i + c] = offset[c];
    rotational_.x[3 * i + c] = rotation_vector[c];
  }
  positional_.active = positional_.active || offset != Vec3::Zero();
  rotational_.active = rotational_.active || rotation_vector != Vec3::Zero();
  if (chain_) {
    modes_from_joints();
    modal_.active = modal_.active || rotational_.active;
  }
  rebuild();
}

void ElasticSweep::set_radial_offset(int i, int j, double delta) {
  assert(i >= 1 && i < def_.rest.section_count());
  radial_.x[static_cast<std::size_t>(i) * def_.rest.radial_count + j] = delta;
  radial_.active = radial_.active || delta != 0.0;
  rebuild();
}

void ElasticSweep::reset() {
  for (Bank* b : {&positional_, &rotational_, &radial_, &modal_}) {
    std::fill(b->x.begin(), b->x.end(), 0.0);
    std::fill(b->v.begin(), b->v.end(), 0.0);
  }
  switched_ = false;   // at rest and still: small motion again
  modes_due_ = false;  // the modes were zeroed with the joints
  rebuild();
}

bool ElasticSweep::switch_if_large() {
  // With an explicit integrator the joints move by the modes whatever the dynamics (exact_chain()).
  if (!chain_ || dynamics_ != Dynamics::automatic || integrator_ != Integrator::exact || switched_ ||
      !rotational_.active)
    return false;
  // |vec(q)| = sin(θ/2) of the rotation q between a section's rest and current axes: compared
  // squared, no trigonometry in a step that does not switch.
  const double limit = std::sin(0.5 * kSwitchAngle);
  const double limit2 = limit * limit;
  for (int i = 1; i < def_.rest.section_count(); ++i) {
    const Quat turn = def_.rest.frames[i].rotation.conjugate() * deformed_.frames[i].rotation;
    if (turn.vec().squaredNorm() > limit2) {
      switched_ = true;
      return true;
    }
  }
  return false;
}

double ElasticSweep::largest_rotation() const {
  double largest = 0;
  for (int i = 1; i < def_.rest.section_count(); ++i)
    largest = std::max(largest, def_.rest.frames[i].rotation.angularDistance(deformed_.frames[i].rotation));
  return largest;
}

double ElasticSweep::energy() const {
  double e = 0;
  if (exact_chain()) {
    // The exact chain's kinetic energy at its pose and the springs' ½ φᵀ K φ (pre-load not counted).
    sync_exact();
    e += exact_->kinetic_energy();
    for (int i = 1; i <= chain_->joints; ++i) {
      const Vec3 p = rotation_vector(i);
      e += 0.5 * p.dot(chain_->stiffness.block<3, 3>(3 * (i - 1), 3 * (i - 1)).diagonal().cwiseProduct(p));
    }
  }
  // In material mode the modes carry the rotational energy (½ η̇² + ½ ω² η², J); the positional
  // and radial springs are in mesh units (N/unit, kg·m/unit), their energy in N·unit: × metres per
  // unit makes it joules too, so that the sum means one thing.
  if (chain_ && !exact_chain() && truncated()) {
    // The kept modes' kinetic energy and the joints' ½ qᵀ K q: Φ is K-orthogonal, so that is the
    // kept modes' ½ ω² η² and the dropped modes' static ½ f²/ω² (their kinetic energy is none).
    for (int m = 0; m < moving_modes_; ++m) e += 0.5 * modal_.v[m] * modal_.v[m];
    for (int i = 1; i <= chain_->joints; ++i) {
      const Vec3 p = rotation_vector(i);
      e += 0.5 * p.dot(chain_->stiffness.block<3, 3>(3 * (i - 1), 3 * (i - 1)).diagonal().cwiseProduct(p));
    }
  }
  for (const Bank* b : {&positional_, chain_ ? &modal_ : &rotational_, &radial_}) {
    if ((exact_chain() || truncated()) && b == &modal_) continue;
    double bank = 0;
    for (std::size_t m = 0; m < b->x.size(); ++m) bank += oscillator_energy(b->params[m], b->x[m], b->v[m]);
    e += bank * energy_unit(*b);
  }
  return e;
}

double ElasticSweep::energy_unit(const Bank& bank) const {
  return chain_ && &bank != &modal_ ? chain_->metres_per_unit : 1.0;
}

double ElasticSweep::max_speed() const {
  double s = 0;
  for (const Bank* b : {&positional_, &rotational_, &radial_}) {
    for (double v : b->v) s = std::max(s, std::abs(v));
  }
  return s;
}

double ElasticSweep::max_displacement() const {
  double d = 0;
  for (const Bank* b : {&positional_, &rotational_, &radial_}) {
    for (double x : b->x) d = std::max(d, std::abs(x));
  }
  return d;
}

bool ElasticSweep::is_finite() const {
  for (const Bank* b : {&positional_, &rotational_, &radial_, &modal_}) {
    if (!all_finite(b->x) || !all_finite(b->v)) return false;
  }
  return true;
}

}  // namespace sweep
