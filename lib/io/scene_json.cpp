#include "sweep/io/scene_json.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sweep/core/error.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/read_file.h"
#include "sweep/io/scene_authoring_detail.h"

namespace sweep::io {
namespace {

using io::element;
using io::Json;
using io::member;

std::uint8_t read_components(const io::JsonReader& r, const Json& v, const std::string& ptr) {
  r.array(v, ptr);
  std::uint8_t mask = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string name = r.string(v[i], element(ptr, i));
    if (name == "rotational") {
      mask |= kRotational;
    } else if (name == "radial") {
      mask |= kRadial;
    } else if (name == "positional") {
      mask |= kPositional;
    } else {
      r.fail_at(element(ptr, i), "unknown component \"" + name + "\" (expected rotational, radial or positional)");
    }
  }
  if (mask == 0) r.fail_at(ptr, "must name at least one component");
  return mask;
}

sim::SceneForce read_force(const io::JsonReader& r, const Json& v, const std::string& ptr, const Rig& rig) {
  r.object(v, ptr,
           {"sweep", "point", "t", "theta", "vector", "frame", "start", "end", "components", "sections", "moment"});
  sim::SceneForce f;
  f.sweep = r.string(r.required(v, ptr, "sweep"), member(ptr, "sweep"));
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    if (rig.sweeps[i].name == f.sweep) f.sweep_index = static_cast<int>(i);
  }
  if (f.sweep_index < 0) r.fail_at(member(ptr, "sweep"), "the rig has no sweep named \"" + f.sweep + "\"");
  const SweepDef& def = rig.sweeps[f.sweep_index];

  const Json* point = r.optional(v, "point");
  const Json* t = r.optional(v, "t");
  const Json* theta = r.optional(v, "theta");
  if (point && (t || theta)) r.fail_at(ptr, "give either \"point\" or \"t\" and \"theta\", not both");
  if (point) {
    f.spec.at_world_point = true;
    f.spec.point = r.bounded_vec3(*point, member(ptr, "point"), limits::kMaxLength);
  } else {
    if (!t || !theta) r.fail_at(ptr, "missing the place: \"point\", or \"t\" and \"theta\"");
    const double frac = r.number(*t, member(ptr, "t"));
    if (frac < 0 || frac > 1)
      r.fail_at(member(ptr, "t"), "must be between 0 (root) and 1 (tip), got " + io::describe(*t));
    f.spec.t = frac * def.rest.length();
    f.spec.theta = r.number(*theta, member(ptr, "theta"));
  }
  f.spec.vector = r.vec3(r.required(v, ptr, "vector"), member(ptr, "vector"));
  if (!(f.spec.vector.norm() <= limits::kMaxForce)) {
    r.fail_at(member(ptr, "vector"), "a force of at most " + format_number(limits::kMaxForce) +
                                         " N, got one of length " + format_number(f.spec.vector.norm()));
  }
  if (const Json* fr = r.optional(v, "frame")) {
    const std::string name = r.string(*fr, member(ptr, "frame"));
    if (name == "world") {
      f.spec.frame = VectorFrame::world;
    } else if (name == "surface") {
      f.spec.frame = VectorFrame::surface;
    } else {
      r.fail_at(member(ptr, "frame"), "must be \"world\" or \"surface\", got " + io::describe(*fr));
    }
  }
  f.start = r.bounded(r.required(v, ptr, "start"), member(ptr, "start"), 0, limits::kMaxTime);
  f.end = f.start;
  if (const Json* e = r.optional(v, "end"))
    f.end = r.bounded(*e, member(ptr, "end"), -limits::kMaxTime, limits::kMaxTime);
  if (f.end < f.start) r.fail_at(member(ptr, "end"), "must not be before \"start\"");
  if (const Json* c = r.optional(v, "components"))
    f.spec.components = read_components(r, *c, member(ptr, "components"));
  if (const Json* s = r.optional(v, "sections")) {
    const std::string sp = member(ptr, "sections");
    if (s->is_number_integer()) {
      f.spec.target = RotationTarget::section;
      f.spec.target_section = static_cast<int>(r.integer(*s, sp, 1, def.rest.section_count() - 1));
    } else {
      const std::string name = r.string(*s, sp);
      if (name == "nearest") {
        f.spec.target = RotationTarget::nearest;
      } else if (name == "chain") {
        f.spec.target = RotationTarget::chain;
      } else {
        const int i = def.section_index(name);
        if (i < 0)
          r.fail_at(sp, "expected \"nearest\", \"chain\", or a section of sweep \"" + def.name +
                            "\"; it has no section \"" + name + "\"");
        if (i == 0) r.fail_at(sp, "section \"" + name + "\" is the root, which is fixed to the body");
        f.spec.target = RotationTarget::section;
        f.spec.target_section = i;
      }
    }
  }
  // A material-mode sweep is in newtons and metres: its moments are the real ones unless the
  // scene asks for the paper's scaled torque.
  if (def.material) f.spec.moment = MomentModel::physical;
  if (const Json* m = r.optional(v, "moment")) {
    const std::string name = r.string(*m, member(ptr, "moment"));
    if (name == "scaled") {
      f.spec.moment = MomentModel::scaled;
    } else if (name == "physical") {
      f.spec.moment = MomentModel::physical;
    } else {
      r.fail_at(member(ptr, "moment"), "must be \"scaled\" or \"physical\", got " + io::describe(*m));
    }
  }
  return f;
}

// A rotation as a unit quaternion [x, y, z, w]. Hand-written quaternions carry a few digits: near
// unit is taken as meant, and normalized.
Quat read_hand_written_rotation(const io::JsonReader& r, const Json& q, const std::string& ptr) {
  if (!q.is_array() || q.size() != 4) r.fail_at(ptr, "must be a quaternion [x, y, z, w], got " + io::describe(q));
  double c[4];
  for (int i = 0; i < 4; ++i) c[i] = r.number(q[i], element(ptr, i));
  Quat rotation(c[3], c[0], c[1], c[2]);
  if (std::abs(rotation.norm() - 1.0) > 1e-3)
    r.fail_at(ptr, "must be a unit quaternion [x, y, z, w], its length is " + format_number(rotation.norm(), 6));
  return rotation.normalized();
}

// The body's path: {"interpolation": "linear" | "cubic", "keys": [{"time", "translation",
// "rotation" | "turn_degrees" (+ "turn_axis")}, ...]} (or {"node", "animation"}: parse_scene).
sim::BodyPath read_body(const io::JsonReader& r, const Json& v, const std::string& ptr) {
  r.object(v, ptr, {"interpolation", "keys"});
  sim::BodyInterpolation interpolation = sim::BodyInterpolation::linear;
  if (const Json* i = r.optional(v, "interpolation")) {
    const std::string name = r.string(*i, member(ptr, "interpolation"));
    if (name == "cubic") {
      interpolation = sim::BodyInterpolation::cubic;
    } else if (name != "linear") {
      r.fail_at(member(ptr, "interpolation"), "must be \"linear\" or \"cubic\", got " + io::describe(*i));
    }
  }
  const std::string kp = member(ptr, "keys");
  const Json& keys = r.required(v, ptr, "keys");
  r.array(keys, kp);
  if (keys.empty()) r.fail_at(kp, "needs at least one key");
  std::vector<sim::BodyKey> out;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::string p = element(kp, k);
    const Json& key = keys[k];
    r.object(key, p, {"time", "translation", "rotation", "turn_degrees", "turn_axis"});
    sim::BodyKey b;
    b.time = r.bounded(r.required(key, p, "time"), member(p, "time"), 0, limits::kMaxDuration);
    if (!out.empty() && !(b.time > out.back().time))
      r.fail_at(member(p, "time"),
                "keys must come in increasing time: " + io::describe(key["time"]) + " is not after the key before");
    if (const Json* t = r.optional(key, "translation"))
      b.translation = r.bounded_vec3(*t, member(p, "translation"), limits::kMaxLength);
    const Json* q = r.optional(key, "rotation");
    const Json* turn = r.optional(key, "turn_degrees");
    if (q && turn) r.fail_at(p, "give either \"rotation\" or \"turn_degrees\", not both");
    if (!turn && r.optional(key, "turn_axis")) r.fail_at(member(p, "turn_axis"), "goes with \"turn_degrees\"");
    if (q) b.rotation = read_hand_written_rotation(r, *q, member(p, "rotation"));
    if (turn) {
      const double degrees = r.bounded(*turn, member(p, "turn_degrees"), -1e6, 1e6);
      Vec3 axis = Vec3::UnitY();
      if (const Json* a = r.optional(key, "turn_axis"))
        axis = r.bounded_vec3(*a, member(p, "turn_axis"), limits::kMaxLength);
      if (!(axis.norm() > 0)) r.fail_at(member(p, "turn_axis"), "must not be zero");
      b.rotation = Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()));
    }
    out.push_back(b);
  }
  return sim::BodyPath(std::move(out), interpolation);
}

// A collider's "margin" (clearance the part keeps, mesh units) and "friction" (Coulomb), when given.
void read_surface(const io::JsonReader& r, const Json& v, const std::string& ptr, double& margin, double& friction) {
  if (const Json* m = r.optional(v, "margin")) margin = r.bounded(*m, member(ptr, "margin"), 0, limits::kMaxLength);
  if (const Json* f = r.optional(v, "friction")) friction = r.bounded(*f, member(ptr, "friction"), 0, 100);
}

// One collider: {"shape": "sphere" | "capsule" | "box" | "plane", its sizes, "attached":
// "world" | "body", "margin", "friction", "name"}.
sim::Collider read_collider(const io::JsonReader& r, const Json& v, const std::string& ptr, std::size_t index) {
  r.object(v, ptr,
           {"name", "shape", "center", "radius", "from", "to", "half_size", "rotation", "point", "normal", "attached",
            "margin", "friction"});
  const std::string sp = member(ptr, "shape");
  const std::string shape = r.string(r.required(v, ptr, "shape"), sp);
  const auto position = [&](const char* key) {
    return r.bounded_vec3(r.required(v, ptr, key), member(ptr, key), limits::kMaxLength);
  };
  const auto size = [&](const char* key) {
    const double x = r.positive(r.required(v, ptr, key), member(ptr, key));
    if (x > limits::kMaxLength) r.fail_at(member(ptr, key), "must be at most 1e9 mesh units");
    return x;
  };
  const auto only = [&](std::initializer_list<const char*> keys) {
    // A member of another shape is a mistake worth stopping for: the user meant something else.
    for (const char* key : {"center", "radius", "from", "to", "half_size", "rotation", "point", "normal"}) {
      if (!v.contains(key)) continue;
      if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return std::string(k) == key; }) == keys.end())
        r.fail_at(member(ptr, key), "is not a member of a " + shape + " collider");
    }
  };
  sim::Collider c;
  if (shape == "sphere") {
    only({"center", "radius"});
    c = sim::Collider::sphere(position("center"), size("radius"));
  } else if (shape == "capsule") {
    only({"from", "to", "radius"});
    c = sim::Collider::capsule(position("from"), position("to"), size("radius"));
  } else if (shape == "box") {
    only({"center", "half_size", "rotation"});
    const Vec3 half = r.bounded_vec3(r.required(v, ptr, "half_size"), member(ptr, "half_size"), limits::kMaxLength);
    if (!(half.minCoeff() > 0))
      r.fail_at(member(ptr, "half_size"), "every half size must be positive (a plate is a thin box, not a flat one)");
    Quat rotation = Quat::Identity();
    if (const Json* q = r.optional(v, "rotation"))
      rotation = read_hand_written_rotation(r, *q, member(ptr, "rotation"));
    c = sim::Collider::box(position("center"), half, rotation);
  } else if (shape == "plane") {
    only({"point", "normal"});
    const Vec3 normal = r.bounded_vec3(r.required(v, ptr, "normal"), member(ptr, "normal"), limits::kMaxLength);
    if (!(normal.norm() > 1e-12)) r.fail_at(member(ptr, "normal"), "must not be zero: it points out of the solid side");
    c = sim::Collider::plane(position("point"), normal);
  } else {
    r.fail_at(sp, "must be \"sphere\", \"capsule\", \"box\" or \"plane\", got " + io::describe(v["shape"]));
  }
  c.name = "collider " + std::to_string(index);
  if (const Json* n = r.optional(v, "name")) c.name = r.string(*n, member(ptr, "name"));
  if (const Json* a = r.optional(v, "attached")) {
    const std::string where = r.string(*a, member(ptr, "attached"));
    if (where != "world" && where != "body")
      r.fail_at(member(ptr, "attached"),
                "must be \"world\" (stays put) or \"body\" (moves with it), got " + io::describe(*a));
    c.carried = where == "body";
  }
  read_surface(r, v, ptr, c.margin, c.friction);
  return c;
}

// The body as a collider: {"spheres", "resolution", "margin", "friction"} (SceneAuthoring::BodyCollider).
SceneAuthoring::BodyCollider read_body_collider(const io::JsonReader& r, const Json& v, const std::string& ptr) {
  r.object(v, ptr, {"spheres", "resolution", "margin", "friction"});
  SceneAuthoring::BodyCollider b;
  // More spheres than this cost every frame more than they add: the body is coarse beside its parts.
  b.spheres = static_cast<int>(r.integer(r.required(v, ptr, "spheres"), member(ptr, "spheres"), 1, 256));
  // The fit samples resolution³ points at most: 200 is already 8 million, seconds of load.
  if (const Json* x = r.optional(v, "resolution"))
    b.resolution = static_cast<int>(r.integer(*x, member(ptr, "resolution"), 8, 200));
  read_surface(r, v, ptr, b.margin, b.friction);
  return b;
}

// A step's length in seconds ("step", "contact_step"), within the limits.
double step_length(const io::JsonReader& r, const Json& value, const std::string& where) {
  const double step = r.positive(value, where);
  if (step < limits::kMinStep || step > limits::kMaxStep)
    r.fail_at(where, "must be between " + format_number(limits::kMinStep) + " and " + format_number(limits::kMaxStep) +
                         " s, got " + io::describe(value));
  return step;
}

// A key that needs the mesh file, met by the runtime's reader (no `authoring` to read it into).
[[noreturn]] void refuse_authoring(const io::JsonReader& r, const std::string& where, const std::string& what,
                                   const std::string& instead) {
  fail(ErrorCategory::unsupported,
       r.source() + ": " + where + ": " + what +
           " needs the mesh file, which the runtime does not read (sweep-sim resolves it); " + instead);
}

// The scene, the authoring keys read into `authoring`, or refused without one.
sim::Scene parse_scene_keys(const Json& json, const std::string& pointer, const io::JsonReader& r, const Rig& rig,
                            SceneAuthoring* authoring) {
  r.object(
      json, pointer,
      {"format", "version", "duration", "fps", "step", "substeps", "gravity", "gravity_start", "integrator", "dynamics",
       "forces", "body", "teleport", "wind", "colliders", "body_collider", "contact_stations", "contact_step"});
  sim::Scene scene;
  const bool own_file = pointer.empty();
  if (own_file) {
    const std::string format = r.string(r.required(json, pointer, "format"), "/format");
    if (format != "sweep-scene") r.fail_at("/format", "must be \"sweep-scene\", got " + io::describe(json["format"]));
  }
  if (const Json* version = own_file ? &r.required(json, pointer, "version") : r.optional(json, "version")) {
    const long long v = r.integer(*version, member(pointer, "version"), 1, 1 << 30);
    if (v != sim::Scene::kFormatVersion) {
      fail(ErrorCategory::unsupported, r.source() + ": " + member(pointer, "version") + ": scene format version " +
                                           std::to_string(v) + " is not supported (this build reads version " +
                                           std::to_string(sim::Scene::kFormatVersion) + ")");
    }
  }
  scene.duration = r.positive(r.required(json, pointer, "duration"), member(pointer, "duration"));
  if (scene.duration > limits::kMaxDuration)
    r.fail_at(member(pointer, "duration"), "must be at most " + format_number(limits::kMaxDuration, 6) + " s");
  const Json& fps = r.required(json, pointer, "fps");
  r.positive(fps, member(pointer, "fps"));  // the sign first, with its own message
  scene.fps = r.bounded(fps, member(pointer, "fps"), limits::kMinFps, limits::kMaxFps);
  if (scene.duration * scene.fps + 1 > limits::kMaxFrames) {
    r.fail_at(member(pointer, "fps"),
              "duration × fps makes more than " + std::to_string(limits::kMaxFrames) + " frames");
  }
  if (const Json* s = r.optional(json, "substeps")) {
    scene.substeps = static_cast<int>(r.integer(*s, member(pointer, "substeps"), 1, limits::kMaxSubsteps));
  }
  if (const Json* st = r.optional(json, "step")) {
    if (r.optional(json, "substeps"))
      r.fail_at(member(pointer, "step"), "give either \"step\" or \"substeps\", not both");
    scene.step = step_length(r, *st, member(pointer, "step"));
  }
  if (const Json* g = r.optional(json, "gravity")) scene.gravity = r.vec3(*g, member(pointer, "gravity"));
  if (const Json* g = r.optional(json, "gravity_start")) {
    const std::string name = r.string(*g, member(pointer, "gravity_start"));
    if (name != "auto" && name != "as-modelled" && name != "unloaded")
      r.fail_at(member(pointer, "gravity_start"),
                "must be \"auto\", \"as-modelled\" or \"unloaded\", got " + io::describe(*g));
    scene.gravity_start = name == "auto"          ? sim::Scene::GravityStart::automatic
                          : name == "as-modelled" ? sim::Scene::GravityStart::as_modelled
                                                  : sim::Scene::GravityStart::unloaded;
  }
  if (const Json* i = r.optional(json, "integrator")) {
    const std::string name = r.string(*i, member(pointer, "integrator"));
    if (!parse_integrator(name, &scene.integrator)) {
      r.fail_at(member(pointer, "integrator"),
                "must be \"exact\", \"semi-implicit-euler\" or \"rk4\", got " + io::describe(*i));
    }
  }
  if (const Json* d = r.optional(json, "dynamics")) {
    const std::string name = r.string(*d, member(pointer, "dynamics"));
    if (name == "auto") {
      scene.dynamics = ElasticSweep::Dynamics::automatic;
    } else if (name == "modal") {
      scene.dynamics = ElasticSweep::Dynamics::modal;
    } else if (name == "exact") {
      scene.dynamics = ElasticSweep::Dynamics::exact;
    } else {
      r.fail_at(member(pointer, "dynamics"), "must be \"auto\", \"modal\" or \"exact\", got " + io::describe(*d));
    }
  }
  if (const Json* b = r.optional(json, "body")) {
    const std::string bp = member(pointer, "body");
    if (b->is_object() && b->contains("node")) {
      // The glTF mesh's own animation of a node: the tools read it from the mesh.
      if (authoring == nullptr) {
        refuse_authoring(r, member(bp, "node"), "a body that follows a glTF node's animation",
                         "give the body's pose live instead (sweep_set_body)");
      }
      SceneAuthoring& a = *authoring;
      r.object(*b, bp, {"node", "animation", "loop", "preroll"});
      a.body_node = r.string((*b)["node"], member(bp, "node"));
      if (a.body_node.empty()) r.fail_at(member(bp, "node"), "must name a node of the glTF mesh");
      if (const Json* n = r.optional(*b, "animation")) a.body_animation = r.string(*n, member(bp, "animation"));
      if (const Json* l = r.optional(*b, "loop")) {
        if (!l->is_boolean()) r.fail_at(member(bp, "loop"), "must be true or false, got " + io::describe(*l));
        a.body_loop = l->get<bool>();
      }
      if (const Json* p = r.optional(*b, "preroll")) a.body_preroll = r.bounded(*p, member(bp, "preroll"), 0, 3600);
    } else {
      scene.body = read_body(r, *b, bp);
    }
  }
  if (const Json* t = r.optional(json, "teleport")) {
    const std::string tp = member(pointer, "teleport");
    if (t->is_boolean()) {
      scene.teleport_enabled = t->get<bool>();
    } else {
      r.object(*t, tp, {"distance", "angle_degrees"});
      if (const Json* d = r.optional(*t, "distance")) scene.teleport_distance = r.positive(*d, member(tp, "distance"));
      if (const Json* a = r.optional(*t, "angle_degrees"))
        scene.teleport_angle = r.bounded(*a, member(tp, "angle_degrees"), 1e-6, 180) * std::numbers::pi / 180;
    }
  }
  if (const Json* w = r.optional(json, "wind")) {
    const std::string wp = member(pointer, "wind");
    r.object(*w, wp, {"velocity", "gust", "gust_period", "turbulence", "seed", "air_density", "drag_coefficient"});
    sim::WindSettings ws;
    ws.enabled = true;
    ws.velocity = r.bounded_vec3(r.required(*w, wp, "velocity"), member(wp, "velocity"), 1e3);
    if (const Json* x = r.optional(*w, "gust")) ws.gust = r.bounded(*x, member(wp, "gust"), 0, 10);
    if (const Json* x = r.optional(*w, "gust_period"))
      ws.gust_period = r.bounded(*x, member(wp, "gust_period"), 0.01, 1e4);
    if (const Json* x = r.optional(*w, "turbulence")) ws.turbulence = r.bounded(*x, member(wp, "turbulence"), 0, 10);
    if (const Json* x = r.optional(*w, "seed"))
      ws.seed = static_cast<std::uint64_t>(r.integer(*x, member(wp, "seed"), 0, 1LL << 53));
    if (const Json* x = r.optional(*w, "air_density"))
      ws.air_density = r.bounded(*x, member(wp, "air_density"), 0, 1e4);
    if (const Json* x = r.optional(*w, "drag_coefficient"))
      ws.drag_coefficient = r.bounded(*x, member(wp, "drag_coefficient"), 0, 100);
    scene.wind = sim::Wind(ws);
  }
  if (const Json* cs = r.optional(json, "colliders")) {
    const std::string cp = member(pointer, "colliders");
    r.array(*cs, cp);
    for (std::size_t i = 0; i < cs->size(); ++i)
      scene.colliders.push_back(read_collider(r, (*cs)[i], element(cp, i), i));
  }
  if (const Json* b = r.optional(json, "body_collider")) {
    if (authoring == nullptr) {
      refuse_authoring(r, member(pointer, "body_collider"), "the body as a collider (spheres fitted in the mesh)",
                       "give its colliders instead");
    }
    authoring->body_collider = read_body_collider(r, *b, member(pointer, "body_collider"));
  }
  if (const Json* st = r.optional(json, "contact_stations")) {
    scene.contact_stations = static_cast<int>(r.integer(*st, member(pointer, "contact_stations"), 1, 64));
  }
  if (const Json* st = r.optional(json, "contact_step"))
    scene.contact_step = step_length(r, *st, member(pointer, "contact_step"));

  const std::string fp = member(pointer, "forces");
  const Json& forces = r.required(json, pointer, "forces");
  r.array(forces, fp);
  for (std::size_t i = 0; i < forces.size(); ++i) {
    scene.forces.push_back(read_force(r, forces[i], element(fp, i), rig));
    // Legal, but surely not meant: the bake ends before the force begins.
    if (scene.forces.back().start > scene.duration) {
      r.warn_at(member(element(fp, i), "start"), "the force starts after the scene ends (duration " +
                                                     io::describe(json["duration"]) + " s): it never acts");
    }
  }
  return scene;
}

// The scene of the file at `path`, its authoring keys read into `authoring` or refused without one.
sim::Scene read_scene_file(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn,
                           SceneAuthoring* authoring) {
  const Json doc = io::parse_json_text(io::read_file(path, limits::kMaxJsonBytes), path.string());
  const io::JsonReader r(path.string(), warn);
  if (!doc.is_object()) r.fail_at("", "must be a JSON object");
  // A rig file that carries its scene. (A "format" that is not a string is reported by
  // parse_scene, with its pointer.)
  const auto format = doc.find("format");
  const bool is_rig = format != doc.end() && format->is_string() && format->get<std::string>() == "sweep-rig";
  if (is_rig && doc.contains("scene")) return parse_scene_keys(doc["scene"], "/scene", r, rig, authoring);
  if (is_rig) r.fail_at("", "this rig file has no \"scene\"; give a scene file");
  return parse_scene_keys(doc, "", r, rig, authoring);
}

}  // namespace

sim::Scene parse_scene(const Json& json, const std::string& pointer, const io::JsonReader& reader, const Rig& rig) {
  return parse_scene_keys(json, pointer, reader, rig, nullptr);
}
sim::Scene parse_scene(const Json& json, const std::string& pointer, const io::JsonReader& reader, const Rig& rig,
                       SceneAuthoring& authoring) {
  return parse_scene_keys(json, pointer, reader, rig, &authoring);
}
sim::Scene read_scene(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn) {
  return read_scene_file(path, rig, warn, nullptr);
}
sim::Scene read_scene(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn,
                      SceneAuthoring& authoring) {
  return read_scene_file(path, rig, warn, &authoring);
}

}  // namespace sweep::io
