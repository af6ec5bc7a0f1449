#pragma once
// Bake writers: stream a baked animation (one set of vertex positions per frame) to the files that
// Blender, game engines and pipeline scripts open. A writer is chosen by the output's extension:
//
//  - `.glb`  glTF 2.0 binary: the rest mesh (triangulated by fanning each polygon, POSITION with
//            min/max, smooth rest NORMALs, uint32 indices), one morph target per frame holding
//            deltas from the rest (named "frame_0000", ... in the mesh's extras.targetNames), and
//            one animation of the morph weights: keys at k/fps, one-hot weights (frame k → target k
//            at 1), LINEAR, so playing it shows the bake. Coordinates are written as they are,
//            with no axis conversion: glTF is Y-up, so a Z-up mesh lies on its back in a Y-up
//            viewer, and Blender's importer (which maps glTF (x, y, z) to its (x, -z, y)) shows
//            it turned the same way. Vertex order and count are the mesh's.
//            When an animated-vertex list is given and smaller than the mesh, targets are SPARSE:
//            all of them share one ascending index list and store a delta per listed vertex.
//            A delta is the float32 difference, correctly rounded, so rest + delta (what a viewer
//            computes at weight 1) is the baked float exactly whenever the delta is no larger than
//            the baked coordinate (a float delta can do no better: otherwise the error is within
//            half a unit in the last place of the delta). Each target also holds NORMAL deltas
//            (the frame's smooth normals, made as the rest's are, minus the rest's; sparse over
//            the moving vertices and their face neighbours), so a bent part is lit as bent.
//            A glTF/GLB source (BakeInfo::source) is written instead as that document whole plus
//            the targets and a new animation (assets/gltf_passthrough.h). The weights animation stores frames² floats
//            (600 frames: 1.4 MB); glTF binary files are limited to 4 GiB, checked in begin().
//            A skinned .glb (joints following the sweeps, no morph targets) is another writer:
//            assets/bake_skin.h (sweep-sim --joints N).
//  - `.pc2`  point cache (Blender's Mesh Cache modifier, 3ds Max, Houdini): "POINTCACHE2\0",
//            int32 version 1, int32 points, float32 start frame 0, float32 sample rate 1, int32
//            samples, then float32 x y z per point per sample, little-endian, in the mesh's
//            vertex order and its local space (BakeSource::to_world).
//  - `.obj`  a numbered sequence, one file a frame: `out.obj` → `out_0000.obj`, `out_0001.obj`,
//            ... (4 digits, more when the frame count needs them; every file of a sequence has
//            the same width). Each holds `v` lines in vertex order (shortest round-trippable
//            float32 text) and the mesh's polygons as they are. Files of an earlier, longer
//            sequence with the same name are not removed.
//
// Every writer is atomic and deterministic: files are written to temporaries beside the target
// and renamed into place only in finish(), so a failure, an exception or a writer destroyed
// without finish() leaves neither a partial file under a final name nor a temporary. The bytes
// depend only on the mesh, the BakeInfo and the frames (not on the output's name or the time).
//
// Errors: a file that cannot be written → Error(output, "<path>: ..."); a non-finite position in
// frame() → Error(diverged) naming the frame and vertex (nothing is written, ever, with NaN or
// Inf); a mesh a format cannot hold (no vertices, glTF without faces or over 4 GiB, a coordinate
// beyond float32) → Error(unsupported or bad_input); a caller breaking the protocol below (frames
// out of order or missing, a listed-static vertex that moved, wrong vertex count) →
// Error(internal). After any error the writer is closed: it has removed its temporaries and
// refuses further calls.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sweep/core/mesh.h"

namespace sweep::assets {

class SkinnedClip;      // assets/skinned_clip.h
class CharacterJoints;  // assets/character_joints.h

// The mesh a bake deforms, as read from its file (assets/mesh_io.h: read_scene_mesh).
struct BakeSource {
  // The file (empty: unknown). A .gltf or .glb makes the .glb writer write that document whole
  // plus the bake (assets/gltf_passthrough.h), as does an .obj with a surface to carry, any other
  // format assimp reads but PLY and STL (every mesh of the file, obj_gltf.h's scene_as_gltf) and a
  // skinned character of any format assimp reads (made a glTF character, skin_gltf.h); any
  // other source (OFF, PLY, STL, a plain OBJ) gets the .glb described above.
  std::filesystem::path path;
  std::string mesh_name;  // the mesh of the file ("" = the whole file: every mesh in it)
  // The importer meshes it is made of, in order (for a glTF, its primitives counted over the
  // file's meshes in order: which primitives the passthrough deforms); empty = all of them.
  std::vector<unsigned> parts;
  // Its local space → world. The bake runs in world space; .pc2 and .obj frames are written in
  // local space (this transform's inverse applied), so that they fit the object as Blender
  // imports it. Identity (the whole file, a format without nodes): written as they are.
  Eigen::Affine3d to_world = Eigen::Affine3d::Identity();
};

struct BakeInfo {
  // Frames that frame() will receive, numbered 0 .. frame_count-1; at least 1.
  int frame_count = 0;
  // Frames per second (> 0). Frame k is at time k / fps seconds; frame 0 is time 0.
  double fps = 24.0;
  // The vertices that may move (indices into the mesh, any order; duplicates are ignored), or
  // nullopt when any vertex may. Every other vertex must equal its rest position in every frame
  // (checked). The glTF writer stores only these vertices' deltas; the OBJ writer formats only
  // these vertices' numbers each frame.
  std::optional<std::vector<std::uint32_t>> animated_vertices;
  // Name of the glTF node and mesh (Blender's object name). Not used by the other formats.
  std::string name = "sweep_bake";
  // Whether the body moves: each frame then comes with the body's pose. The .pc2 and
  // .obj writers write world positions (pose applied; then in the mesh's local space); the .glb writer keeps the
  // deformation in the body's frame (morph targets) and animates its node's translation and rotation (LINEAR: slerp),
  // so engines play both. Without it every pose must be the identity.
  bool body_moves = false;
  // The mesh file the bake deforms and which mesh of it (BakeSource).
  BakeSource source;
  // Where a writer says what it repaired in the source (normals recomputed, a missing texture
  // left out); none: said nowhere.
  std::function<void(const std::string&)> warn;
  // A skinned character's clip drove the bake (assets/skinned_clip.h): frame k is its pose at
  // scene time k / fps, and the frames are world positions (every vertex may move). The .glb
  // writer then keeps the skin and writes the parts' motion under it (gltf_passthrough.h);
  // `part_vertices` (ascending) are the vertices the parts move off their skinned pose.
  const SkinnedClip* skinned = nullptr;
  std::vector<std::uint32_t> part_vertices;
  // With skinned: the parts' motion as joints added to the character's skeleton, posed by the
  // bake driver before each frame (its keys read when the .glb is finished), instead of morph
  // targets under the skin.
  const CharacterJoints* character_joints = nullptr;
};

// The body's pose for one frame: world = rotation · position + translation.
struct BodyPose {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// A streaming bake: begin() once, frame() for k = 0, 1, ..., frame_count-1 in that order, then
// finish(), which puts the files in place. Nothing keeps all frames in memory (the glTF writer
// streams its binary chunk through an unnamed scratch file beside the output).
}  // namespace sweep::assets
namespace sweep::io {
class Publication;
}
namespace sweep::assets {

class BakeWriter {
 public:
  virtual ~BakeWriter() = default;
  BakeWriter() = default;
  BakeWriter(const BakeWriter&) = delete;
  BakeWriter& operator=(const BakeWriter&) = delete;

  // `rest` is the mesh as read (vertex order kept; its double positions are stored as float32).
  virtual void begin(const Mesh& rest, const BakeInfo& info) = 0;
  // Positions of all vertices in the mesh's vertex order for frame `index`, in the body's frame,
  // and the body's pose at that frame.
  virtual void frame(int index, std::span<const Eigen::Vector3f> positions, const BodyPose& body) = 0;
  void frame(int index, std::span<const Eigen::Vector3f> positions) { frame(index, positions, BodyPose{}); }
  // Writes what is left and renames every file into place.
  virtual void finish() = 0;
  // Writes what is left into sealed temporaries and hands them to `outputs`, which puts them in
  // place with the run's other outputs (all or nothing: io/atomic_file.h).
  virtual void finish_into(io::Publication& outputs) = 0;
  // About how many bytes the finished files will take (after begin(): from the mesh, the frame
  // count and the moving vertices), for a warning or a refusal before the bake starts.
  virtual std::uint64_t estimated_bytes() const = 0;
  // The morph targets a .glb will hold (0 for other formats).
  virtual int morph_targets() const { return 0; }
  // The final paths this bake writes (known after begin(); they exist after finish()).
  virtual std::vector<std::filesystem::path> files() const = 0;
};

// Chooses the writer by `out`'s extension (.glb, .pc2, .obj; case-insensitive). Anything else:
// Error(unsupported). Does not touch the file system.
std::unique_ptr<BakeWriter> make_bake_writer(const std::filesystem::path& out);
bool is_bake_extension(const std::filesystem::path& out);

// The writers themselves, for a caller that picks the format another way.
std::unique_ptr<BakeWriter> make_gltf_bake_writer(const std::filesystem::path& out);
std::unique_ptr<BakeWriter> make_pc2_bake_writer(const std::filesystem::path& out);
std::unique_ptr<BakeWriter> make_obj_bake_writer(const std::filesystem::path& out);

// The file name of frame `index` in an OBJ sequence of `frame_count` frames for `out`
// ("dir/out.obj", 3, 120 → "dir/out_0003.obj").
std::filesystem::path obj_sequence_path(const std::filesystem::path& out, int index, int frame_count);
// The final paths a bake to `out` writes: `out` itself, or for .obj every frame's file.
std::vector<std::filesystem::path> bake_files(const std::filesystem::path& out, int frame_count);

}  // namespace sweep::assets
