#pragma once
// Runs a scene on a rig: one ElasticSweep per sweep, stepped at a fixed internal step of
// 1 / (fps · substeps) s whatever the output frame rate, with each scene force switched on and off
// at its times. Skips what the scene does not need:
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
#include <vector>

#include "core/elastic_sweep.h"
#include "core/rig.h"
#include "sim/scene.h"

namespace sweep::sim {

struct SleepSettings {
  double speed = 1e-5;         // largest spring speed allowed for sleep (mesh units/s or rad/s)
  double displacement = 1e-5;  // largest spring displacement allowed (mesh units or rad)
  double quiet_time = 0.25;    // s the sweep must stay under both before it sleeps
  bool enabled = true;
};

// A spring displacement this many times the sweep's length (or 1, if larger) means the simulation
// has run away: no elastic part bends that far.
inline constexpr double kRunawayFactor = 1e6;

class Simulator {
 public:
  Simulator(const Rig& rig, const Scene& scene, SleepSettings sleep = {});

  // Advances one output frame: `substeps` internal steps. Frame 0 is the rest pose at time 0.
  void advance_frame();
  int frame() const { return frame_; }
  double time() const { return frame_ / scene_.fps; }

  int sweep_count() const { return static_cast<int>(sweeps_.size()); }
  const ElasticSweep& sweep(int i) const { return sweeps_[i].body; }
  bool is_driven(int i) const { return sweeps_[i].driven; }
  bool is_awake(int i) const { return sweeps_[i].awake; }
  // Whether sweep i's shape changed during the last advance_frame (it must be re-deformed).
  bool moved_last_frame(int i) const { return sweeps_[i].moved; }
  long long steps_taken(int i) const { return sweeps_[i].steps; }

 private:
  struct SweepState {
    ElasticSweep body;
    bool driven = false;
    bool awake = false;
    bool moved = false;
    double quiet = 0;  // s spent under the sleep tolerances
    long long steps = 0;
    std::vector<std::size_t> forces{};  // indices of the scene forces acting on it, in scene order
    std::exception_ptr failure{};       // divergence during the current frame, at failure_step
    long long failure_step = 0;
  };
  struct ForceState {
    ForceId id = 0;  // 0 while not applied
  };

  // Sweep i's internal step number `step`: switch its forces on and off, then step it if awake.
  void step_sweep(int i, long long step);
  // Whether sweep i may move during [from, to): driven, and awake or with a force in that time.
  bool has_work(int i, double from, double to) const;
  void check_finite(int i, double t) const;

  const Scene& scene_;
  SleepSettings sleep_;
  std::vector<SweepState> sweeps_;
  std::vector<ForceState> forces_;
  long long step_index_ = 0;
  int frame_ = 0;
};

}  // namespace sweep::sim
