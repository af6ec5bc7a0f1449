#pragma once
// Runs a scene on a rig: one ElasticSweep per sweep, stepped on a clock of its own — internal
// times n·h with h = Scene::step_seconds(), whatever the output frame rate. An output frame that
// falls between two internal times is reached by one exact partial step on a copy (the view), and
// the next frame continues from the internal time, so the frame rate never changes the motion. Each
// scene force is switched on and off exactly at its times: a step that contains a switching time
// is split there. Skips what the scene does not need:
//  - a sweep that no force in the scene reaches is never stepped (it is not "driven");
//  - spring kinds no force drives are not stepped (ElasticSweep);
//  - a sweep whose motion has died out sleeps — it is not stepped, and its shape does not change,
//    so nothing needs deforming — until one of its forces starts again (the Jolt way: a timer
//    reset whenever motion leaves a small tolerance, an explicit wake).
// Divergence (non-finite or runaway springs, possible with the explicit integrators) throws
// Error(diverged) naming the sweep, the time and the integrator; the simulator is then left
// mid-frame and must not be advanced again.
//
// Sweeps never interact, so a frame steps them side by side on the threads (OpenMP) when more
// than one has work; results do not depend on the thread count.
#include <exception>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sweep/core/elastic_sweep.h"
#include "sweep/core/held_rest.h"
#include "sweep/core/rig.h"
#include "sweep/sim/contact.h"
#include "sweep/sim/scene.h"

namespace sweep::sim {

struct SleepSettings {
  double speed = 1e-5;         // largest spring speed allowed for sleep (mesh units/s or rad/s)
  double displacement = 1e-5;  // largest spring displacement allowed (mesh units or rad)
  double quiet_time = 0.25;    // s the sweep must stay under both before it sleeps
  bool enabled = true;
};

// A part resting on a collider sleeps once no section has moved by more than this share of the
// part's length for SleepSettings::quiet_time (a thousandth of a percent: invisible; its resting
// contacts keep it trembling by about a tenth of that).
inline constexpr double kHeldDrift = 1e-5;

// A spring displacement this many times the sweep's length (or 1, if larger) means the simulation
// has run away: no elastic part bends that far.
inline constexpr double kRunawayFactor = 1e6;

class Simulator {
 public:
  Simulator(const Rig& rig, const Scene& scene, SleepSettings sleep = {});

  // Advances to the next output frame time, frame/fps. Frame 0 is the rest pose at time 0.
  void advance_frame();
  // Advances to time t ≥ time() on the same internal clock: internal steps of Scene::step_seconds()
  // up to the last one before t, then one exact partial step to t on the view. Where t falls
  // changes nothing but what is shown: advancing in any slices to the same time gives the same
  // pose (to the rounding of the times). Counts as a frame (frame() is the advances made).
  void advance_to(double t);
  int frame() const { return frame_; }
  double time() const { return time_; }

  // Live input, for a game's loop (each applies from the current time on):
  //  - the body's pose at the end of the next advance_to (world = rotation · mesh + translation).
  //    The body moves from its pose now to it as a linear piece of a body path: translation
  //    straight and rotation by slerp across the advance, at constant velocity, the change of
  //    velocity from the last advance's piece a kick at its start (BodyPath, linear). A pose
  //    given before the first advance is also where the body starts, at rest. The path kept is
  //    what the internal clock still needs (a few keys). It replaces the scene's body path from
  //    now on; without a new pose the body holds the last one.
  //  - a force: a scene force (sweep_index, spec, start and end in s, start ≥ time()), played
  //    exactly as one read from the scene. Forces that are over are dropped as new ones come.
  //  - gravity (world axes, m/s²): material-mode parts feel its change from the next step on.
  //  - wind (sim/wind.h): the same, its gusts and turbulence timed on the simulator's clock.
  void set_body_pose(const Quat& rotation, const Vec3& translation);
  void add_force(const SceneForce& force);
  void set_gravity(const Vec3& gravity);
  void set_wind(const WindSettings& wind);
  const Scene& scene() const { return scene_; }
  // Whether a frame steps its sweeps side by side on OpenMP's threads (the default) or all on the
  // calling thread; the results are the same bits either way.
  void set_parallel(bool on) { parallel_ = on; }
  // Whether the sweeps' steps evaluate pose-dependent loads at the predicted mid-step pose (the
  // default, as every bake runs) or take the start-of-step loads (ElasticSweep::set_midpoint_loads).
  void set_midpoint_loads(bool on);
  // Material parts: whether only the modes the internal step resolves move, ω·step ≤
  // ElasticSweep::kResolvedModeBound, the others taken quasi-statically
  // (ElasticSweep::set_moving_modes: the same settled shapes, a step's work and data a fraction),
  // or all of them (the default, as every bake runs). A scene with colliders keeps them all.
  void set_resolved_modes_only(bool on);

  int sweep_count() const { return static_cast<int>(sweeps_.size()); }
  // Sweep i at the current frame's time.
  const ElasticSweep& sweep(int i) const { return sweeps_[i].show_view ? sweeps_[i].view : sweeps_[i].body; }
  bool is_driven(int i) const { return sweeps_[i].driven; }
  bool is_awake(int i) const { return sweeps_[i].awake; }
  // Whether sweep i's shape changed during the last advance_frame (it must be re-deformed).
  bool moved_last_frame(int i) const { return sweeps_[i].moved; }
  long long steps_taken(int i) const { return sweeps_[i].steps; }
  // When sweep i's automatic dynamics (Scene::dynamics) first turned to the exact chain: the end
  // of the internal step at which a section had turned past ElasticSweep::kSwitchAngle (s, on the
  // simulator's clock; < 0: never) and the largest rotation of a section against its rest pose
  // there (rad). A teleport puts the part to rest on the modes again; this keeps the first switch.
  struct ChainSwitch {
    double time = -1;
    double angle = 0;
  };
  const ChainSwitch& chain_switch(int i) const { return sweeps_[i].chain_switch; }
  // A material part under gravity: whether its as-modelled rest holds (core/held_rest.h; empty when
  // the scene starts it unloaded or has no gravity, and for the paper's springs), and whether it
  // started from that rest (Scene::gravity_start: automatic starts it there where it holds).
  const std::optional<HeldRest>& held_rest(int i) const { return sweeps_[i].held; }
  bool starts_as_modelled(int i) const { return sweeps_[i].preloaded; }
  // The body at the current frame's time (world = rotation · mesh + translation).
  BodyState body() const { return scene_.body.at(time()); }
  // Frames (their numbers) at which the body jumped and the parts were put to rest.
  const std::vector<int>& teleports() const { return teleports_; }
  // One message per world collider a teleport carried a part through unmet (a teleport meets the
  // world's colliders only where they stand after it), naming the collider, the part and the
  // frame: a body keyed to move that fast is taken as a cut, not as motion. And one per part and
  // frame in which the body moved so fast that a step near a collider was cut into fewer pieces
  // than it needed.
  const std::vector<std::string>& skipped_colliders() const { return skipped_; }

 private:
  struct SweepState {
    ElasticSweep body;  // at the internal time grid·h
    ElasticSweep view;  // body advanced to the frame time, when that falls between internal times
    bool show_view = false;
    bool driven = false;
    bool awake = false;
    bool moved = false;
    bool windy = false;  // a material part in a wind: always loaded, never asleep
    double quiet = 0;    // s spent under the sleep tolerances
    long long steps = 0;
    long long grid = 0;                      // internal steps done
    std::vector<std::size_t> forces{};       // indices of the scene forces acting on it, in scene order
    std::vector<ForceId> ids{}, view_ids{};  // per entry of `forces`: its id in body / view, 0 = off
    std::exception_ptr failure{};            // divergence during the current frame, at failure_step
    long long failure_step = 0;
    ContactSolver contact;                     // its contacts with the scene's colliders
    ContactSolver::AnchorMemo anchors;         // contact's stick anchors across the view's partial step
    std::vector<PlacedCollider> placed{};      // scratch: the colliders in mesh coordinates at one time
    std::vector<PlacedCollider> placed_end{};  // scratch: the same at a step's end
    bool touched = false;                      // touched a collider during the current internal step
    double too_fast = 0;                       // this frame: the most pieces a step needed past the cap
    std::vector<Vec3> held_at{};               // its section centres when it last moved, while it touches
    int keyed = -1;                            // its keyed bend, in scene_.keyed_bends (−1: none)
    std::vector<Vec3> keyed_now{};             // scratch: the keyed bend's accelerations at one time
    ChainSwitch chain_switch{};                // its first switch to the exact chain
    std::optional<HeldRest> held{};            // whether its as-modelled rest holds, at held_gravity
    Vec3 held_gravity = Vec3::Zero();          // body axes
    bool preloaded = false;                    // started from its as-modelled rest under gravity
  };
  // Gravity (body axes) on sweep s at the start: pre-loaded or not as the scene's gravity_start
  // says, automatic deciding by the as-modelled rest's check. Returns whether it starts unloaded.
  bool start_under_gravity(SweepState& s, const Vec3& gravity);
  // The time the colliders are placed at for time t: inside a teleport, its end (the parts are
  // put to rest in the new place).
  double collider_time(double t, bool teleporting) const;
  // The scene's colliders in mesh coordinates at time t (world ones moved by the body's inverse).
  void place_colliders(double t, std::vector<PlacedCollider>& out) const;

  // Advances sweep i (its body, or its view) over [from, to], split at switching times; a step
  // of the internal clock when `grid_step` (sleep is decided there, and only there).
  void advance_span(int i, bool on_view, double from, double to, bool grid_step);
  // Its stages, for one piece [cur, next) of the span:
  // the piece's end: the next switching time (a force's start or end, a corner of the body's path);
  double piece_end(const SweepState& s, double cur, double to) const;
  // a corner of the body's path at the piece's start kicks the part (true: it did);
  bool apply_kicks(ElasticSweep& body, double cur, double next, bool teleporting) const;
  // impulses at the piece's start, forces switched on or off over it (true: one woke the part);
  bool switch_forces(const SweepState& s, ElasticSweep& body, std::vector<ForceId>& ids, double cur, double next) const;
  // the piece stepped (`length` long), cut where colliders are within reach, its contacts resolved:
  //   into how many pieces the colliders cut it (s.placed at cur and s.placed_end at next when
  //   they were placed to decide; s.too_fast raised past the cap);
  struct ContactCut {
    int pieces = 1;
    bool placed_at_ends = false;
  };
  ContactCut cut_for_contacts(SweepState& s, const ElasticSweep& body, double cur, double next, double length,
                              bool teleporting);
  //   then each piece stepped and its contacts resolved;
  void step_piece(SweepState& s, ElasticSweep& body, bool on_view, double cur, double next, double length,
                  bool teleporting);
  // after an internal step of the body: whether the part has fallen asleep.
  void settle(SweepState& s, double from, double to);
  // Whether sweep i may move during [from, to): driven, and awake or with a force in that time.
  bool has_work(int i, double from, double to) const;
  // Whether a world collider, moving against the moving body, may reach sweep i over [from, to].
  bool collider_comes(int i, double from, double to) const;
  void check_finite(const ElasticSweep& body, double t) const;

  // The body's loads on sweep s over a piece centred on `mid` (inertia, turning gravity, its keyed
  // bend).
  void set_body_motion(SweepState& s, ElasticSweep& sweep, double mid, bool teleporting) const;
  // Whether the body or sweep s's keyed bend loads it during [from, to].
  bool loads(const SweepState& s, double from, double to) const {
    return body_loads(from, to) || (s.keyed >= 0 && scene_.keyed_bends[s.keyed].loads_between(from, to));
  }
  // Whether the body jumps between the two times (cut, respawn): see Scene::teleport_distance.
  bool jumps(double from, double to) const;
  // Adds to skipped_ the world colliders the parts, at rest and carried by the body over the
  // teleport's [from, to), come into (frame: the frame the teleport was found in).
  void note_skipped_colliders(double from, double to, int frame);

  // Advances every sweep from `start` (the current time) to `target`.
  void advance_between(double start, double target);
  // After the body path changed: its corners, its cuts, and every part driven if it moves.
  void path_changed();
  // Applies a body pose given for the advance to `target`.
  void take_body_pose(double target);
  // The earliest time a driven sweep's internal clock stands at (what the path must still cover).
  double earliest_grid_time() const;
  // Internal steps done by time t (t within rounding of an internal time counts as on it).
  long long grid_steps_by(double t) const;
  void drive(SweepState& s);  // marks it driven, its clock brought to the current time
  void drop_finished_forces();

  Scene scene_;  // a copy: live input changes its body path, forces and gravity
  SleepSettings sleep_;
  std::vector<SweepState> sweeps_;
  int frame_ = 0;
  double time_ = 0;
  bool live_loads_ = false;  // gravity or wind changed live: the parts' loads are set every step
  bool parallel_ = true;
  bool pose_pending_ = false;
  BodyKey pending_pose_{};
  std::vector<BodyKey> pose_keys_;  // scratch of take_body_pose: the live path's next keys
  // The last teleport, a span of time [teleport_from_, teleport_to_]: from the start of the first
  // frame the jump reaches (where the parts were put to rest) to the end of the jump (the path's
  // cut, or that frame's end when the jump is not one piece of the path). Every internal step or
  // piece of one that overlaps it, whichever frame it falls in, feels no body loads and sees the
  // colliders where they stand at its end (so that a world collider does not sweep across the
  // part, nor drag it by friction, as the body jumps past it); no corner of the path inside it,
  // ends included, kicks the part or splits a step.
  bool teleported_ = false;
  double teleport_from_ = 0, teleport_to_ = 0;
  // The cuts of the path: pieces (merged when they touch) that move farther than the teleport
  // distance, or turn more than its angle, within a frame's time. Known from the path, they are
  // found wherever the frames fall (a cut split over two frames, each half under the distance).
  std::vector<std::pair<double, double>> cuts_;
  // Whether [from, to] overlaps the teleport's span (not just touches it).
  bool in_teleport(double from, double to) const { return teleported_ && from < teleport_to_ && to > teleport_from_; }
  // Whether time t lies in the teleport's span, ends included.
  bool in_teleport(double t) const { return teleported_ && t >= teleport_from_ && t <= teleport_to_; }
  // Whether the body loads the parts during [from, to] outside the teleport's span (its keys,
  // both ends of the cut included, are not loads: the part is at rest in the new place).
  bool body_loads(double from, double to) const;
  std::vector<double> kinks_;           // times where a linear path's velocity jumps
  std::vector<std::size_t> kink_keys_;  // and their keys
  double teleport_distance_ = 0, teleport_angle_ = 0;
  std::vector<int> teleports_;
  std::vector<std::string> skipped_;
};

}  // namespace sweep::sim
