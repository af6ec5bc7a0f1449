// Scene defaults that depend on the rig.
#include "sweep/sim/scene.h"

#include <gtest/gtest.h>

#include "core/sample_sweeps.h"
#include "sweep/core/error.h"
#include "sweep/io/json_reader.h"
#include "sweep/io/scene_authoring_detail.h"
#include "sweep/io/scene_json.h"

namespace sweep::sim {
namespace {

TEST(Scene, AMaterialSweepsForcesTakeTheRealMomentUnlessTheSceneSaysScaled) {
  // The paper's scaled torque (C_rot |f|, whatever the arm) has no meaning in newtons and metres:
  // a sweep with a material takes the moment a × f unless the scene asks otherwise.
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "springs";
  SweepDef with_material = test::sweep_def(test::straight_shape(4, 6));
  with_material.name = "material";
  with_material.material = Material{};
  with_material.section_materials.assign(4, Material{});
  rig.sweeps.push_back(with_material);
  const io::Json json = io::Json::parse(R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [
    {"sweep": "springs", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 1},
    {"sweep": "material", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 1},
    {"sweep": "material", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 1, "moment": "scaled"}]})");
  const Scene scene = parse_scene(json, "", io::JsonReader("scene.json", {}), rig);
  ASSERT_EQ(scene.forces.size(), 3u);
  EXPECT_EQ(scene.forces[0].spec.moment, MomentModel::scaled);
  EXPECT_EQ(scene.forces[1].spec.moment, MomentModel::physical);
  EXPECT_EQ(scene.forces[2].spec.moment, MomentModel::scaled);
}

// A one-tube scene with `extra` keys (", \"key\": value") after its required ones, as the runtime reads it.
Scene one_tube_scene(const std::string& extra) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "tube";
  const io::Json json = io::Json::parse(
      R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [])" + extra + "}");
  return parse_scene(json, "", io::JsonReader("scene.json", {}), rig);
}

// The message a scene is refused with ("" if it is read), by the runtime's reader or (authored) the
// tools', which reads the keys that need the mesh file.
std::string refusal(const std::string& colliders, bool authored = false) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "tube";
  const io::Json json = io::Json::parse(R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30,
    "forces": [], "colliders": )" + colliders +
                                        "}");
  try {
    io::SceneAuthoring authoring;
    if (authored)
      parse_scene(json, "", io::JsonReader("scene.json", {}), rig, authoring);
    else
      parse_scene(json, "", io::JsonReader("scene.json", {}), rig);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, CollidersAreReadWithTheirShapesAndPlaces) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "tube";
  const io::Json json = io::Json::parse(R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30,
    "forces": [], "contact_stations": 2, "contact_step": 0.001, "colliders": [
      {"name": "ball", "shape": "sphere", "center": [1, 2, 3], "radius": 0.5, "margin": 0.01, "friction": 0.2},
      {"shape": "capsule", "from": [0, 0, 0], "to": [0, 2, 0], "radius": 0.1, "attached": "body"},
      {"shape": "box", "center": [0, 0, 5], "half_size": [1, 2, 0.01], "rotation": [0, 0, 0.7071068, 0.7071068]},
      {"shape": "plane", "point": [0, -1, 0], "normal": [0, 3, 0]}]})");
  const Scene scene = parse_scene(json, "", io::JsonReader("scene.json", {}), rig);
  ASSERT_EQ(scene.colliders.size(), 4u);
  EXPECT_EQ(scene.contact_stations, 2);
  EXPECT_EQ(scene.contact_step, 0.001);
  const Collider& ball = scene.colliders[0];
  EXPECT_EQ(ball.name, "ball");
  EXPECT_EQ(ball.shape, ColliderShape::sphere);
  EXPECT_EQ(ball.pose.center, Vec3(1, 2, 3));
  EXPECT_EQ(ball.margin, 0.01);
  EXPECT_EQ(ball.friction, 0.2);
  EXPECT_FALSE(ball.carried);
  const Collider& rod = scene.colliders[1];
  EXPECT_EQ(rod.name, "collider 1");
  EXPECT_TRUE(rod.carried);
  EXPECT_EQ(rod.half_length, 1.0);
  EXPECT_NEAR((rod.pose.rotation * Vec3::UnitZ() - Vec3::UnitY()).norm(), 0, 1e-12);  // along from → to
  EXPECT_NEAR((scene.colliders[2].pose.rotation * Vec3::UnitX() - Vec3::UnitY()).norm(), 0, 1e-6);
  EXPECT_NEAR((scene.colliders[3].pose.rotation * Vec3::UnitZ() - Vec3::UnitY()).norm(), 0, 1e-12);
}

TEST(Scene, BadCollidersAreRefusedWithWhereAndWhy) {
  EXPECT_NE(refusal(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 0}])")
                .find("/colliders/0/radius: must be a positive number"),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "cone", "center": [0, 0, 0]}])")
                .find("/colliders/0/shape: must be \"sphere\", \"capsule\", \"box\" or \"plane\""),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}])")
                .find("/colliders/0/normal: must not be zero"),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "box", "center": [0, 0, 0], "half_size": [1, 0, 1]}])")
                .find("/colliders/0/half_size: every half size must be positive"),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "from": [0, 0, 0]}])")
                .find("/colliders/0/from: is not a member of a sphere collider"),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "attached": "leg"}])")
                .find("/colliders/0/attached: must be \"world\""),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "friction": -1}])")
                .find("/colliders/0/friction: must be between 0 and 100"),
            std::string::npos);
  EXPECT_NE(refusal(R"([{"shape": "capsule", "from": [0, 0, 0], "radius": 1}])")
                .find("/colliders/0: missing required member \"to\""),
            std::string::npos);
  EXPECT_NE(refusal(R"({"shape": "plane"})").find("/colliders: "), std::string::npos);
  EXPECT_EQ(refusal(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1}])"), "");
}

TEST(Scene, ABadContactStepIsRefusedWithWhereAndWhy) {
  EXPECT_NE(refusal(R"([], "contact_step": 0)").find("/contact_step: must be a positive number"), std::string::npos);
  EXPECT_NE(refusal(R"([], "contact_step": 2)").find("/contact_step: must be between 1e-06 and 1 s, got 2"),
            std::string::npos);
  EXPECT_NE(refusal(R"([], "contact_step": "fine")").find("/contact_step: "), std::string::npos);
  EXPECT_EQ(refusal(R"([], "contact_step": 0.004)"), "");
  EXPECT_EQ(Scene{}.contact_step, Scene::kDefaultContactStep);
}

// "dynamics" chooses how a material part's joints move: auto (the default: the rest-pose modes
// while the motion is small, the exact chain from when it is not), the rest-pose modes throughout
// or the exact chain throughout; anything else is refused with where and why.
TEST(Scene, DynamicsIsReadAndABadOneIsRefusedWithWhereAndWhy) {
  const auto read = [](const std::string& extra) { return one_tube_scene(extra); };
  using Joints = ElasticSweep::Dynamics;
  EXPECT_EQ(read("").dynamics, Joints::automatic);
  EXPECT_EQ(Scene{}.dynamics, Joints::automatic);
  EXPECT_EQ(read(R"(, "dynamics": "auto")").dynamics, Joints::automatic);
  EXPECT_EQ(read(R"(, "dynamics": "exact")").dynamics, Joints::exact);
  EXPECT_EQ(read(R"(, "dynamics": "modal")").dynamics, Joints::modal);
  EXPECT_NE(
      refusal(R"([], "dynamics": "rigid")").find("/dynamics: must be \"auto\", \"modal\" or \"exact\", got \"rigid\""),
      std::string::npos);
}

// "gravity_start": auto (the default: as modelled where that pose holds, unloaded where it does
// not), as-modelled or unloaded; anything else is refused with where and why.
TEST(Scene, GravityStartIsReadAndABadOneIsRefusedWithWhereAndWhy) {
  const auto read = [](const std::string& extra) { return one_tube_scene(extra).gravity_start; };
  using Start = Scene::GravityStart;
  EXPECT_EQ(read(""), Start::automatic);
  EXPECT_EQ(Scene{}.gravity_start, Start::automatic);
  EXPECT_EQ(read(R"(, "gravity_start": "auto")"), Start::automatic);
  EXPECT_EQ(read(R"(, "gravity_start": "as-modelled")"), Start::as_modelled);
  EXPECT_EQ(read(R"(, "gravity_start": "unloaded")"), Start::unloaded);
  EXPECT_NE(refusal(R"([], "gravity_start": "held")")
                .find("/gravity_start: must be \"auto\", \"as-modelled\" or \"unloaded\", got \"held\""),
            std::string::npos);
}

// A skinned mesh's clip: "loop" and "preroll" are read beside "node" and "animation", and bad ones
// refused with where and why.
TEST(Scene, ASkinnedClipsLoopAndPrerollAreRead) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "tube";
  auto read = [&](const std::string& body) {
    const io::Json json = io::Json::parse(R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30,
      "forces": [], "body": )" + body + "}");
    io::SceneAuthoring authoring;
    const Scene scene = parse_scene(json, "", io::JsonReader("scene.json", {}), rig, authoring);
    EXPECT_TRUE(scene.body.empty());  // the tools fill it from the mesh
    return authoring;
  };
  const io::SceneAuthoring scene = read(R"({"node": "Hip", "animation": "Walk", "loop": true, "preroll": 1.5})");
  EXPECT_EQ(scene.body_node, "Hip");
  EXPECT_EQ(scene.body_animation, "Walk");
  EXPECT_TRUE(scene.body_loop);
  EXPECT_EQ(scene.body_preroll, 1.5);
  const io::SceneAuthoring plain = read(R"({"node": "Hip"})");
  EXPECT_FALSE(plain.body_loop);
  EXPECT_EQ(plain.body_preroll, 0);
  auto refused = [&](const std::string& body) {
    try {
      read(body);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(R"({"node": "Hip", "loop": 1})").find("/body/loop: must be true or false"), std::string::npos);
  EXPECT_NE(refused(R"({"node": "Hip", "preroll": -1})").find("/body/preroll: "), std::string::npos);
}

// The message a scene with this "body_collider" is refused with by the tools' reader ("" if it is read).
std::string body_refusal(const std::string& body) {
  return refusal(R"([], "body_collider": )" + body, true);
}

TEST(Scene, TheBodyColliderIsReadAndBadOnesAreRefusedWithWhereAndWhy) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
  rig.sweeps.back().name = "tube";
  const io::Json json = io::Json::parse(R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30,
    "forces": [], "body_collider": {"spheres": 12, "resolution": 32, "margin": 0.01, "friction": 0.25}})");
  io::SceneAuthoring authoring;
  const Scene scene = parse_scene(json, "", io::JsonReader("scene.json", {}), rig, authoring);
  EXPECT_EQ(authoring.body_collider.spheres, 12);
  EXPECT_EQ(authoring.body_collider.resolution, 32);
  EXPECT_EQ(authoring.body_collider.margin, 0.01);
  EXPECT_EQ(authoring.body_collider.friction, 0.25);
  EXPECT_TRUE(scene.colliders.empty());  // the tools fit the spheres, as they read the mesh
  EXPECT_EQ(body_refusal(R"({"spheres": 8})"), "");
  EXPECT_NE(body_refusal(R"({"resolution": 8})").find("/body_collider: missing required member \"spheres\""),
            std::string::npos);
  EXPECT_NE(body_refusal(R"({"spheres": 1000})").find("/body_collider/spheres: must be between 1 and 256"),
            std::string::npos);
  EXPECT_NE(
      body_refusal(R"({"spheres": 8, "resolution": 2})").find("/body_collider/resolution: must be between 8 and 200"),
      std::string::npos);
  EXPECT_NE(body_refusal(R"({"spheres": 8, "margin": -1})").find("/body_collider/margin: must be between 0 and"),
            std::string::npos);
  EXPECT_NE(
      body_refusal(R"({"spheres": 8, "friction": 101})").find("/body_collider/friction: must be between 0 and 100"),
      std::string::npos);
  EXPECT_NE(body_refusal("true").find("/body_collider: "), std::string::npos);
}

// The runtime runs a scene as it is: the keys that need the mesh file are refused by its reader,
// as unsupported (exit-code category 3), naming the file and the key; the tools' reader takes them.
TEST(Scene, TheRuntimesReaderRefusesWhatNeedsTheMeshFile) {
  const auto category = [](const std::string& tail) {
    Rig rig;
    rig.sweeps.push_back(test::sweep_def(test::straight_shape(4, 6)));
    rig.sweeps.back().name = "tube";
    const io::Json json = io::Json::parse(
        R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [], )" + tail + "}");
    try {
      parse_scene(json, "", io::JsonReader("scene.json", {}), rig);
    } catch (const Error& e) {
      return std::pair(e.category(), std::string(e.what()));
    }
    return std::pair(ErrorCategory::usage, std::string());
  };
  const auto [node, node_text] = category(R"("body": {"node": "Hip"})");
  EXPECT_EQ(node, ErrorCategory::unsupported);
  EXPECT_EQ(node_text.find("scene.json: /body/node: a body that follows a glTF node's animation needs the mesh file"),
            0u)
      << node_text;
  const auto [proxy, proxy_text] = category(R"("body_collider": {"spheres": 8})");
  EXPECT_EQ(proxy, ErrorCategory::unsupported);
  EXPECT_EQ(proxy_text.find("scene.json: /body_collider: the body as a collider"), 0u) << proxy_text;
  EXPECT_EQ(refusal(R"([], "body_collider": {"spheres": 8})", true), "");
}

}  // namespace
}  // namespace sweep::sim
