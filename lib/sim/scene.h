#pragma once
// A simulation scene (schema: rigs/scene.schema.json): how long, at what frame rate, and which
// forces act where and when. Plain data: io/scene_json.h reads it from its own file ("format":
// "sweep-scene") or from under "scene" in the rig file.
#include <string>
#include <vector>

#include "sweep/core/elastic_sweep.h"
#include "sweep/core/force.h"
#include "sweep/core/oscillator.h"
#include "sweep/core/rig.h"
#include "sweep/sim/body_path.h"
#include "sweep/sim/collider.h"
#include "sweep/sim/keyed_bend.h"
#include "sweep/sim/wind.h"

namespace sweep::sim {

struct SceneForce {
  std::string sweep;     // name of the sweep it acts on
  int sweep_index = -1;  // resolved against the rig
  // The force split (place, vector, components, rotation target), with t in the sweep's own
  // arc length (the file gives it as a fraction of the length, 0 = root, 1 = tip).
  ForceSpec spec;
  double start = 0;  // s
  double end = 0;    // s; end == start makes it an impulse of vector·1 s (N·s) at `start`
  bool impulse() const { return end == start; }
};

struct Scene {
  static constexpr int kFormatVersion = 1;
  double duration = 2.0;  // s
  double fps = 30;        // output frames per second (the internal step does not depend on it)
  // The internal step, s. Output frames fall wherever they fall: each is reached by one exact
  // partial step from the last internal time, so the motion is the same at any frame rate. 0 = not
  // given: then `substeps`, if given, keeps its old meaning (step = 1 / (fps · substeps)) so scenes
  // written for it give their old frames; else kDefaultStep.
  double step = 0;
  int substeps = 0;  // internal steps per output frame, the old way to set the step; 0 = not given
  Integrator integrator = Integrator::exact;
  // How a material part's joints move (ElasticSweep::Dynamics): automatic (the default) moves them
  // by the rest-pose modes, stepped in closed form, while the part's motion is small, and by the
  // geometrically exact chain (core/chain_dynamics.h: the inertia, velocity terms and gravity of
  // the current pose, right however far the part turns) from the end of the internal step where a
  // section has turned more than ElasticSweep::kSwitchAngle from its rest pose; modal and exact
  // keep one of them throughout. In a scene with colliders the automatic dynamics keep the modes:
  // the exact chain's contacts are not yet as sure as theirs (a fast swing can end a frame through
  // a thin plate, a friction hold can add energy). The paper's springs mode is the same either way.
  ElasticSweep::Dynamics dynamics = ElasticSweep::Dynamics::automatic;
  // Gravity, m/s² in world axes: every span of a material-mode sweep weighs on the chain.
  Vec3 gravity = Vec3::Zero();
  // How a material part starts under it. as_modelled: the modelled mesh is the pose under gravity
  // (the springs pre-loaded to hold it; no sag on frame 0). unloaded: the mesh is the unloaded
  // rest and the part sags. automatic (the default): as modelled where that pose holds — a stable
  // equilibrium, core/held_rest.h — and unloaded where it does not (a soft part held level would
  // roll over sideways at a nudge; unloaded it droops and sways to its hanging pose instead).
  enum class GravityStart { automatic, as_modelled, unloaded };
  GravityStart gravity_start = GravityStart::automatic;
  std::vector<SceneForce> forces;
  // The body's motion: the whole mesh moves with it, each part's root with the body, and
  // the parts feel its accelerations. Empty: the body stands still. (A scene file's body that follows
  // a node of a glTF mesh, and its "body_collider", need the mesh file: the tools resolve them into
  // this path and into `colliders`, assets/authored_scene.h; the runtime's reader refuses them.)
  BodyPath body;
  // Per sweep (by index; missing or empty: none), the keyed bend of its own pose relative to its
  // root, which loads its springs as the body's motion does (sim/keyed_bend.h): a skinned clip's
  // part (assets/skinned_clip.h) sets it, on the simulator's clock.
  std::vector<KeyedBend> keyed_bends;
  // A body that jumps farther than this in one frame's time (mesh units), or turns by more than
  // this (radians), has been cut or respawned: the parts are put to rest in the new place instead
  // of feeling the jump (a piece of the path between two keys, wherever the frames fall, or the
  // body between a frame's ends; Simulator keeps the jump's span of time). 0 = the default: the
  // longest part's length, and a quarter turn.
  double teleport_distance = 0;
  double teleport_angle = 0;
  bool teleport_enabled = true;
  // Wind on material-mode parts (sim/wind.h); none by default.
  Wind wind;
  // Colliders the parts may not enter (sim/collider.h, sim/contact.h); none by default. A world
  // collider stays put while the body moves; a carried one moves with it.
  std::vector<Collider> colliders;
  // Chords per span between key sections that meet the colliders (sim/contact.h).
  int contact_stations = 2;
  // The longest step a part takes while a collider is within its reach (s): a longer internal
  // step is cut into equal pieces no longer than this there, each resolved against the colliders.
  // The contacts' push out and friction are first order in the step: at 1/30 s a soft tube lying
  // on a slope was thrown 8 to 24 units, at the default 1/480 s it stays on it (BENCHMARKS.md), so
  // it keeps that fine default when a scene gives a coarser step.
  // Far from every collider a coarse step stays whole. Within reach, the whole motion steps at
  // contact_step — the body's loads too, sampled at each piece's middle, so a collider that never
  // touches still changes a moving body's part slightly (as a finer step would).
  double contact_step = kDefaultContactStep;

  // 1/480 s: 16 steps per 30 fps frame, 20 at 24 fps. Coarser steps were measured against a far
  // finer one (tools/bench/step-accuracy.py, BENCHMARKS.md; the bar: 1e-4 of the part's length)
  // and are not the default: at 1/240 s a soft material part (E = 2e5 Pa, the rest-pose modes) on
  // a moving body under gravity runs away within 0.4 s where at 1/480 s it stays (the Allocation
  // tests' loop), and at 1/120 s the follower loads of the diplodocus Fig. 4 scene are 3.4e-4 of
  // the length off (sections, rotation angle × length; 5.8e-5 at 1/240 s, 2.7e-6 at 1/480 s). A
  // tube swung through 0.9 of its length by a body turn and a skinned clip's keyed bend miss the
  // bar even at 1/480 s (1.2e-4, 3.8e-4). Scenes whose parts allow it give a coarser `step`.
  static constexpr double kDefaultStep = 1.0 / 480;
  // contact_step's default, the same as the step's (see contact_step).
  static constexpr double kDefaultContactStep = 1.0 / 480;

  int frame_count() const;  // frames at 0, 1/fps, ..., duration
  double step_seconds() const {
    if (step > 0) return step;
    if (substeps > 0) return 1.0 / (fps * substeps);
    return kDefaultStep;
  }
};

}  // namespace sweep::sim
