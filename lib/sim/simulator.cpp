#include "sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

#include "core/error.h"

namespace sweep::sim {

Simulator::Simulator(const Rig& rig, const Scene& scene, SleepSettings sleep)
    : scene_(scene), sleep_(sleep) {
  sweeps_.reserve(rig.sweeps.size());
  for (const SweepDef& def : rig.sweeps) {
    sweeps_.push_back(SweepState{.body = ElasticSweep(def)});
    sweeps_.back().body.set_integrator(scene.integrator);
  }
  for (std::size_t f = 0; f < scene.forces.size(); ++f) {
    SweepState& s = sweeps_[scene.forces[f].sweep_index];
    s.driven = true;
    s.forces.push_back(f);
  }
  forces_.resize(scene.forces.size());
}

void Simulator::advance_frame() {
  for (SweepState& st : sweeps_) st.moved = false;
  // Sweeps are independent (every force acts on one sweep), so each runs the frame's substeps on
  // its own — side by side on the threads when more than one has work. Each sweep does the same
  // operations in the same order either way: the same bits whatever the thread count.
  const long long first = step_index_;
  const double h = scene_.step_seconds();
  const double frame_start = static_cast<double>(first) * h;
  const double frame_end = static_cast<double>(first + scene_.substeps) * h;
  int busy = 0;
  for (std::size_t i = 0; i < sweeps_.size(); ++i) {
    sweeps_[i].failure = {};
    busy += has_work(static_cast<int>(i), frame_start, frame_end);
  }
  // Serial unless it pays: entering a parallel region costs a microsecond even on one thread.
  const auto run = [&](int i) {
    if (!sweeps_[i].driven) return;
    for (int k = 0; k < scene_.substeps; ++k) {
      try {
        step_sweep(i, first + k);
      } catch (...) {
        sweeps_[i].failure = std::current_exception();
        sweeps_[i].failure_step = first + k;
        return;
      }
    }
  };
  const int count = sweep_count();
  if (busy >= 2) {
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
  step_index_ += scene_.substeps;
  ++frame_;
}

bool Simulator::has_work(int i, double from, double to) const {
  const SweepState& st = sweeps_[i];
  if (!st.driven) return false;
  if (st.awake) return true;
  for (std::size_t f : st.forces) {
    const SceneForce& force = scene_.forces[f];
    if (force.start < to && force.end >= from) return true;
  }
  return false;
}

void Simulator::step_sweep(int i, long long step) {
  const double h = scene_.step_seconds();
  const double t0 = static_cast<double>(step) * h;
  // A force acts over the steps whose midpoint lies in [start, end): when start and end fall on
  // step boundaries this is exact, and it never depends on rounding at the boundary itself.
  const double mid = t0 + 0.5 * h;
  SweepState& s = sweeps_[i];
  for (std::size_t fi : s.forces) {
    const SceneForce& f = scene_.forces[fi];
    if (f.impulse()) {
      if (f.start >= t0 && f.start < t0 + h) {
        s.body.apply_impulse(f.spec);
        s.awake = true;
        s.quiet = 0;
      }
      continue;
    }
    const bool active = f.start <= mid && mid < f.end;
    if (active && forces_[fi].id == 0) {
      forces_[fi].id = s.body.add_force(f.spec);
      s.awake = true;
      s.quiet = 0;
    } else if (!active && forces_[fi].id != 0) {
      s.body.remove_force(forces_[fi].id);
      forces_[fi].id = 0;
    }
  }
  if (!s.awake) return;
  s.body.step(h);
  ++s.steps;
  s.moved = true;
  check_finite(i, t0 + h);
  if (!sleep_.enabled || s.body.force_count() > 0) return;
  const bool quiet =
      s.body.max_speed() < sleep_.speed && s.body.max_displacement() < sleep_.displacement;
  s.quiet = quiet ? s.quiet + h : 0.0;
  if (s.quiet >= sleep_.quiet_time) s.awake = false;
}

void Simulator::check_finite(int i, double t) const {
  const ElasticSweep& body = sweeps_[i].body;
  const double limit = kRunawayFactor * std::max(1.0, body.rest().length());
  if (body.is_finite() && body.max_displacement() < limit) return;
  std::ostringstream msg;
  if (scene_.integrator == Integrator::exact) {
    // The closed form cannot diverge: a runaway here is the inputs' doing (forces far too large
    // for the springs, within the limits each has on its own), so it is bad input, not exit 5,
    // which README reserves for the explicit integrators.
    msg << "sweep \"" << body.definition().name << "\" moved more than " << kRunawayFactor
        << " times its length by t = " << t
        << " s: the scene's forces are far too large for its springs (raise mass or "
           "frequency_hz, or lower the forces)";
    fail(ErrorCategory::bad_input, msg.str());
  }
  msg << "the simulation diverged: sweep \"" << body.definition().name << "\" at t = " << t
      << " s (" << integrator_name(scene_.integrator) << " integrator, step "
      << scene_.step_seconds()
      << " s); the exact integrator is stable at every step, or use more substeps";
  fail(ErrorCategory::diverged, msg.str());
}

}  // namespace sweep::sim
