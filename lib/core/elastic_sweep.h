#pragma once
// The runtime: one elastic sweep (the paper's §II–III). Load a SweepDef, add or remove forces,
// step(dt), read the deformed key frames and radii. No file or console I/O.
//
// Kinematics: the deformed frame of section i is M'_i = M'_{i-1} · T_{i-1,i} · D_i with
// D_i = [exp(φ_i) | x_i] acting in A_i = M'_{i-1}·T_{i-1,i}, i.e. about the section's own centre and in
// its own axes. Section 0 is the root, fixed to the body: it never moves. Springs are independent
// damped oscillators: 3 positional (x_i), 3 rotational (φ_i: bend about local x and y, twist about
// local z) and n radial (δ_i[j]: the deformed radius is r_i[j] + δ_i[j], floored at
// kMinRadiusFraction·r_i[j] so a handle can never invert its section).
#include <array>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "sweep/core/chain_dynamics.h"
#include "sweep/core/chain_model.h"
#include "sweep/core/force.h"
#include "sweep/core/locate.h"
#include "sweep/core/oscillator.h"
#include "sweep/core/rig.h"

namespace sweep {

using ForceId = int;

class ElasticSweep {
 public:
  explicit ElasticSweep(SweepDef def);

  const SweepDef& definition() const { return def_; }
  const SweepShape& rest() const { return def_.rest; }
  const SweepShape& deformed() const { return deformed_; }  // current frames and radii

  // Forces act from now until removed; each is re-split every step at its point on the current
  // surface. A force given at a world point is projected to the current surface here, once.
  ForceId add_force(const ForceSpec& force);
  bool remove_force(ForceId id);
  void clear_forces();
  std::size_t force_count() const { return forces_.size(); }
  // Room for `count` forces at once: add_force and copy_state_from then allocate nothing up to it.
  void reserve_forces(std::size_t count) { forces_.reserve(count); }

  // An impulse (N·s): the same split as a force, applied at once as a change of velocity.
  void apply_impulse(const ForceSpec& impulse);

  void set_integrator(Integrator integrator) {
    modes_from_joints_if_due();  // the modes may take over the joints
    integrator_ = integrator;
  }
  Integrator integrator() const { return integrator_; }

  // Advances the springs by dt seconds (any dt > 0: the oscillators are stepped in closed form).
  // Loads that follow the moving surface are evaluated at the predicted mid-step pose (a half step
  // with the start-of-step loads), so the step is second order in dt for them and exact for loads
  // that do not depend on the pose.
  void step(double dt);
  // Off: step() takes the start-of-step loads over the whole step instead (no predictor: half the
  // step's work, its loads' pose error O(dt) rather than O(dt²); loads that do not depend on the
  // pose are unchanged). libsweep offers it (sweep_set_predictor); on by default, as every bake runs.
  void set_midpoint_loads(bool on) { midpoint_loads_ = on; }

  // Material mode, the modes' dynamics: how many of the lowest modes move (all, the default). The
  // others are taken quasi-statically, the mode-acceleration method: q = Φ_m η_m + (K⁻¹ −
  // Φ_m Ω_m⁻² Φ_mᵀ) τ for the step's joint loads τ, K diagonal. A settled part's shape is the full
  // modes' to rounding (q = K⁻¹ τ either way); what goes is the dropped modes' own motion, their
  // ringing after a change of load and their share of an impulse (a kick moves the kept modes
  // alone). A step then reads m columns of Φ instead of all of them: O(n·m) work and data where it
  // was O(n²). All the modes: the same bits as ever. Not for a part under contact (the contact
  // rows move every mode: the simulator keeps them all in a scene with colliders). Clamped to
  // [1, 3·joints]; no-op in the paper's mode.
  void set_moving_modes(int count);
  int moving_modes() const { return moving_modes_; }
  // How many of the chain's modes have ω·step ≤ bound (at least one): those a step resolves.
  static int resolved_modes(const ChainModel& chain, double step, double bound);
  // The bound of the modes a step resolves: ω·step = 2π, a whole period a step (60 Hz at 1/60 s).
  // Faster modes ring through more than a period between two steps: what the steps show of them
  // is their static share and an alias. On the diplodocus at 1/60 s that keeps 25 of the tail's 45
  // modes and 33 of the neck's (K = 16), 21 and 27 of 93 at K = 32: the saving grows with the
  // sections, whose added modes are the fast ones. Measured on the walking, hit diplodocus
  // (sweep-bench-live): its vertices' largest error against a fine step is the full modes' to 0.5%
  // (1.67e-4 of the length against 1.66e-4); at the Nyquist bound, π (13 and 17 modes), the
  // dropped 30–60 Hz modes' ringing after a jump of the body's velocity (the walk's start, a push's
  // onset) made it 6.4e-4, four times the step's own.
  static constexpr double kResolvedModeBound = 2 * std::numbers::pi;

  // Copies the motion (spring states, forces, deformed shape) of `other`, a sweep built from the
  // same definition, without allocating once sized: how a simulator peeks ahead to an output time
  // and comes back (sim::Simulator).
  void copy_state_from(const ElasticSweep& other);

  // Spring coordinates of section i (section 0 is always zero), settable for scripted poses.
  Vec3 section_offset(int i) const;
  Vec3 rotation_vector(int i) const;
  double radial_offset(int i, int j) const;
  void set_section_pose(int i, const Vec3& offset, const Vec3& rotation_vector);
  void set_radial_offset(int i, int j, double delta);
  void reset();  // back to rest, at rest, forces kept

  // Σ ½ m v² + ½ k x² over every spring (force potential not counted); joules in material mode.
  double energy() const;
  double max_speed() const;         // largest |v| over every spring coordinate
  double max_displacement() const;  // largest |x| over every spring coordinate
  bool is_finite() const;           // false once any state is NaN or Inf (a diverged integrator)

  // Gravity (m/s², world axes; material mode only — the paper's springs have no physical mass):
  // every section's weight loads the chain. Pre-loaded (the default): the rest pose is the pose
  // under this gravity, so only a change of the load moves the part; otherwise the part starts
  // unloaded and sags.
  void set_gravity(const Vec3& g, bool preloaded = true);

  // The body's motion as the part feels it, in the body's axes (the mesh's, which the
  // sweep lives in): the acceleration of the body's origin (mesh units/s²), its angular velocity
  // (rad/s) and angular acceleration (rad/s²), and gravity (m/s², in the body's axes: it turns
  // with the body; material mode only). Held until set again. Each section of mass m at centre c
  // moving at v relative to the body takes −m (a + α × c + ω × (ω × c) + 2 ω × v) + m g. In
  // material mode that loads the chain as weight does (the positional and joint springs carry what
  // lies beyond them; lengths in metres); with the paper's independent springs each section's own
  // positional spring takes its share, with that spring's mass (lengths in mesh units): the
  // offsets add up along the chain, so the tip lags most. A body at rest or moving at constant
  // velocity loads nothing.
  // Wind (material mode only, like gravity): each span of the part, a cylinder of its section's
  // mean diameter and the length the section stands for, takes the cross-flow drag
  // ½ ρ C_d · d h · |u⊥| u⊥, u⊥ the air's speed relative to the section across the part's axis
  // (the body's own velocity and the section's motion included).
  struct BodyMotion {
    Vec3 acceleration = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();
    Vec3 angular_acceleration = Vec3::Zero();
    Vec3 gravity = Vec3::Zero();
    Vec3 velocity = Vec3::Zero();  // of the body's origin, body axes, mesh units/s (for the wind)
    Vec3 wind = Vec3::Zero();      // the air's velocity, body axes, m/s
    double drag = 0;               // ½ ρ_air C_d, kg/m³; 0: no wind
  };
  void set_body_motion(const BodyMotion& motion);
  const BodyMotion& body_motion() const { return body_; }
  // The keyed pose's own motion relative to the body (a skinned part's bend keyed by the joints
  // below its root, sim/keyed_bend.h): each section's acceleration (mesh units/s², body axes; one
  // per section, section 0's unused), held until set again; empty: none. A section takes −m a
  // from it as from the body's acceleration at its centre, so its deviation from the keyed pose
  // obeys m q'' + c q' + k q = −m a (material mode: through the joints, as weight; the exact
  // chain takes it as it takes the wind, an applied load).
  void set_keyed_acceleration(std::span<const Vec3> acceleration);
  // An instant change of the body's velocity (Δv of its origin, Δω; body axes): each section
  // takes the impulse −m (Δv + Δω × c), as at the corner of a linear keyframed path (material
  // mode: through its joints alone, which leaves the part all but still in the world across its
  // axis; a kick along the axis, which the joints cannot take, is left out).
  void apply_body_kick(const Vec3& dv, const Vec3& dw);

  // Material mode (SweepDef::material): the coupled chain and its modes; null in the paper's mode.
  // Shared (read-only) by every sweep of the same rest shape and materials while one lives.
  const ChainModel* chain() const { return chain_.get(); }
  // How a material part's joints move. modal: the rest-pose modes stepped in closed form, right
  // for small motion only (the mass matrix and velocity terms are the rest pose's: a soft part
  // that turns far gains energy, leaves its plane or runs away). exact: the geometrically exact
  // chain (core/chain_dynamics.h). automatic: the modes while the motion is small, the exact chain
  // from the internal step at whose end switch_if_large() finds a section turned farther than
  // kSwitchAngle from its rest pose (one way: back to the modes only on reset()).
  enum class Dynamics { modal, exact, automatic };
  // The largest rotation of a section against its rest pose, in the root's axes, that the
  // automatic dynamics leave to the rest-pose modes (radians, 11.5°). Measured on the soft 3.1 m
  // tube swinging freely in its first mode (tests/core/auto_chain_test.cpp): over one period the
  // modes' sections stray from the exact chain's by 3e-5 of the length at 0.1 rad, 3e-4 at this
  // amplitude, 1e-3 at 0.3 rad (as the amplitude cubed). A walking creature's tail and neck turn
  // 5–9° (the rigged diplodocus walk) and stay on the modes, at a modal step's cost; a part that
  // swings or droops farther switches while the modes are still within 3e-4 of the length a period,
  // and a soft part released level switches before it has gained energy it was not given
  // (tests/sim/large_rotation_test.cpp).
  static constexpr double kSwitchAngle = 0.2;

  // Whether the joints move by the geometrically exact chain now: material mode with the exact
  // integrator, and the exact dynamics or the automatic ones once switched. Its inertia, velocity
  // terms and gravity are those of the current pose, so a part that turns far keeps the energy it
  // was given; the contact solver's couplings, kicks and moves are taken from its current pose too
  // (core/contact_rows.cpp), and a step its Newton iteration does not settle is halved down to
  // 2⁻¹⁶ of it. Undamped, its energy is kept only to the step's second-order error, not exactly as
  // the modes' closed form keeps it (a limp rope, 1e4 Pa, whipping undamped at 1/24 s gained a
  // third of m g L), so tests of "never gains" read it to that error; and its step costs several
  // modal steps. With an explicit integrator the joints move as the rest-pose modes, stepped by it
  // (the integrators' comparison).
  bool exact_chain() const {
    return exact_.has_value() && integrator_ == Integrator::exact &&
           (dynamics_ == Dynamics::exact || (dynamics_ == Dynamics::automatic && switched_));
  }
  void set_dynamics(Dynamics dynamics) {
    modes_from_joints_if_due();  // the modes may take over the joints
    dynamics_ = dynamics;
  }
  Dynamics dynamics() const { return dynamics_; }
  // On: the exact chain; off (a sweep's default): the rest-pose modes.
  void set_exact_chain(bool on) { set_dynamics(on ? Dynamics::exact : Dynamics::modal); }
  // The automatic dynamics' check, made by whoever steps the sweep at the end of an internal step
  // (the simulator on its internal clock, never on a partial step to a frame's time: the switch
  // then falls at the same time whatever the frame rate). True when it switched now: the joints'
  // φ and w, which the modes keep in step with them, carry over as they stand. No-op otherwise.
  bool switch_if_large();
  // The largest rotation of a section against its rest pose, in the root's axes (radians).
  double largest_rotation() const;
  // Whether the automatic dynamics have switched to the exact chain (cleared by reset()).
  bool switched() const { return switched_; }
  // The exact chain at the current state (null in the paper's mode): its pose, energies, mass matrix.
  const ChainDynamics* exact_chain_state() const {
    if (!exact_) return nullptr;
    sync_exact();
    return &*exact_;
  }

  // Which spring kinds have ever been driven (a kind never driven is not stepped).
  bool positional_active() const { return positional_.active; }
  bool rotational_active() const { return rotational_.active; }
  bool radial_active() const { return radial_.active; }

 private:
  // The contact solver moves and kicks the springs through contact rows (core/contact_rows_detail.h,
  // not installed: no game calls it).
  friend class ContactRows;
  // All oscillators of one kind, flat: coordinate c of section i at index i·width + c.
  // A few step maps stay cached, keyed by (dt, integrator): a simulator alternates its internal
  // step, half of it (the mid-step predictor) and the odd partial step to a switching time.
  static constexpr int kMapSlots = 4;
  struct Bank {
    int width = 0;
    std::vector<double> x, v, f;
    std::vector<double> x0, v0;  // start-of-step state while the predictor runs
    std::vector<OscillatorParams> params;
    std::array<std::vector<StepMap>, kMapSlots> maps;
    bool active = false;
  };
  struct MapSlot {
    double dt = 0;
    Integrator integrator = Integrator::exact;
    long long used = -1;  // last use, for least-recently-used replacement
  };
  struct ActiveForce {
    ForceId id;
    ForceSpec spec;
    double t, theta;
  };
  // Where a force or an impulse acts: its world point located on the current shape (or its own
  // t, θ), t clamped to [0, L] — one rule for add_force and apply_impulse.
  ActiveForce placed(const ForceSpec& force, ForceId id) const;

  void init_bank(Bank& bank, int width, const SpringSettings& (*pick)(const SectionSprings&, int));
  void gather_loads(const std::vector<ActiveForce>& forces);
  int map_slot(double dt);       // the cached maps for dt, computed if missing
  void advance_banks(int slot);  // every active oscillator, loads held
  void rebuild();
  // Material mode: rotational loads to modal loads, and modal state back to joint coordinates.
  void project_rotational_loads();
  void joints_from_modes();
  void joint_speeds_from_modes();  // q̇ alone, from the moving modes (a truncated sweep's kick)
  void modes_from_joints();
  // The exact chain moves the joints and reads nothing of the modes (the contacts' rows take its
  // joints too): after its steps and kicks the modes are brought to the joints only when something
  // reads them — the modes' own dynamics taking over (set_dynamics, set_integrator), a change of
  // the moving modes, the contact rows. A live frame's kick and step then never touch the modes
  // (two dense products with the chain's mass matrix and modes each, data of their own).
  void modes_from_joints_if_due() {
    if (modes_due_) modes_from_joints();
  }
  bool truncated() const { return moving_modes_ < static_cast<int>(modal_.x.size()); }

  SweepDef def_;
  SweepShape deformed_;
  std::vector<Frame> relative_;  // T_{i-1,i} (entry 0: identity)
  std::vector<Frame> pre_;       // A_i, the frame D_i acts in
  Bank positional_, rotational_, radial_;
  // Material mode: the rotational coordinates move as modes. modal_ holds η, η̇ and the modal
  // loads; rotational_ keeps q = Φ η and q̇ = Φ η̇ (what rebuild, sleep and the user read).
  std::shared_ptr<const ChainModel> chain_;  // shared: built once per rig, copies of a sweep share it
  Bank modal_;
  int moving_modes_ = 0;  // the lowest modes that move (material mode; the others quasi-static)
  std::vector<double> joint_scratch_;
  double energy_unit(const Bank& bank) const;  // what turns a bank's ½ m v² + ½ k x² into energy()'s
  // The exact chain: the joints' state lives in rotational_ (φ and the relative angular velocity
  // w in A_i's axes) and is loaded into it for each step, kick or energy read (allocation-free).
  mutable std::optional<ChainDynamics> exact_;
  Dynamics dynamics_ = Dynamics::modal;
  bool switched_ = false;   // the automatic dynamics have turned to the exact chain
  bool modes_due_ = false;  // the exact chain moved the joints since the modes last followed them
  bool midpoint_loads_ = true;
  std::vector<double> exact_torque_;  // scratch: the forces' joint torques in N·m
  void step_exact(double dt);
  void sync_exact() const;  // exact_'s state from rotational_
  BodyMotion body_;
  std::vector<double> gravity_preload_;   // rest-pose gravity loads in spring axes (3K pos, 3K rot)
  std::vector<Vec3> section_velocity_;    // scratch: each centre's velocity relative to the body
  std::vector<Vec3> shift_velocity_;      // scratch: its share from the positional springs
  std::vector<Vec3> keyed_acceleration_;  // per section; empty: no keyed bend
  bool body_loads() const;                // whether body_ or the keyed bend loads anything
  // to_joints false: the positional springs' and the wind's shares alone (the exact chain takes the
  // rest itself). `keyed`: the keyed bend's loads too (a kick has none).
  void add_body_loads(const BodyMotion& motion, bool to_joints, bool keyed);
  void loads_to_springs(bool subtract_preload);  // loads_ into each bank's f, in spring axes
  void kick();                                   // loads in the banks' f as impulses (N·s)
  void kick_joints();                            // material mode: kick()'s share, the joints'
  SectionLoads loads_;
  std::vector<ActiveForce> forces_;
  // Scratch of placed(): the locator of a force or impulse given at a world point, reset on the
  // current shape each time it is needed (its table's storage reused: a frame that plays one does
  // not allocate).
  mutable SweepLocator locator_;
  ForceId next_id_ = 1;
  Integrator integrator_ = Integrator::exact;
  std::array<MapSlot, kMapSlots> slots_{};
  long long map_clock_ = 0;
};

}  // namespace sweep
