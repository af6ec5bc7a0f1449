#include "sweep/core/presets.h"

#include <array>
#include <cctype>
#include <cmath>
#include <numbers>
#include <vector>

#include "sweep/core/chain_model.h"
#include "sweep/core/sway.h"

namespace sweep {
namespace {

// Frequencies: a tail sways at 1–3 Hz, a long neck slower and more damped, an ear is quick and
// light, a tentacle slow and lively, a strand (hair, rope) barely holds itself and hangs.
constexpr std::array kPresets{
    Preset{"tail", 2.0, 0.1, 1050, true},     Preset{"neck", 1.0, 0.15, 1050, true},
    Preset{"ear", 4.0, 0.1, 1100, true},      Preset{"tentacle", 0.8, 0.08, 1040, true},
    Preset{"strand", 0.4, 0.03, 1100, false},
};

double first_bending_omega2(const SweepShape& rest, const Material& m) {
  const ChainModel model = build_chain_model(rest, std::vector<Material>(rest.section_count(), m));
  for (int c = 0; c < model.omega2.size(); ++c) {
    if (is_bending_mode(model, c)) return model.omega2[c];
  }
  return model.omega2[0];
}

// A name's words in lower case: "TailTip_2" → tail, tip; "hairStrands" → hair, strands.
std::vector<std::string> words_of(std::string_view name) {
  std::vector<std::string> words;
  std::string word;
  char previous = 0;
  for (const char c : name) {
    const bool letter = std::isalpha(static_cast<unsigned char>(c)) != 0;
    const bool new_word =
        !letter || (std::isupper(static_cast<unsigned char>(c)) && std::islower(static_cast<unsigned char>(previous)));
    if (new_word && !word.empty()) words.push_back(std::move(word)), word.clear();
    if (letter) word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    previous = c;
  }
  if (!word.empty()) words.push_back(std::move(word));
  return words;
}

struct KindWord {
  std::string_view word;
  std::string_view preset;
};
constexpr std::array kKindWords{
    KindWord{"tail", "tail"},         KindWord{"neck", "neck"},      KindWord{"ear", "ear"},
    KindWord{"tentacle", "tentacle"}, KindWord{"trunk", "tentacle"}, KindWord{"strand", "strand"},
    KindWord{"hair", "strand"},       KindWord{"rope", "strand"},    KindWord{"tuft", "strand"},
};

}  // namespace

PresetChoice preset_for_name(std::string_view part_name) {
  for (const std::string& word : words_of(part_name)) {
    for (const KindWord& k : kKindWords) {
      const bool plural = word.size() == k.word.size() + 1 && word.back() == 's' && word.starts_with(k.word);
      if (word == k.word || plural) {
        return {find_preset(k.preset), "its name says " + std::string(k.word)};
      }
    }
  }
  return {find_preset(kFallbackPreset),
          "no tail, neck, ear, tentacle, trunk, strand, hair, rope or tuft in its name: the fallback for a limb"};
}

double default_frequency_hz() {
  return find_preset("tail")->frequency_hz;
}

std::span<const Preset> presets() {
  return kPresets;
}

const Preset* find_preset(std::string_view name) {
  for (const Preset& p : kPresets) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::string preset_names() {
  std::string out;
  for (const Preset& p : kPresets) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out;
}

Material with_frequency(const SweepShape& rest, Material m, double frequency_hz) {
  // The bending stiffness is proportional to E and the masses do not depend on it, so ω² ∝ E:
  // one rescale lands on the frequency. (A shear modulus given apart from E makes the twist not
  // follow; bending and twist couple only on a curved part, so a second pass settles it.)
  const double target = std::pow(2 * std::numbers::pi * frequency_hz, 2);
  m.youngs_modulus = 1e6;
  for (int pass = 0; pass < 3; ++pass) {
    const double w2 = first_bending_omega2(rest, m);
    if (!(w2 > 0)) break;
    const double ratio = target / w2;
    m.youngs_modulus *= ratio;
    if (std::abs(ratio - 1) < 1e-12) break;
  }
  return m;
}

Material preset_base(const Preset& preset) {
  Material m;
  m.poisson_ratio = 0.45;
  m.density = preset.density;
  m.damping_ratio = preset.damping_ratio;
  return m;
}

Material preset_material(const SweepShape& rest, const Preset& preset, double metres_per_unit) {
  Material m = preset_base(preset);
  m.metres_per_unit = metres_per_unit;
  return with_frequency(rest, m, preset.frequency_hz);
}

Material resolve_material(const MaterialRequest& request, const SweepShape& rest) {
  if (request.youngs_modulus_given) return request.material;
  return with_frequency(rest, request.material,
                        request.preset != nullptr ? request.preset->frequency_hz : default_frequency_hz());
}

}  // namespace sweep
