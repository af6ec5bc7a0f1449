#include "sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace sweep::sim {

Simulator::Simulator(const Rig& rig, const Scene& scene, SleepSettings sleep) : scene_(scene), sleep_(sleep) {
  sweeps_.reserve(rig.sweeps.size());
  for (const SweepDef& def : rig.sweeps) {
    sweeps_.push_back({ElasticSweep(def)});
    sweeps_.back().body.set_integrator(scene.integrator);
  }
  for (const SceneForce& f : scene.forces) sweeps_[f.sweep_index].driven = true;
  forces_.resize(scene.forces.size());
}

void Simulator::advance_frame() {
  for (SweepState& s : sweeps_) s.moved = false;
  for (int k = 0; k < scene_.substeps; ++k) internal_step();
  ++frame_;
}

void Simulator::internal_step() {
  const double h = scene_.step_seconds();
  const double t0 = static_cast<double>(step_index_) * h;
  // A force acts over the steps whose midpoint lies in [start, end): when start and end fall on
  // step boundaries this is exact, and it never depends on rounding at the boundary itself.
  const double mid = t0 + 0.5 * h;
  for (std::size_t i = 0; i < scene_.forces.size(); ++i) {
    const SceneForce& f = scene_.forces[i];
    SweepState& s = sweeps_[f.sweep_index];
    if (f.impulse()) {
      if (f.start >= t0 && f.start < t0 + h) {
        s.body.apply_impulse(f.spec);
        s.awake = true;
        s.quiet = 0;
      }
      continue;
    }
    const bool active = f.start <= mid && mid < f.end;
    if (active && forces_[i].id == 0) {
      forces_[i].id = s.body.add_force(f.spec);
      s.awake = true;
      s.quiet = 0;
    } else if (!active && forces_[i].id != 0) {
      s.body.remove_force(forces_[i].id);
      forces_[i].id = 0;
    }
  }
  for (std::size_t i = 0; i < sweeps_.size(); ++i) {
    SweepState& s = sweeps_[i];
    if (!s.driven || !s.awake) continue;
    s.body.step(h);
    ++s.steps;
    s.moved = true;
    check_finite(static_cast<int>(i), t0 + h);
    if (!sleep_.enabled || s.body.force_count() > 0) continue;
    const bool quiet = s.body.max_speed() < sleep_.speed && s.body.max_displacement() < sleep_.displacement;
    s.quiet = quiet ? s.quiet + h : 0.0;
    if (s.quiet >= sleep_.quiet_time) s.awake = false;
  }
  ++step_index_;
}

void Simulator::check_finite(int i, double t) const {
  const ElasticSweep& body = sweeps_[i].body;
  const double limit = kRunawayFactor * std::max(1.0, body.rest().length());
  if (body.is_finite() && body.max_displacement() < limit) return;
  std::ostringstream msg;
  msg << "the simulation diverged: sweep \"" << body.definition().name << "\" at t = " << t << " s ("
      << integrator_name(scene_.integrator) << " integrator, step " << scene_.step_seconds()
      << " s); the exact integrator is stable at every step, or use more substeps";
  fail(ErrorCategory::diverged, msg.str());
}

}  // namespace sweep::sim
