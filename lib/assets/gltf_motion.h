#pragma once
// The body's motion from a glTF file's own animation: scene "body": {"node": NAME,
// "animation": NAME}. The mesh is read in world space at rest (the nodes' rest transforms
// applied), so the body at time t is the node's motion away from its rest pose, in world axes:
//     B(t) = P · L(t) · L₀⁻¹ · P⁻¹
// with L(t) the node's animated local transform (its translation and rotation channels; the rest
// value where a channel is missing), L₀ its rest transform and P its parent's world transform.
// Channels must be LINEAR (glTF's lerp and slerp are the path's linear pieces, so the keys are
// taken as they are, on the union of both channels' times: exact, not resampled); STEP and
// CUBICSPLINE are refused with what to do, as are a scale channel on the node (a body does not
// change size) and an animated ancestor (only the node's own animation is read).
#include <filesystem>
#include <string>

#include "sweep/sim/body_path.h"

namespace sweep::assets {

// Throws Error(bad_input) naming the file and the node or animation: no such node, no animation
// moves it, a channel that cannot be read, a refused interpolation.
sim::BodyPath read_gltf_body_path(const std::filesystem::path& gltf, const std::string& node,
                                  const std::string& animation = {});

}  // namespace sweep::assets
