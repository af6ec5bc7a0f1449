#pragma once
// A whole bake: simulate a scene on a rig, deform the bound vertices every frame, and stream the
// frames to one or more writers (.glb, .pc2, .obj). What sweep-sim runs; no console I/O here
// (progress goes to a callback).
//
// Per frame: advance the simulator; re-deform only the sweeps whose shape changed (a sweep no force
// reaches, or one asleep, keeps its last positions); hand all positions to every writer. Unbound
// vertices are copied from the rest mesh once, at the start.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sweep/assets/bake.h"
#include "sweep/assets/bake_skin.h"
#include "sweep/assets/edge_stretch.h"
#include "sweep/assets/skinned_clip.h"
#include "sweep/bind/bind.h"
#include "sweep/core/held_rest.h"
#include "sweep/core/mesh.h"
#include "sweep/core/rig.h"
#include "sweep/core/sway.h"
#include "sweep/sim/scene.h"
#include "sweep/sim/simulator.h"

namespace sweep::io {
class Publication;  // io/atomic_file.h
}

namespace sweep::assets {

struct BakeOptions {
  std::vector<std::filesystem::path> outputs;  // chosen by extension: .glb, .pc2, .obj
  // The mesh file and which mesh of it (BakeInfo::source): a glTF source's .glb bake is that
  // document plus the bake; .pc2 and .obj frames are in the mesh's local space.
  BakeSource source;
  bool exact = false;         // the per-vertex reference path instead of the fast station path
  int stations_per_span = 8;  // fast path: stations per span (error falls as its square)
  sim::SleepSettings sleep;
  // Called after each frame is written: (frames done, frames in all).
  std::function<void(int, int)> progress;
  // Where the finished files go: with one, they are handed to it (the caller adds its report and
  // puts them all in place at once); without, each writer puts its own in place.
  io::Publication* publication = nullptr;
  // Refuse (Error(output)) before simulating when the files would take more bytes than this
  // (estimated by the writers); 0: no limit.
  std::uint64_t max_output_bytes = 0;
  // > 0: every .glb output is a skinned glTF with this many joints a sweep (bake_skin.h; with
  // skinned, joints added to the character's skeleton) instead of morph targets; the other outputs are as ever.
  // kMinSkinJoints … kMaxSkinJoints, and at most a sweep's station count (check_skin_joints), else Error(usage) before
  // anything is written.
  int joints = 0;
  // With joints: the ring joints at each station (1: none) and how they are keyed (skin_fit.h).
  int ring_joints = 1;
  RingMotion ring_motion = RingMotion::scale;
  bool ring_fit = false;
  // A skinned mesh's clip drives the bake (assets/skinned_clip.h): each sweep is simulated on its
  // root joint's motion (a simulator of its own, the scene's forces on it kept), the preroll's
  // frames first, and the writers get world positions; a .glb is the input asset whole with the
  // parts' motion as joints added to its skeleton (with joints: their layout; character_joints.h)
  // or, with morph, as morph targets under its skin (gltf_passthrough.h).
  const SkinnedClip* skinned = nullptr;
  // With skinned: the .glb's parts' motion as morph targets under the skin (joints must be 0).
  // Without skinned: Error(usage).
  bool morph = false;
  // With skinned: .pc2 and .obj frames hold each vertex before skinning (the mesh's bind space,
  // its POSITION where no part moves it): skinning them by the clip gives the bake. Without
  // skinned: Error(usage).
  bool under_skin = false;
  // Told what a person should know before a long bake (a .glb too large for engines to load), and
  // during it (a teleport that carried a part through a world collider, Simulator::skipped_colliders).
  std::function<void(const std::string&)> warn;
};

struct FrameStats {
  double time = 0;              // s
  double max_displacement = 0;  // largest distance of any vertex from its rest position, mesh units
  int awake_sweeps = 0;         // sweeps stepped during this frame
  double edge_stretch = 1;      // largest edge length / rest length this frame (EdgeStretchMeter)
};

struct SweepBakeStats {
  std::string name;
  bool driven = false;      // some force reaches it (else never stepped nor deformed)
  long long steps = 0;      // internal steps taken
  int frames_deformed = 0;  // frames in which its vertices were rebuilt
  std::size_t bound_vertex_count = 0;
  // Fast path: work blocks, and those computed straight into the mesh because the mesh's vertex
  // order keeps them contiguous (ring order; FastDeformer) — the fastest case. 0 with --exact.
  std::size_t work_blocks = 0, blocks_in_place = 0;
  // What its settings give (core/sway.h): first sway frequencies and droop under the scene's
  // gravity (in the body's axes at the start).
  SwayFigures sway;
  // Over the frames it was deformed in (core/fold_check.h): the largest bend of one span (rad),
  // its span and first frame; the first frame a span folded past 90° (−1: none) and the first
  // frame two of its sections' discs crossed (−1: none), with the sections.
  double largest_bend = 0;
  int bend_span = 0, bend_frame = 0;
  int fold_frame = -1, fold_span = 0;
  int cross_frame = -1, cross_a = 0, cross_b = 0;
  // Material mode: the largest rotation of a section against its rest pose, in the root's axes,
  // over the frames it was deformed in (rad); and when the automatic dynamics turned it to the
  // exact chain (s, the bake's time; < 0: never) and that rotation there (rad).
  double largest_rotation = 0;
  double exact_chain_time = -1, exact_chain_angle = 0;
  // Material mode under gravity: whether its as-modelled rest holds (core/held_rest.h; empty when
  // the scene starts it unloaded), and whether it started from that rest (else unloaded).
  std::optional<HeldRest> held_rest;
  bool as_modelled = false;
};

struct BakeReport {
  int frames = 0;
  double fps = 0;
  double step_seconds = 0;  // the internal step, s
  std::vector<FrameStats> per_frame;
  std::vector<SweepBakeStats> sweeps;
  double simulate_seconds = 0;               // wall time stepping springs
  double deform_seconds = 0;                 // wall time rebuilding vertices
  double write_seconds = 0;                  // wall time in the writers
  std::vector<std::filesystem::path> files;  // every file written
  std::vector<double> teleport_times;        // s: frames where the body jumped and the parts were put to rest
  // The bake's quality figure: the largest edge stretch over all frames and edges, the edge, and
  // the first frame where it was reached (0 when no edge stretched).
  EdgeStretch max_stretch;
  int max_stretch_frame = 0;
  std::size_t stretch_edge_count = 0;  // edges measured (those with an animated end)
  double stretch_seconds = 0;          // wall time measuring them (inside deform_seconds)
  // With joints: the skin's joints (the body joint included) and the skinned result's error
  // against the bake's positions (the first skinned .glb's; all are the same).
  int skin_joints = 0;
  SkinError skin_error;
  // The joints were added to a skinned character's own skeleton (skin_joints counts the new ones).
  bool skin_in_character = false;
};

// Runs the bake. `binding` must match `mesh` and `rig` (io::check_binding). Throws Error: bad
// options (usage), divergence (diverged), unwritable outputs (output). On any error no output file
// is left under its final name.
BakeReport run_bake(const Mesh& mesh, const Rig& rig, const bind::Binding& binding, const sim::Scene& scene,
                    const BakeOptions& options);

}  // namespace sweep::assets
