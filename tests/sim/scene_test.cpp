// Scene defaults that depend on the rig.
#include <gtest/gtest.h>

#include "core/sample_sweeps.h"
#include "io/json_reader.h"
#include "io/scene_json.h"
#include "sim/scene.h"

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

}  // namespace
}  // namespace sweep::sim
