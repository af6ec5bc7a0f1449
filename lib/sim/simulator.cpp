#include "sweep/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <utility>

#include "sweep/core/error.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"

namespace sweep::sim {

namespace {

// How close (relative) a frame time must be to an internal time to count as on it: frame times
// k/fps carry a rounding error of an ulp or so, which must not turn into a partial step of ~h.
constexpr double kOnGridTolerance = 1e-9;
// Pieces a step within a collider's reach is cut into, at most, for a fast body's sake.
constexpr double kMostPieces = 1e5;
// Times a teleport's path is sampled at, at most, for each part and world collider.
constexpr int kSkippedSamples = 100000;

// Keys a live body path keeps (take_body_pose): a few before the earliest internal clock, now and
// the pose given. Its buffers are reserved for this many, so a game's frames do not allocate.
constexpr std::size_t kLiveKeys = 8;

}  // namespace

Simulator::Simulator(const Rig& rig, const Scene& scene, SleepSettings sleep) : scene_(scene), sleep_(sleep) {
  for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
    const std::string wrong = scene.colliders[c].check();
    if (!wrong.empty()) {
      fail(ErrorCategory::usage, "Scene::colliders[" + std::to_string(c) + "] (\"" + scene.colliders[c].name +
                                     "\", a " + shape_name(scene.colliders[c].shape) + "): " + wrong);
    }
  }
  if (scene.contact_stations < 1 || scene.contact_stations > 64)
    fail(ErrorCategory::usage, "Scene::contact_stations must be between 1 and 64");
  if (!std::isfinite(scene.contact_step) || scene.contact_step < limits::kMinStep ||
      scene.contact_step > limits::kMaxStep)
    fail(ErrorCategory::usage, "Scene::contact_step must be between " + format_number(limits::kMinStep) + " and " +
                                   format_number(limits::kMaxStep) + " s");
  pose_keys_.reserve(kLiveKeys);
  kink_keys_.reserve(kLiveKeys);
  kinks_.reserve(kLiveKeys);
  sweeps_.reserve(rig.sweeps.size());
  for (const SweepDef& def : rig.sweeps) {
    sweeps_.push_back(SweepState{.body = ElasticSweep(def),
                                 .view = ElasticSweep(def),
                                 .contact = ContactSolver(def.rest, scene.contact_stations),
                                 .anchors = {}});
    sweeps_.back().body.set_integrator(scene.integrator);
    sweeps_.back().view.set_integrator(scene.integrator);
    sweeps_.back().body.set_dynamics(scene.dynamics);
    sweeps_.back().view.set_dynamics(scene.dynamics);
    if (def.material && scene.gravity != Vec3::Zero()) {
      // Gravity in the body's axes at time 0: what the modelled pose is pre-loaded with.
      const Vec3 g = scene.body.at(0).rotation.conjugate() * scene.gravity;
      // Starting unloaded, the part sags from frame 0: it is driven and awake.
      if (start_under_gravity(sweeps_.back(), g)) sweeps_.back().driven = sweeps_.back().awake = true;
    }
  }
  // A keyed bend drives its part (from scene_, the simulator's own copy).
  for (std::size_t i = 0; i < sweeps_.size() && i < scene_.keyed_bends.size(); ++i) {
    const KeyedBend& bend = scene_.keyed_bends[i];
    if (bend.empty()) continue;
    if (bend.sections() != rig.sweeps[i].rest.section_count())
      fail(ErrorCategory::usage, "Scene::keyed_bends[" + std::to_string(i) + "] has " +
                                     std::to_string(bend.sections()) + " sections; sweep \"" + rig.sweeps[i].name +
                                     "\" has " + std::to_string(rig.sweeps[i].rest.section_count()));
    sweeps_[i].keyed = static_cast<int>(i);
    sweeps_[i].keyed_now.assign(static_cast<std::size_t>(bend.sections()), Vec3::Zero());
    sweeps_[i].driven = true;
  }
  for (std::size_t f = 0; f < scene.forces.size(); ++f) {
    SweepState& s = sweeps_[scene.forces[f].sweep_index];
    s.driven = true;
    s.forces.push_back(f);
  }
  for (SweepState& s : sweeps_) {
    s.ids.assign(s.forces.size(), 0);
    s.view_ids.assign(s.forces.size(), 0);
    // Room for all its forces on at once, in the body and the view: switching them on and copying
    // the body into the view then allocate nothing during the frames.
    s.body.reserve_forces(s.forces.size());
    s.view.reserve_forces(s.forces.size());
  }
  // A moving body reaches every part (a part it never loads sleeps all the same: path_changed), and
  // wind every part with a material.
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    if (rig.sweeps[i].material && scene.wind.settings().any())
      sweeps_[i].driven = sweeps_[i].awake = sweeps_[i].windy = true;
  }
  double longest = 0;
  for (const SweepDef& def : rig.sweeps) longest = std::max(longest, def.rest.length());
  teleport_distance_ = scene.teleport_distance > 0 ? scene.teleport_distance : longest;
  teleport_angle_ = scene.teleport_angle > 0 ? scene.teleport_angle : 0.5 * 3.141592653589793;
  path_changed();
}

bool Simulator::start_under_gravity(SweepState& s, const Vec3& gravity) {
  using Start = Scene::GravityStart;
  if (scene_.gravity_start == Start::unloaded) {
    s.held.reset();
  } else if (!s.held || s.held_gravity != gravity) {
    s.held = sweep::held_rest(s.body.definition(), *s.body.chain(), gravity);
    s.held_gravity = gravity;
  }
  s.preloaded =
      scene_.gravity_start == Start::as_modelled || (scene_.gravity_start == Start::automatic && s.held->holds());
  s.body.set_gravity(gravity, s.preloaded);
  s.view.set_gravity(gravity, s.preloaded);
  return !s.preloaded;
}

void Simulator::path_changed() {
  scene_.body.kink_keys(kink_keys_);
  kinks_.clear();
  for (const std::size_t k : kink_keys_) kinks_.push_back(scene_.body.keys()[k].time);
  cuts_.clear();
  if (scene_.teleport_enabled && scene_.body.moves() && scene_.fps > 0) {
    const std::vector<BodyKey>& keys = scene_.body.keys();
    for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
      const double a = keys[k].time, b = keys[k + 1].time;
      // The most the piece moves within a frame's time (at its mean rate: exact for linear pieces).
      const double share = std::min(1.0, 1.0 / (scene_.fps * (b - a)));
      const BodyState from = scene_.body.at(a), to = scene_.body.at(b);
      if (share * (to.translation - from.translation).norm() <= teleport_distance_ &&
          share * from.rotation.angularDistance(to.rotation) <= teleport_angle_)
        continue;
      if (!cuts_.empty() && cuts_.back().second == a) {
        cuts_.back().second = b;
      } else {
        cuts_.emplace_back(a, b);
      }
    }
  }
  // A moving body reaches every part.
  if (scene_.body.moves()) {
    for (SweepState& s : sweeps_) drive(s);
  }
}

bool Simulator::body_loads(double from, double to) const {
  if (in_teleport(from) || in_teleport(to) || in_teleport(from, to)) {
    // Only what lies after the span, its last key left out.
    if (to <= teleport_to_) return false;
    from = std::nextafter(teleport_to_, std::numeric_limits<double>::infinity());
  }
  return scene_.body.loads_between(from, to);
}

bool Simulator::jumps(double from, double to) const {
  if (!scene_.teleport_enabled || !scene_.body.moves()) return false;
  const BodyState a = scene_.body.at(from), b = scene_.body.at(to);
  return (b.translation - a.translation).norm() > teleport_distance_ ||
         a.rotation.angularDistance(b.rotation) > teleport_angle_;
}

void Simulator::set_body_motion(SweepState& s, ElasticSweep& sweep, double mid, bool teleporting) const {
  const bool windy = scene_.wind.settings().any();
  if (s.keyed >= 0) {
    // The keyed bend's loads, like the body's, are none inside a teleport.
    scene_.keyed_bends[s.keyed].at(mid, s.keyed_now);
    sweep.set_keyed_acceleration(teleporting ? std::span<const Vec3>() : std::span<const Vec3>(s.keyed_now));
  }
  // A body at rest: gravity, if any, was set once (unless it was changed live).
  if (!scene_.body.moves() && !windy && !live_loads_) return;
  ElasticSweep::BodyMotion m;
  const BodyState b = scene_.body.at(mid);
  const Quat to_body = b.rotation.conjugate();
  m.gravity = to_body * scene_.gravity;
  if (!teleporting) {
    m.acceleration = b.acceleration;
    m.angular_velocity = b.angular_velocity;
    m.angular_acceleration = b.angular_acceleration;
    m.velocity = to_body * b.velocity;
  }
  if (windy) {
    m.wind = to_body * scene_.wind.at(mid);
    m.drag = scene_.wind.drag();
  }
  sweep.set_body_motion(m);
}

void Simulator::advance_frame() {
  const double target = static_cast<double>(frame_ + 1) / scene_.fps;
  take_body_pose(target);
  advance_between(time_, target);
  ++frame_;
  time_ = target;
}

long long Simulator::grid_steps_by(double t) const {
  const double q = t / scene_.step_seconds();
  long long n = std::llround(q);
  if (std::abs(q - static_cast<double>(n)) > kOnGridTolerance * std::max(1.0, q))
    n = static_cast<long long>(std::floor(q));
  return n;
}

void Simulator::advance_to(double t) {
  if (!std::isfinite(t) || t < time_ || t > limits::kMaxTime)
    fail(ErrorCategory::usage,
         "advance to t = " + (std::isfinite(t) ? format_number(t) : std::string("a non-finite time")) +
             " s: must be a time from the current one (" + format_number(time_) + " s) to " +
             format_number(limits::kMaxTime) + " s");
  // A time within rounding of an internal time is that time: a body key or force switch there then
  // falls on the step boundary, not an ulp before it inside the step just taken.
  const double q = t / scene_.step_seconds();
  const double on = std::round(q);
  if (std::abs(q - on) <= kOnGridTolerance * std::max(1.0, q)) t = std::max(time_, on * scene_.step_seconds());
  if (t == time_) return;
  take_body_pose(t);
  advance_between(time_, t);
  ++frame_;
  time_ = t;
}

void Simulator::advance_between(double start, double target) {
  for (SweepState& st : sweeps_) st.moved = false;
  const double h = scene_.step_seconds();
  // Internal steps done by the frame time, and the partial step beyond them (0 on the grid).
  const long long n = grid_steps_by(target);
  const double grid_time = static_cast<double>(n) * h;
  const double partial = target - grid_time > kOnGridTolerance * h ? target - grid_time : 0.0;

  // A body that jumps during this frame (a cut, a respawn) puts the parts to rest in the new place,
  // at this frame's start, rather than whipping them: no body loads until the jump's end, even
  // when that end (or an internal step that crosses the jump) falls in a later frame. A cut of
  // the path this frame reaches is the jump; else one found between the frame's ends alone
  // (several pieces together, a cubic path's swing) lasts the frame.
  double cut_from = std::numeric_limits<double>::infinity(), cut_to = -cut_from;
  for (const auto& [a, b] : cuts_) {
    if (a < target && b > start) cut_from = std::min(cut_from, a), cut_to = std::max(cut_to, b);
  }
  // Still inside the last teleport (a cut longer than a frame): the parts were put to rest already.
  const bool going_on = teleported_ && start < teleport_to_;
  bool reset = false;
  if (cut_to > cut_from) {
    if (going_on && cut_from < teleport_to_) {
      if (cut_to > teleport_to_) note_skipped_colliders(teleport_to_, cut_to, frame_ + 1);
      teleport_to_ = std::max(teleport_to_, cut_to);
    } else {
      reset = true;
      teleport_to_ = cut_to;
    }
  } else if (!going_on && jumps(start, target)) {
    reset = true;
    teleport_to_ = target;
  }
  if (reset) note_skipped_colliders(start, teleport_to_, frame_ + 1);
  if (reset) {
    teleported_ = true;
    teleport_from_ = start;
    teleports_.push_back(frame_ + 1);
    for (SweepState& st : sweeps_) {
      st.body.reset();
      st.view.reset();
      st.contact.forget_anchors();
      st.moved = true;
      // It settles in the new place as a part does from its start: awake (a part asleep on the
      // ground, reset to its unloaded rest, must sag and meet the ground there again), its sleep
      // timer and held pose from nothing.
      st.awake = st.driven;
      st.quiet = 0;
      st.held_at.clear();
    }
  }
  int busy = 0;
  for (std::size_t i = 0; i < sweeps_.size(); ++i) {
    sweeps_[i].failure = {};
    busy += has_work(static_cast<int>(i), static_cast<double>(sweeps_[i].grid) * h, target);
  }
  // Sweeps are independent (every force acts on one sweep), so each runs its steps on its own —
  // side by side on the threads when more than one has work. Each sweep does the same operations
  // in the same order either way: the same bits whatever the thread count.
  const auto run = [&](int i) {
    SweepState& st = sweeps_[i];
    if (!st.driven) return;
    try {
      for (; st.grid < n; ++st.grid) {
        advance_span(i, false, static_cast<double>(st.grid) * h, static_cast<double>(st.grid + 1) * h, true);
      }
      // Leaving last frame's view changes the shape even when the body did not move.
      if (st.show_view) st.moved = true;
      st.show_view = false;
      if (partial > 0 && has_work(i, grid_time, target)) {
        st.view.copy_state_from(st.body);
        st.view_ids = st.ids;  // same size: no allocation
        st.contact.save_anchors(st.anchors);
        advance_span(i, true, grid_time, target, false);
        st.contact.restore_anchors(st.anchors);
        st.show_view = true;
        st.moved = true;
      }
    } catch (...) {
      st.failure = std::current_exception();
      st.failure_step = st.grid;
    }
  };
  const int count = sweep_count();
  // Serial unless it pays: entering a parallel region costs a microsecond even on one thread.
  if (busy >= 2 && parallel_) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < count; ++i) run(i);
  } else {
    for (int i = 0; i < count; ++i) run(i);
  }
  // A sweep that diverged stopped there; report the earliest (then the lowest-numbered) one. The
  // frame is not counted, and the simulator must not be advanced again (the other sweeps did
  // finish the frame).
  const SweepState* failed = nullptr;
  for (const SweepState& st : sweeps_) {
    if (st.failure && (failed == nullptr || st.failure_step < failed->failure_step)) failed = &st;
  }
  if (failed != nullptr) std::rethrow_exception(failed->failure);
  for (SweepState& st : sweeps_) {
    if (!(st.too_fast > 0)) continue;
    std::ostringstream msg;
    msg << "frame " << frame_ + 1 << ": the body moves so fast against the world's colliders that sweep \""
        << st.body.definition().name << "\" would need " << format_number(st.too_fast, 3)
        << " pieces of a step near them, more than " << format_number(kMostPieces, 3)
        << ": it may pass through one unmet; slow the body or give the scene a shorter step";
    skipped_.push_back(msg.str());
    st.too_fast = 0;
  }
}

void Simulator::drive(SweepState& s) {
  if (s.driven) return;
  // Never stepped until now, it stands at rest: its clock joins the others' (the steps it skips
  // would have done nothing).
  s.grid = grid_steps_by(time_);
  s.driven = true;
}

double Simulator::earliest_grid_time() const {
  double t = time_;
  for (const SweepState& s : sweeps_) {
    if (s.driven) t = std::min(t, static_cast<double>(s.grid) * scene_.step_seconds());
  }
  return t;
}

void Simulator::set_resolved_modes_only(bool on) {
  for (SweepState& s : sweeps_) {
    const ChainModel* chain = s.body.chain();
    if (chain == nullptr || !scene_.colliders.empty()) continue;
    const int count = on ? ElasticSweep::resolved_modes(*chain, scene_.step_seconds(), ElasticSweep::kResolvedModeBound)
                         : 3 * chain->joints;
    s.body.set_moving_modes(count);
    s.view.set_moving_modes(count);
  }
}

void Simulator::set_midpoint_loads(bool on) {
  for (SweepState& s : sweeps_) {
    s.body.set_midpoint_loads(on);
    s.view.set_midpoint_loads(on);
  }
}

void Simulator::set_body_pose(const Quat& rotation, const Vec3& translation) {
  if (!rotation.coeffs().allFinite() || !translation.allFinite() || std::abs(rotation.norm() - 1) > 1e-6)
    fail(ErrorCategory::usage, "the body's pose must be finite, its rotation a unit quaternion");
  pending_pose_.rotation = rotation.normalized();
  pending_pose_.translation = translation;
  pose_pending_ = true;
}

void Simulator::take_body_pose(double target) {
  if (!pose_pending_) return;
  pose_pending_ = false;
  const BodyPath& path = scene_.body;
  const Vec3 pivot = path.pivot();
  // The keys hold the pivot's position p (world = R (mesh − c) + p): p = translation + R c.
  BodyKey key = pending_pose_;
  key.translation += key.rotation * pivot;
  std::vector<BodyKey>& keys = pose_keys_;  // scratch: the path's old keys come back into it
  keys.clear();
  if (frame_ == 0 && !path.moves()) {
    // Before the first advance: the body starts here, at rest, its parts pre-loaded with gravity
    // in its axes as at a scene's start.
    key.time = 0;
    keys.push_back(key);
    for (SweepState& s : sweeps_) {
      if (!s.body.definition().material || scene_.gravity == Vec3::Zero()) continue;
      const Vec3 g = key.rotation.conjugate() * scene_.gravity;
      if (start_under_gravity(s, g)) {  // unloaded, it sags from frame 0
        drive(s);
        s.awake = true;
      }
    }
  } else {
    // The keys the internal clocks still need: from the one before the last key at or before the
    // earliest clock (its velocity before is that key's kick), up to now.
    const double keep_from = earliest_grid_time();
    if (path.interpolation() == BodyInterpolation::linear) {
      const std::vector<BodyKey>& old = path.keys();
      std::size_t first = 0;
      for (std::size_t k = 0; k < old.size(); ++k) {
        if (old[k].time <= keep_from) first = k;
      }
      if (first > 0) --first;
      for (std::size_t k = first; k < old.size() && old[k].time < time_; ++k) keys.push_back(old[k]);
    }
    const BodyState now = path.at(time_);
    keys.push_back(
        BodyKey{.time = time_, .translation = now.translation + now.rotation * pivot, .rotation = now.rotation});
    key.time = target;
    keys.push_back(key);
  }
  scene_.body.swap_keys(keys, BodyInterpolation::linear, pivot);
  keys.reserve(kLiveKeys);  // the scene's own keys came back: allocates once, on the first pose
  path_changed();
}

void Simulator::add_force(const SceneForce& force) {
  if (force.sweep_index < 0 || force.sweep_index >= sweep_count())
    fail(ErrorCategory::usage, "a force on sweep " + std::to_string(force.sweep_index) + ": the rig has " +
                                   std::to_string(sweep_count()) + " sweeps");
  if (!std::isfinite(force.start) || !std::isfinite(force.end) || force.start < time_ || force.end < force.start)
    fail(ErrorCategory::usage, "a force from " + format_number(force.start) + " s to " + format_number(force.end) +
                                   " s: it must start now (" + format_number(time_) +
                                   " s) or later, and not end before it starts");
  if (!force.spec.vector.allFinite() || !force.spec.point.allFinite())
    fail(ErrorCategory::usage, "a force's point and vector must be finite");
  drop_finished_forces();
  SweepState& s = sweeps_[force.sweep_index];
  drive(s);
  scene_.forces.push_back(force);
  s.forces.push_back(scene_.forces.size() - 1);
  s.ids.push_back(0);
  s.view_ids.push_back(0);
  s.body.reserve_forces(s.forces.size());  // allocates here, not in the frames that switch it on
  s.view.reserve_forces(s.forces.size());
}

void Simulator::drop_finished_forces() {
  // A force is over once every step its sweep takes starts after its end, and it has been taken off.
  std::vector<std::size_t> renumber(scene_.forces.size(), 0);
  std::vector<bool> keep(scene_.forces.size(), true);
  for (const SweepState& s : sweeps_) {
    const double clock = static_cast<double>(s.grid) * scene_.step_seconds();
    for (std::size_t k = 0; k < s.forces.size(); ++k) {
      if (s.ids[k] == 0 && s.view_ids[k] == 0 && scene_.forces[s.forces[k]].end < clock) keep[s.forces[k]] = false;
    }
  }
  if (std::find(keep.begin(), keep.end(), false) == keep.end()) return;
  std::size_t next = 0;
  for (std::size_t f = 0; f < keep.size(); ++f) {
    renumber[f] = next;
    if (keep[f]) scene_.forces[next++] = scene_.forces[f];
  }
  scene_.forces.resize(next);
  for (SweepState& s : sweeps_) {
    std::size_t out = 0;
    for (std::size_t k = 0; k < s.forces.size(); ++k) {
      if (!keep[s.forces[k]]) continue;
      s.forces[out] = renumber[s.forces[k]];
      s.ids[out] = s.ids[k];
      s.view_ids[out] = s.view_ids[k];
      ++out;
    }
    s.forces.resize(out);
    s.ids.resize(out);
    s.view_ids.resize(out);
  }
}

void Simulator::set_gravity(const Vec3& gravity) {
  if (!gravity.allFinite()) fail(ErrorCategory::usage, "gravity must be finite");
  scene_.gravity = gravity;
  live_loads_ = true;
  for (SweepState& s : sweeps_) {
    if (!s.body.definition().material) continue;
    drive(s);
    s.awake = true;
    s.quiet = 0;
  }
}

void Simulator::set_wind(const WindSettings& wind) {
  const bool finite = wind.velocity.allFinite() && std::isfinite(wind.gust) && std::isfinite(wind.gust_period) &&
                      std::isfinite(wind.turbulence) && std::isfinite(wind.air_density) &&
                      std::isfinite(wind.drag_coefficient);
  if (!finite || wind.gust < 0 || wind.gust > 1 || wind.gust_period <= 0 || wind.turbulence < 0 ||
      wind.air_density < 0 || wind.drag_coefficient < 0)
    fail(ErrorCategory::usage,
         "wind: finite numbers, gust from 0 to 1, a positive gust period, and no negative "
         "turbulence, air density or drag coefficient");
  scene_.wind = Wind(wind);
  // Set every step from now on, so that wind that stops stops loading the parts too.
  live_loads_ = true;
  for (SweepState& s : sweeps_) {
    if (!s.body.definition().material) continue;
    s.windy = wind.any();
    drive(s);
    s.awake = true;
    s.quiet = 0;
  }
}

void Simulator::note_skipped_colliders(double from, double to, int frame) {
  // The farthest any point of a part's rest pose lies from the mesh's origin: how far a turn of
  // the body by an angle moves it (times the angle).
  double extent = 0;
  for (const SweepState& st : sweeps_) {
    const SweepShape& rest = st.body.rest();
    double radius = 0;
    for (const double r : rest.radii) radius = std::max(radius, r);
    for (const Frame& f : rest.frames) extent = std::max(extent, f.center.norm() + rest.length() + 1.5 * radius);
  }
  // How far the body's motion between two times may move a part's point against the world (exact
  // on a linear path, whose pieces move straight and turn one way).
  const auto moved = [&](const BodyState& a, const BodyState& b) {
    return (b.translation - a.translation).norm() + a.rotation.angularDistance(b.rotation) * extent;
  };
  for (const Collider& col : scene_.colliders) {
    if (col.carried) continue;  // it jumps with the body
    for (const SweepState& st : sweeps_) {
      const SweepShape& rest = st.body.rest();
      // Marched from the jump's start, each time as far as the body cannot have closed the gap
      // the part had there (at least a thousandth of its length: a collider the part would cut
      // by less is not told), up to the jump's end, where the colliders are met again.
      const double least = 1e-3 * rest.length();
      double t = from;
      bool into = false;
      for (int sample = 0; t < to && sample < kSkippedSamples && !into; ++sample) {
        const BodyState here = scene_.body.at(t);
        const Frame world_to_mesh = Frame{here.rotation, here.translation}.inverse();
        const double gap = clearance(rest, {&col, world_to_mesh * col.pose}, scene_.contact_stations).gap;
        into = gap < 0;
        double dt = to - t;
        while (dt > kOnGridTolerance * (to - from) && moved(here, scene_.body.at(t + dt)) > std::max(gap, least))
          dt *= 0.5;
        t += dt;
      }
      if (!into) continue;
      const double travel = moved(scene_.body.at(from), scene_.body.at(to));
      std::ostringstream msg;
      msg << "frame " << frame << ": the body's move from t = " << format_number(from, 6) << " to "
          << format_number(to, 6) << " s (" << format_number(travel, 6) << " mesh units, "
          << format_number(travel / (to - from), 6)
          << " a second) is taken as a teleport (it goes farther than the teleport distance, "
          << format_number(teleport_distance_, 6) << ", or turns more than its angle, within a frame's time): sweep \""
          << st.body.definition().name << "\" is put to rest in the new place and passes through collider \""
          << col.name << "\" (a " << shape_name(col.shape)
          << ") without meeting it; if the body really moves that fast, raise the scene's teleport "
             "distance or set \"teleport\": false";
      skipped_.push_back(msg.str());
    }
  }
}

void Simulator::place_colliders(double t, std::vector<PlacedCollider>& out) const {
  out.resize(scene_.colliders.size());
  const BodyState b = scene_.body.at(t);
  const Frame mesh_to_world{b.rotation, b.translation};
  const Frame world_to_mesh = mesh_to_world.inverse();
  for (std::size_t c = 0; c < out.size(); ++c) {
    const Collider& col = scene_.colliders[c];
    out[c] = {&col, col.carried ? col.pose : world_to_mesh * col.pose};
  }
}

bool Simulator::collider_comes(int i, double from, double to) const {
  if (!scene_.body.moves()) return false;
  const bool any_world =
      std::any_of(scene_.colliders.begin(), scene_.colliders.end(), [](const Collider& c) { return !c.carried; });
  if (!any_world) return false;  // carried ones never come nearer
  std::vector<PlacedCollider> a, b;
  place_colliders(from, a);
  place_colliders(to, b);
  // Only the world's colliders come nearer: one the body carries stays where it is beside the part.
  std::erase_if(a, [](const PlacedCollider& p) { return p.collider->carried; });
  std::erase_if(b, [](const PlacedCollider& p) { return p.collider->carried; });
  return sweeps_[i].contact.may_reach(sweeps_[i].body.deformed(), a, b);
}

bool Simulator::has_work(int i, double from, double to) const {
  const SweepState& st = sweeps_[i];
  if (!st.driven) return false;
  if (st.awake) return true;
  if (loads(st, from, to)) return true;
  if (collider_comes(i, from, to)) return true;
  for (std::size_t f : st.forces) {
    const SceneForce& force = scene_.forces[f];
    if (force.start < to && force.end >= from) return true;
  }
  return false;
}

// A span is cut into pieces at switching times; each piece is stepped in stages (simulator.h).
void Simulator::advance_span(int i, bool on_view, double from, double to, bool grid_step) {
  SweepState& s = sweeps_[i];
  ElasticSweep& body = on_view ? s.view : s.body;
  std::vector<ForceId>& ids = on_view ? s.view_ids : s.ids;
  bool awake = s.awake;  // the view's waking is its own: the body wakes when it gets there
  const auto wake = [&] {
    awake = true;
    if (!on_view) s.quiet = 0;
  };
  if (grid_step) {
    s.touched = false;
  }
  bool stepped = false;
  double cur = from;
  while (cur < to) {
    const double next = piece_end(s, cur, to);
    const bool teleporting = in_teleport(cur, next);
    if (apply_kicks(body, cur, next, teleporting)) wake();
    if (switch_forces(s, body, ids, cur, next)) wake();
    if (!awake && !teleporting && (loads(s, cur, next) || collider_comes(i, cur, next))) wake();
    if (awake) {
      // A whole internal step is stepped with h itself: (n+1)·h − n·h differs from h in its last
      // bits, and a step of new length costs new step maps.
      const bool whole = grid_step && cur == from && next == to;
      step_piece(s, body, on_view, cur, next, whole ? scene_.step_seconds() : next - cur, teleporting);
      stepped = true;
    }
    cur = next;
  }
  if (!stepped) return;
  check_finite(body, to);
  if (on_view) return;
  s.awake = awake;
  s.moved = true;
  if (!grid_step) return;
  ++s.steps;
  // The automatic dynamics decide at the internal step's end, on the body alone (a view's partial
  // step to a frame's time never switches: the switch does not depend on the frame rate).
  // Not in a scene with colliders: the exact chain's contacts are not yet as sure as the modes'
  // (Scene::dynamics), so a part there keeps the modes.
  if (scene_.colliders.empty() && s.body.switch_if_large() && s.chain_switch.time < 0)
    s.chain_switch = {to, s.body.largest_rotation()};
  settle(s, from, to);
}

double Simulator::piece_end(const SweepState& s, double cur, double to) const {
  // The piece up to the next switching time: over it every force is either on or off.
  double next = to;
  for (std::size_t fi : s.forces) {
    for (double sw : {scene_.forces[fi].start, scene_.forces[fi].end}) {
      if (sw > cur && sw < next) next = sw;
    }
  }
  // (A teleport feels no body loads: the corners inside it split nothing.)
  for (double kink : kinks_) {
    if (kink > cur && kink < next && !in_teleport(kink)) next = kink;
  }
  return next;
}

bool Simulator::apply_kicks(ElasticSweep& body, double cur, double next, bool teleporting) const {
  // The corner of a linear body path is a kick (pieces start at switching times, so a corner
  // in [cur, next) is at cur); none inside a teleport, ends included (the part is at rest in
  // the new place as at a scene's start, where the body's motion gives no kick either).
  if (teleporting) return false;
  bool kicked = false;
  for (std::size_t k = 0; k < kinks_.size(); ++k) {
    if (kinks_[k] >= cur && kinks_[k] < next && !in_teleport(kinks_[k])) {
      Vec3 dv, dw;
      scene_.body.jump_at(kink_keys_[k], dv, dw);
      body.apply_body_kick(dv, dw);
      kicked = true;
    }
  }
  return kicked;
}

bool Simulator::switch_forces(const SweepState& s, ElasticSweep& body, std::vector<ForceId>& ids, double cur,
                              double next) const {
  bool woke = false;
  const double mid = cur + 0.5 * (next - cur);
  for (std::size_t k = 0; k < s.forces.size(); ++k) {
    const SceneForce& f = scene_.forces[s.forces[k]];
    if (f.impulse()) {
      // Pieces start at switching times, so an impulse in [cur, next) is at cur.
      if (f.start >= cur && f.start < next) {
        body.apply_impulse(f.spec);
        woke = true;
      }
      continue;
    }
    const bool active = f.start <= mid && mid < f.end;
    if (active && ids[k] == 0) {
      ids[k] = body.add_force(f.spec);
      woke = true;
    } else if (!active && ids[k] != 0) {
      body.remove_force(ids[k]);
      ids[k] = 0;
    }
  }
  return woke;
}

double Simulator::collider_time(double t, bool teleporting) const {
  return teleporting ? std::max(t, teleport_to_) : t;
}

Simulator::ContactCut Simulator::cut_for_contacts(SweepState& s, const ElasticSweep& body, double cur, double next,
                                                  double length, bool teleporting) {
  // Within a collider's reach the step is cut into equal pieces no longer than contact_step,
  // each met by the colliders (Scene::contact_step says why).
  ContactCut cut;
  if (!scene_.colliders.empty() && (length > scene_.contact_step * (1 + 1e-9) || scene_.body.moves())) {
    place_colliders(collider_time(cur, teleporting), s.placed);
    place_colliders(collider_time(next, teleporting), s.placed_end);
    cut.placed_at_ends = true;
    if (s.contact.within_reach(body, s.placed, s.placed_end)) {
      cut.pieces = static_cast<int>(std::ceil(length / scene_.contact_step * (1 - 1e-9)));
      // And a body keyed to move very fast: no collider moves farther than the part's thinnest
      // section against it in a piece (ContactSolver::pieces_for_move).
      const double by_move = s.contact.pieces_for_move(body, s.placed, s.placed_end);
      if (by_move > 1) cut.pieces = std::max(cut.pieces, static_cast<int>(std::min(std::ceil(by_move), kMostPieces)));
      if (by_move > kMostPieces) s.too_fast = std::max(s.too_fast, by_move);
    }
  }
  return cut;
}

void Simulator::step_piece(SweepState& s, ElasticSweep& body, bool on_view, double cur, double next, double length,
                           bool teleporting) {
  const bool contacts = !scene_.colliders.empty();
  const ContactCut cut = cut_for_contacts(s, body, cur, next, length, teleporting);
  const int pieces = cut.pieces;
  const bool placed_at_ends = cut.placed_at_ends;  // s.placed at cur, s.placed_end at next
  const double piece = length / pieces;
  for (int p = 0; p < pieces; ++p) {
    const double a = cur + (next - cur) * p / pieces;
    const bool last = p + 1 == pieces;
    const double b = last ? next : cur + (next - cur) * (p + 1) / pieces;
    set_body_motion(s, body, a + 0.5 * (b - a), teleporting);
    if (contacts) {
      if (p > 0 || !placed_at_ends) place_colliders(collider_time(a, teleporting), s.placed);
      s.contact.begin_step(body, s.placed);
    }
    body.step(piece);
    if (contacts) {
      if (last && placed_at_ends) {
        std::swap(s.placed, s.placed_end);
      } else {
        place_colliders(collider_time(b, teleporting), s.placed);
      }
      if (s.contact.resolve(body, s.placed, b - a) && !on_view) s.touched = true;
    }
  }
}

void Simulator::settle(SweepState& s, double from, double to) {
  const ElasticSweep& body = s.body;
  if (!sleep_.enabled || body.force_count() > 0 || s.windy) return;
  if (loads(s, from, to)) return;
  bool quiet = body.max_speed() < sleep_.speed && body.max_displacement() < sleep_.displacement;
  if (s.touched) {
    // A part held by a collider rests away from its rest pose, and each step its springs take up
    // a step's weight that the contact then takes out: its speeds never fall still. Its pose does:
    // it is quiet while no section has left, by more than kHeldDrift of the part's length, where
    // it was when this quiet stretch began.
    const std::vector<Frame>& frames = body.deformed().frames;
    double drift = s.held_at.size() == frames.size() ? 0.0 : std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < s.held_at.size() && k < frames.size(); ++k)
      drift = std::max(drift, (frames[k].center - s.held_at[k]).norm());
    quiet = drift < kHeldDrift * body.rest().length();
    if (!quiet) {
      s.held_at.resize(frames.size());
      for (std::size_t k = 0; k < frames.size(); ++k) s.held_at[k] = frames[k].center;
    }
  } else {
    s.held_at.clear();
  }
  s.quiet = quiet ? s.quiet + (to - from) : 0.0;
  if (s.quiet >= sleep_.quiet_time) s.awake = false;
}

void Simulator::check_finite(const ElasticSweep& body, double t) const {
  const double limit = kRunawayFactor * std::max(1.0, body.rest().length());
  if (body.is_finite() && body.max_displacement() < limit) return;
  std::ostringstream msg;
  if (scene_.integrator == Integrator::exact) {
    // The closed form cannot diverge: a runaway here is the inputs' doing (forces far too large
    // for the springs, within the limits each has on its own), so it is bad input, not exit 5,
    // which docs/tools.md reserves for the explicit integrators.
    msg << "sweep \"" << body.definition().name << "\" moved more than " << kRunawayFactor
        << " times its length by t = " << t << " s: the scene's forces are far too large for "
        << (body.chain()
                ? "its material (raise youngs_modulus_pa or damping_ratio, shorten the step, or lower the forces)"
                : "its springs (raise mass or frequency_hz, or lower the forces)");
    fail(ErrorCategory::bad_input, msg.str());
  }
  msg << "the simulation diverged: sweep \"" << body.definition().name << "\" at t = " << t << " s ("
      << integrator_name(scene_.integrator) << " integrator, step " << scene_.step_seconds()
      << " s); the exact integrator is stable at every step, or use a smaller step";
  fail(ErrorCategory::diverged, msg.str());
}

}  // namespace sweep::sim
