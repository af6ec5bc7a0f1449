#pragma once
// Material presets: a kind of part in one word. A preset fixes the part's first sway frequency
// (Hz), its damping and its density; the Young's modulus is then solved from the part's own
// sections so that it sways at that frequency whatever its size or the mesh's units. So the same
// asset at 1×, 10× or 100× moves the same way in angle and time under a body motion scaled with
// it. Its sag under gravity is not scale-free, and cannot be: a cantilever's droop and first
// frequency are tied by δ/L ≈ 1.545 g / (ω₁² L), so at a fixed frequency a part twice as long (in
// metres: metres_per_unit says how long) droops half as much of its length.
#include <span>
#include <string>
#include <string_view>

#include "sweep/core/material.h"
#include "sweep/core/sweep_shape.h"

namespace sweep {

struct Preset {
  std::string_view name;
  double frequency_hz;   // first sway (bending) frequency the part is given
  double damping_ratio;  // ζ of every mode
  double density;        // kg/m³
  // Whether a part of this kind holds the pose it was modelled in under its own weight (a tail,
  // a neck), its modulus raised where the frequency's leaves it too weak; a strand hangs.
  bool holds_its_pose;
};

// Standard gravity (m/s²), what a preset part must hold its modelled pose against, pointing
// against the mesh's up (as its part names go by).
inline constexpr double kStandardGravity = 9.80665;
// A preset part that holds its pose holds it twice over: the stiffness it would need to just hold
// (its load factor, core/held_rest.h) at most half its own.
inline constexpr double kPresetLoadFactor = 0.5;

std::span<const Preset> presets();
const Preset* find_preset(std::string_view name);  // nullptr when there is none of that name
std::string preset_names();                        // "tail, neck, …" for messages

// `m` with its Young's modulus chosen so that a part of shape `rest` made of it has its first
// bending mode at `frequency_hz` (the chain model's, core/chain_model.h). Every other member of
// `m` is kept (its density, ν or G, metres_per_unit, damping).
Material with_frequency(const SweepShape& rest, Material m, double frequency_hz);

// The preset's material for `rest`: its density and damping, ν = 0.45, the mesh scale given, and
// E solved for its frequency.
Material preset_material(const SweepShape& rest, const Preset& preset, double metres_per_unit);

// The preset a part fitted without a material takes, by the words of its name (split at
// non-letters and at a lower-to-upper case change, any case, a plural's s dropped): tail → tail,
// neck → neck, ear → ear, tentacle or trunk → tentacle, strand, hair, rope or tuft → strand; any
// other name (a leg, an arm, a horn, "part") the fallback, kFallbackPreset. `why` says which word
// chose it, or that none did.
struct PresetChoice {
  const Preset* preset = nullptr;
  std::string why;
};
PresetChoice preset_for_name(std::string_view part_name);

// A part no word names: a limb, which should barely move under its body's motion, so the
// stiffest and quickest preset (a spider's legs under a body bob: see README).
inline constexpr std::string_view kFallbackPreset = "ear";

// The frequency a material that gives no Young's modulus is solved for: the tail preset's, a
// part that holds its own weight and sways visibly (rather than a fixed modulus, which leaves a
// long part too soft to stand and a small one rigid).
double default_frequency_hz();

// The preset's members before E is solved: density, damping, ν = 0.45 (the rest the defaults').
Material preset_base(const Preset& preset);

// A material as asked for: a preset's members (or the defaults) with those given explicitly on
// top. With a preset and no Young's modulus given, E is solved on the part's rest shape for the
// preset's frequency (with the density, ν or G and scale as given); explicit settings win.
struct MaterialRequest {
  Material material;
  const Preset* preset = nullptr;
  bool youngs_modulus_given = false;
};
Material resolve_material(const MaterialRequest& request, const SweepShape& rest);

}  // namespace sweep
