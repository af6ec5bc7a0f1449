#pragma once
// What a part's settings give before anything moves it: how fast it sways and how far it sags
// under its own weight. The figures a person checks a part's look against (a tail sways at 1–3 Hz
// and droops a few per cent of its length; a leg barely moves).
#include <vector>

#include "sweep/core/chain_model.h"
#include "sweep/core/rig.h"

namespace sweep {

struct SwayFigures {
  // The lowest frequencies of the part's bending (sway) modes, Hz, up to two (one in each plane
  // of a round part). Material mode: the chain's modes whose motion is mostly bend (twist modes
  // left out). The paper's springs: the lowest bend frequency_hz of the movable sections (each
  // is its own oscillator).
  std::vector<double> frequencies_hz;
  // The tip's sag under `gravity`, as a fraction of the part's length (its arc length), from the
  // chain's linear statics at the rest pose: K q = τ_gravity, the tip moved by every joint's turn.
  // 0 with the paper's springs, which do not feel gravity.
  double droop = 0;
  bool feels_gravity = false;  // material mode: gravity loads the part
};

// `gravity`: m/s², in the rig's axes (the body's at the bake's start).
SwayFigures sway_figures(const SweepDef& def, const Vec3& gravity);

// The same figures of a chain model already built for `rest` (material mode).
SwayFigures sway_figures(const ChainModel& model, const SweepShape& rest, const Vec3& gravity);

// A bending mode of the chain: more of its motion (joint rotation, squared) is bend (x, y) than
// twist (z).
bool is_bending_mode(const ChainModel& model, int mode);

}  // namespace sweep
