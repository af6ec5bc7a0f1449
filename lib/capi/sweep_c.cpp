// The C interface (sweep/sweep.h) over the runtime: an instance holds a rig, its binding, a
// sim::Simulator fed live (sim/simulator.h, "Live input") and the fast deformers. Every entry
// point catches everything: a C host sees an error code and a thread-local message, never an
// exception.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <span>
#include <string>
#include <vector>

#include "sweep/bind/fast_deform.h"
#include "sweep/core/error.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/live_positions.h"
#include "sweep/sim/simulator.h"
#include "sweep/sim/skin_joints.h"
#include "sweep/sweep.h"

struct sweep_instance {
  sweep::Rig rig;
  sweep::sim::Scene scene;
  std::unique_ptr<sweep::sim::Simulator> simulator;
  std::vector<std::unique_ptr<sweep::bind::FastDeformer>> deformers;
  std::unique_ptr<sweep::sim::LivePositions> positions;  // the parts' vertices as of their last deform
  std::unique_ptr<sweep::sim::SkinJoints> joints;        // the skinned export's skeleton, posed on demand
  // Per sweep: moved since its vertices were last deformed / its joints last posed. What a frame
  // reads is computed when it is read (sweep_positions, sweep_joints), for the parts that moved.
  std::vector<char> deform_due, joints_due;
  bool broken = false;  // diverged: the simulator stopped mid-advance
  // The deformed positions and posed joints, brought up to the current time (const entry points
  // read through these: an instance is used by one thread at a time).
  void deform_moved();
  void pose_moved();
};

void sweep_instance::deform_moved() {
  for (int i = 0; i < simulator->sweep_count(); ++i) {
    if (!deform_due[i]) continue;
    positions->deform(i, *deformers[i], simulator->sweep(i).deformed());
    deform_due[i] = 0;
  }
}

void sweep_instance::pose_moved() {
  for (int i = 0; i < simulator->sweep_count(); ++i) {
    if (!joints_due[i]) continue;
    const sweep::ElasticSweep& sweep = simulator->sweep(i);
    joints->pose(i, sweep.deformed(), sweep.radial_active());
    joints_due[i] = 0;
  }
}

namespace {

using sweep::ErrorCategory;
using sweep::fail;

thread_local std::string last_error;

int report(int code, const std::string& message) {
  try {
    last_error = message;
  } catch (...) {  // out of memory for the message itself: keep the code
  }
  return code;
}

// Runs `body`, turning whatever it throws into an error code and this thread's message.
template <typename Body>
int guarded(const char* function, Body&& body) {
  try {
    body();
    return SWEEP_OK;
  } catch (const sweep::Error& e) {
    return report(sweep::exit_code(e.category()), std::string(function) + ": " + e.what());
  } catch (const std::bad_alloc&) {
    return report(SWEEP_ERROR_INTERNAL, std::string(function) + ": out of memory");
  } catch (const std::exception& e) {
    return report(SWEEP_ERROR_INTERNAL, std::string(function) + ": " + e.what());
  } catch (...) {
    return report(SWEEP_ERROR_INTERNAL, std::string(function) + ": an unknown exception");
  }
}

void need(const void* pointer, const char* what) {
  if (pointer == nullptr) fail(ErrorCategory::usage, std::string(what) + " is NULL");
}

void usable(const sweep_instance* instance) {
  need(instance, "the instance");
  if (instance->broken)
    fail(ErrorCategory::diverged, "the simulation diverged in an earlier sweep_advance; close the instance");
}

// The binding's bound vertices, deformed by the parts' rest shapes, must come back near the rest
// positions given: a binding made for another mesh does not. (The binding's own hash is of the
// mesh's positions as doubles, which float positions cannot reproduce unless they were floats.)
void check_rest(const sweep_instance& in, const std::vector<sweep::bind::Vec3f>& rest) {
  std::vector<sweep::bind::Vec3f> shaped = rest;
  for (std::size_t i = 0; i < in.deformers.size(); ++i) in.deformers[i]->deform(in.rig.sweeps[i].rest, shaped);
  // 1 % of the shortest part: the fast path's rest error is a few millionths of it.
  double shortest = std::numeric_limits<double>::infinity();
  for (const sweep::SweepDef& def : in.rig.sweeps) shortest = std::min(shortest, def.rest.length());
  for (std::size_t v = 0; v < rest.size(); ++v) {
    const double off = (shaped[v] - rest[v]).cast<double>().norm();
    if (off > 0.01 * shortest) {
      fail(ErrorCategory::bad_input, "the binding was made for a mesh with other vertex positions (vertex " +
                                         std::to_string(v) + " is " + sweep::format_number(off) +
                                         " from where it binds); run sweep-bind again");
    }
  }
}

// The internal step of an instance whose settings give none: one step a 60 fps frame. Measured on
// the diplodocus in material mode, walking, under gravity and hit (sweep-bench-live, BENCHMARKS.md):
// its vertices stay within 1.7e-4 of their part's length of a step 64 times finer (1/3840 s; 2.3e-5
// at sweep-sim's 1/480 s), at a sixth of the cost of 1/480 s. The oscillators step in closed form (stable
// at any step); what a longer step gives up is the loads' variation within it, which a body moving
// at constant velocity across each frame (sweep_set_body) barely has.
constexpr double kLiveStep = 1.0 / 60;

// The stations a span of the skinned export (sweep-sim's default), which bound its joints a sweep.
constexpr int kExportStationsPerSpan = 8;

std::vector<const sweep::SweepShape*> rest_shapes(const sweep::Rig& rig) {
  std::vector<const sweep::SweepShape*> rests;
  for (const sweep::SweepDef& def : rig.sweeps) rests.push_back(&def.rest);
  return rests;
}

// The skeleton of `sweep-sim --joints` given alone: 24 joints a sweep and 24 around each station,
// or as many along each sweep as the fewest stations any sweep has.
sweep::sim::SkinJointLayout default_skin(const sweep::Rig& rig) {
  sweep::sim::SkinJointLayout layout;
  for (const sweep::SweepDef& def : rig.sweeps)
    layout.stations =
        std::min(layout.stations, std::max(2, (def.rest.section_count() - 1) * kExportStationsPerSpan + 1));
  return layout;
}

// The rest positions of a mesh, one copy for every instance opened with the same ones while one
// lives: a crowd of one creature then streams one copy through its frames' world copies (which
// stays in cache from one creature to the next) instead of one each from memory.
static_assert(sizeof(sweep::bind::Vec3f) == 3 * sizeof(float), "compared as bytes below");
std::shared_ptr<const std::vector<sweep::bind::Vec3f>> shared_rest(std::vector<sweep::bind::Vec3f> rest) {
  static std::mutex mutex;
  static std::vector<std::weak_ptr<const std::vector<sweep::bind::Vec3f>>> meshes;
  const std::lock_guard lock(mutex);
  std::erase_if(meshes, [](const auto& m) { return m.expired(); });
  for (const auto& m : meshes) {
    auto mesh = m.lock();
    // Bit for bit (a NaN is refused before this; -0 and 0 are told apart).
    if (mesh && mesh->size() == rest.size() &&
        std::memcmp(mesh->data(), rest.data(), rest.size() * sizeof(sweep::bind::Vec3f)) == 0)
      return mesh;
  }
  auto mesh = std::make_shared<const std::vector<sweep::bind::Vec3f>>(std::move(rest));
  meshes.push_back(mesh);
  return mesh;
}

sweep::Vec3 vec3(const double xyz[3]) {
  return {xyz[0], xyz[1], xyz[2]};
}

bool finite_floats(const float* xyz) {
  return std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && std::isfinite(xyz[2]);
}

// By classification, not arithmetic (Eigen's allFinite subtracts, which traps on an infinity when
// the host enables floating-point exceptions).
bool finite(const double* x, int n) {
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(x[k])) return false;
  }
  return true;
}

// A number for a message; NaN and infinities by name (no arithmetic on them).
std::string describe(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return sweep::format_number(x);
}

}  // namespace

extern "C" {

sweep_instance* sweep_open(const char* rig_path, const char* binding_path, const char* settings_path,
                           const float* rest_xyz, int vertex_count) {
  std::unique_ptr<sweep_instance> in;
  const int code = guarded("sweep_open", [&] {
    need(rig_path, "rig_path");
    need(binding_path, "binding_path");
    need(rest_xyz, "rest_xyz");
    if (vertex_count <= 0)
      fail(ErrorCategory::usage, "vertex_count must be positive, got " + std::to_string(vertex_count));
    in = std::make_unique<sweep_instance>();
    in->rig = sweep::io::read_rig(rig_path);
    sweep::Mesh mesh;
    std::vector<sweep::bind::Vec3f> rest(static_cast<std::size_t>(vertex_count));
    mesh.positions.resize(rest.size());
    for (std::size_t v = 0; v < rest.size(); ++v) {
      rest[v] = {rest_xyz[3 * v], rest_xyz[3 * v + 1], rest_xyz[3 * v + 2]};
      if (!finite_floats(rest_xyz + 3 * v))
        fail(ErrorCategory::usage, "rest_xyz: vertex " + std::to_string(v) + " is not finite");
      mesh.positions[v] = rest[v].cast<double>();
    }
    sweep::bind::Binding binding = sweep::io::read_binding(binding_path);
    const bool same_positions = binding.mesh_hash == sweep::bind::hash_positions(mesh.positions);
    if (!same_positions) binding.mesh_hash = sweep::bind::hash_positions(mesh.positions);  // checked below instead
    sweep::io::check_binding(binding, mesh, in->rig, binding_path);
    if (settings_path != nullptr) in->scene = sweep::io::read_scene(settings_path, in->rig);
    // Settings that give no step take the live one, with the exact integrator (stable at any step).
    if (in->scene.step == 0 && in->scene.substeps == 0 && in->scene.integrator == sweep::Integrator::exact)
      in->scene.step = kLiveStep;
    for (std::size_t i = 0; i < in->rig.sweeps.size(); ++i) {
      in->deformers.push_back(
          std::make_unique<sweep::bind::FastDeformer>(in->rig.sweeps[i].rest, binding.sweeps[i], rest));
    }
    if (!same_positions) check_rest(*in, rest);
    in->simulator = std::make_unique<sweep::sim::Simulator>(in->rig, in->scene);
    // An instance's frame runs on the calling thread: its parts are a few microseconds of work each,
    // less than waking OpenMP's threads costs after a frame's sleep (on this 2-core machine a paced
    // frame on 2 threads took 20-40 ms against 0.2 ms on one: sweep-bench-live); a game spreads its
    // creatures over its own threads instead.
    in->simulator->set_parallel(false);
    // A material part's modes that ring through more than a period a live step are taken
    // quasi-statically (the same settled shapes): a step reads a fraction of each part's modes
    // (sweep_set_all_modes).
    in->simulator->set_resolved_modes_only(true);
    std::vector<const sweep::bind::FastDeformer*> parts;
    for (const auto& d : in->deformers) parts.push_back(d.get());
    in->positions = std::make_unique<sweep::sim::LivePositions>(shared_rest(std::move(rest)), parts);
    in->deform_due.assign(in->deformers.size(), 0);
    in->joints_due.assign(in->deformers.size(), 0);
    in->joints = std::make_unique<sweep::sim::SkinJoints>(rest_shapes(in->rig), default_skin(in->rig));
  });
  return code == SWEEP_OK ? in.release() : nullptr;
}

void sweep_close(sweep_instance* instance) {
  delete instance;
}

const char* sweep_last_error(void) {
  return last_error.c_str();
}

int sweep_set_body(sweep_instance* instance, const double m[16]) {
  return guarded("sweep_set_body", [&] {
    usable(instance);
    need(m, "world_from_mesh");
    for (int k = 0; k < 16; ++k) {
      if (!std::isfinite(m[k])) fail(ErrorCategory::usage, "world_from_mesh[" + std::to_string(k) + "] is not finite");
    }
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1)
      fail(ErrorCategory::usage, "world_from_mesh's last row must be 0 0 0 1 (column-major: elements 3, 7, 11, 15)");
    sweep::Mat3 r;
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < 3; ++row) r(row, c) = m[4 * c + row];
    }
    // Rigid: a rotation, to float precision (an engine's matrices are often floats).
    const double off = (r.transpose() * r - sweep::Mat3::Identity()).cwiseAbs().maxCoeff();
    if (off > 1e-5 || r.determinant() < 0)
      fail(ErrorCategory::usage,
           "world_from_mesh is not rigid (a rotation and a translation): RᵀR is off the identity by " +
               sweep::format_number(off) + (r.determinant() < 0 ? ", and it mirrors" : ""));
    instance->simulator->set_body_pose(sweep::Quat(r).normalized(), {m[12], m[13], m[14]});
  });
}

int sweep_add_force(sweep_instance* instance, const char* part, const double point[3], const double force[3],
                    double seconds) {
  return guarded("sweep_add_force", [&] {
    usable(instance);
    need(part, "part");
    need(point, "point");
    need(force, "force");
    const sweep::Vec3 p = vec3(point), f = vec3(force);
    if (!finite(point, 3) || !finite(force, 3)) fail(ErrorCategory::usage, "the point and the force must be finite");
    if (f.norm() > sweep::limits::kMaxForce)
      fail(ErrorCategory::usage, "a force of at most " + sweep::format_number(sweep::limits::kMaxForce) +
                                     " N, got one of " + sweep::format_number(f.norm()));
    if (!std::isfinite(seconds) || seconds < 0 || seconds > sweep::limits::kMaxTime)
      fail(ErrorCategory::usage, "seconds must be between 0 (an impulse) and " +
                                     sweep::format_number(sweep::limits::kMaxTime) + ", got " + describe(seconds));
    sweep::sim::SceneForce live;
    for (std::size_t i = 0; i < instance->rig.sweeps.size(); ++i) {
      if (instance->rig.sweeps[i].name == part) live.sweep_index = static_cast<int>(i);
    }
    if (live.sweep_index < 0) {
      std::string names;
      for (const sweep::SweepDef& def : instance->rig.sweeps)
        names += (names.empty() ? "\"" : ", \"") + def.name + "\"";
      fail(ErrorCategory::usage, "the rig has no part \"" + std::string(part) + "\" (its parts: " + names + ")");
    }
    live.sweep = part;
    // The scene's defaults (io/scene_json.cpp): a point projected to the surface, world axes, the
    // paper's components, nearest sections; physical moments in material mode. The scene gives
    // points and vectors in the mesh's space: the body's pose now takes the world's there.
    const sweep::sim::BodyState body = instance->simulator->body();
    live.spec.at_world_point = true;
    live.spec.point = body.rotation.conjugate() * (p - body.translation);
    live.spec.vector = body.rotation.conjugate() * f;
    if (instance->rig.sweeps[live.sweep_index].material) live.spec.moment = sweep::MomentModel::physical;
    live.start = instance->simulator->time();
    live.end = live.start + seconds;
    instance->simulator->add_force(live);
  });
}

int sweep_advance(sweep_instance* instance, double dt) {
  return guarded("sweep_advance", [&] {
    usable(instance);
    if (!std::isfinite(dt) || dt < 0 || dt > sweep::limits::kMaxTime)
      fail(ErrorCategory::usage, "dt must be a number of seconds from 0 to " +
                                     sweep::format_number(sweep::limits::kMaxTime) + ", got " + describe(dt));
    sweep::sim::Simulator& sim = *instance->simulator;
    const int before = sim.frame();
    try {
      sim.advance_to(sim.time() + dt);
    } catch (const sweep::Error& e) {
      if (e.category() != ErrorCategory::usage) instance->broken = true;
      throw;
    }
    if (sim.frame() == before) return;  // dt too small to move the clock
    for (int i = 0; i < sim.sweep_count(); ++i) {
      if (!sim.moved_last_frame(i)) continue;
      instance->deform_due[i] = 1;
      instance->joints_due[i] = 1;
    }
  });
}

int sweep_positions(const sweep_instance* instance, float* out_xyz) {
  return guarded("sweep_positions", [&] {
    need(instance, "the instance");
    need(out_xyz, "out_xyz");
    const_cast<sweep_instance*>(instance)->deform_moved();
    const sweep::sim::BodyState body = instance->simulator->body();
    const Eigen::Matrix3f r = body.rotation.toRotationMatrix().cast<float>();
    const sweep::bind::Vec3f t = body.translation.cast<float>();
    instance->positions->world(r, t, out_xyz);
  });
}

int sweep_positions_local(const sweep_instance* instance, float* out_xyz) {
  return guarded("sweep_positions_local", [&] {
    need(instance, "the instance");
    need(out_xyz, "out_xyz");
    const_cast<sweep_instance*>(instance)->deform_moved();
    instance->positions->local(out_xyz);
  });
}

int sweep_bound_count(const sweep_instance* instance) {
  int count = 0;
  const int code = guarded("sweep_bound_count", [&] {
    need(instance, "the instance");
    // At most the mesh's vertex_count, an int (LivePositions checks each is bound once).
    count = static_cast<int>(instance->positions->bound_indices().size());
  });
  return code == SWEEP_OK ? count : -code;
}

int sweep_bound_indices(const sweep_instance* instance, int* out_indices) {
  return guarded("sweep_bound_indices", [&] {
    need(instance, "the instance");
    need(out_indices, "out_indices");
    const std::span<const std::uint32_t> indices = instance->positions->bound_indices();
    for (std::size_t i = 0; i < indices.size(); ++i) out_indices[i] = static_cast<int>(indices[i]);
  });
}

int sweep_bound_positions(const sweep_instance* instance, float* out_xyz) {
  return guarded("sweep_bound_positions", [&] {
    need(instance, "the instance");
    need(out_xyz, "out_xyz");
    const_cast<sweep_instance*>(instance)->deform_moved();
    const std::span<const sweep::bind::Vec3f> bound = instance->positions->bound();
    if (!bound.empty()) std::memcpy(out_xyz, bound.data(), bound.size_bytes());
  });
}

int sweep_joint_count(const sweep_instance* instance) {
  int count = 0;
  const int code = guarded("sweep_joint_count", [&] {
    need(instance, "the instance");
    count = instance->joints->joint_count();
  });
  return code == SWEEP_OK ? count : -code;
}

int sweep_joints(const sweep_instance* instance, float* out_16xN) {
  return guarded("sweep_joints", [&] {
    need(instance, "the instance");
    need(out_16xN, "out_16xN");
    sweep_instance& in = *const_cast<sweep_instance*>(instance);
    in.pose_moved();
    const sweep::sim::BodyState body = in.simulator->body();
    in.joints->world_matrices({body.rotation, body.translation},
                              {out_16xN, static_cast<std::size_t>(16) * in.joints->joint_count()});
  });
}

int sweep_set_predictor(sweep_instance* instance, int on) {
  return guarded("sweep_set_predictor", [&] {
    usable(instance);
    if (on != 0 && on != 1) fail(ErrorCategory::usage, "on must be 0 or 1, got " + std::to_string(on));
    instance->simulator->set_midpoint_loads(on == 1);
  });
}

int sweep_set_all_modes(sweep_instance* instance, int on) {
  return guarded("sweep_set_all_modes", [&] {
    usable(instance);
    if (on != 0 && on != 1) fail(ErrorCategory::usage, "on must be 0 or 1, got " + std::to_string(on));
    instance->simulator->set_resolved_modes_only(on == 0);
  });
}

int sweep_set_skin(sweep_instance* instance, int joints_per_sweep, int ring_joints) {
  return guarded("sweep_set_skin", [&] {
    usable(instance);
    for (const sweep::SweepDef& def : instance->rig.sweeps) {
      const int stations = (def.rest.section_count() - 1) * kExportStationsPerSpan + 1;
      if (joints_per_sweep > stations)
        fail(ErrorCategory::usage, "joints_per_sweep " + std::to_string(joints_per_sweep) + " on sweep \"" + def.name +
                                       "\", which has " + std::to_string(stations) +
                                       " stations: at most one joint a station");
    }
    auto joints = std::make_unique<sweep::sim::SkinJoints>(rest_shapes(instance->rig),
                                                           sweep::sim::SkinJointLayout{joints_per_sweep, ring_joints});
    instance->joints = std::move(joints);
    std::fill(instance->joints_due.begin(), instance->joints_due.end(), 1);
  });
}

}  // extern "C"
