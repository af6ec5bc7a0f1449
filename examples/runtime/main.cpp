// The sweep runtime as a game uses it: load a rig, its binding and a scene once; then each frame
// step the simulation and deform the mesh's vertices. Only the runtime library (sweep::runtime:
// Eigen, nlohmann-json, OpenMP) is linked: no CGAL, assimp or tinygltf.
//
//   sweep-runtime-example RIG BINDING MESH.obj [SCENE] [-o LAST_FRAME.f32]
//
// MESH.obj stands for the engine's own mesh: only its `v` lines are read, in file order (the
// binding checks that they are the positions it was made for). The scene defaults to the rig's
// own. It prints the largest displacement every few frames and can write the last frame's
// positions as raw little-endian float32 x y z, the layout of a .pc2 frame.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "sweep/bind/fast_deform.h"
#include "sweep/core/error.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/simulator.h"

namespace {

// The engine's vertex positions (here: the `v` lines of an OBJ, in order).
std::vector<sweep::Vec3> engine_positions(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<sweep::Vec3> positions;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    double x, y, z;
    if (s >> tag && tag == "v" && s >> x >> y >> z) positions.emplace_back(x, y, z);
  }
  return positions;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string dump;
  if (auto o = std::find(args.begin(), args.end(), "-o"); o != args.end() && o + 1 != args.end()) {
    dump = *(o + 1);
    args.erase(o, o + 2);
  }
  if (args.size() < 3 || args.size() > 4) {
    std::fprintf(stderr, "usage: %s RIG BINDING MESH.obj [SCENE] [-o LAST_FRAME.f32]\n", argv[0]);
    return 1;
  }
  try {
    using namespace sweep;
    // Once, at load time.
    const Rig rig = io::read_rig(args[0]);
    Mesh mesh;
    mesh.positions = engine_positions(args[2]);
    const bind::Binding binding = io::load_binding(args[1], mesh, rig);  // refuses a stale one
    const sim::Scene scene = io::read_scene(args.size() == 4 ? args[3] : args[0], rig);
    sim::Simulator simulator(rig, scene);
    std::vector<bind::Vec3f> rest(mesh.positions.size()), positions;
    for (std::size_t v = 0; v < rest.size(); ++v) rest[v] = mesh.positions[v].cast<float>();
    positions = rest;
    std::vector<std::unique_ptr<bind::FastDeformer>> deformers;
    for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
      deformers.push_back(std::make_unique<bind::FastDeformer>(rig.sweeps[i].rest, binding.sweeps[i], rest));
    }

    // Every frame: step, then deform the sweeps that moved (asleep or undriven ones cost nothing).
    std::vector<bind::DeformJob> jobs;
    for (int frame = 1; frame < scene.frame_count(); ++frame) {
      simulator.advance_frame();
      jobs.clear();
      for (int i = 0; i < simulator.sweep_count(); ++i) {
        if (simulator.moved_last_frame(i)) jobs.push_back({deformers[i].get(), &simulator.sweep(i).deformed()});
      }
      bind::deform_sweeps(jobs, positions);  // `positions` is what the engine uploads
      if (frame % 10 == 0 || frame + 1 == scene.frame_count()) {
        float largest = 0;
        for (std::size_t v = 0; v < rest.size(); ++v) largest = std::max(largest, (positions[v] - rest[v]).norm());
        std::printf("frame %d  t = %.3f s  largest displacement %.6g\n", frame, simulator.time(), largest);
      }
    }
    if (!dump.empty()) {
      std::ofstream out(dump, std::ios::binary);
      for (const bind::Vec3f& p : positions) out.write(reinterpret_cast<const char*>(p.data()), 3 * sizeof(float));
      if (!out) throw std::runtime_error(dump + ": cannot write");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
