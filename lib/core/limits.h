#pragma once
// The one table of limits. Every entry point that takes these values (fit options, the rig
// reader, the binding reader, the scene reader, the mesh readers) checks them against this table,
// so a file one tool writes is a file the next one reads; docs/formats.md lists them ("Limits").
// Each limit is far beyond any real use and close enough that the arithmetic on it stays finite.
#include <cstdint>

namespace sweep::limits {

// Sweep shape.
constexpr int kMinSections = 2;  // key sections K of a sweep
constexpr int kMaxSections = 100000;
constexpr int kMinRadial = 3;  // radius samples n per section
constexpr int kMaxRadial = 4096;
// Any length in a rig (section t, centre coordinates, radii, seeds), in mesh units: squares and
// sums of squares of such values stay finite with room to spare.
constexpr double kMaxLength = 1e9;

// Springs (core/springs.h), physical ranges: outside them the closed-form step under-/overflows.
constexpr double kMinMass = 1e-6;         // kg
constexpr double kMaxMass = 1e6;          // kg
constexpr double kMinFrequencyHz = 1e-3;  // Hz
constexpr double kMaxFrequencyHz = 1e4;   // Hz
constexpr double kMaxDampingRatio = 1e3;  // dimensionless (0 = undamped, 1 = critical)
constexpr double kMaxForceScale = 1e6;    // C_rot (mesh units), C_rad (dimensionless)

// Scenes.
constexpr double kMinFps = 1e-3;  // frames per second
constexpr double kMaxFps = 10000.0;
constexpr double kMaxDuration = 86400.0;  // s: a day of animation
constexpr int kMaxFrames = 1000000;       // duration × fps + 1
constexpr int kMaxSubsteps = 100000;      // steps per frame
constexpr double kMinStep = 1e-6;         // s: the scene's internal step; far finer than any spring needs
constexpr double kMaxStep = 1.0;          // s: the closed form takes any step, but loads are re-split per step
constexpr double kMaxForce = 1e9;         // N: length of a force vector
constexpr double kMaxTime = 86400.0;      // s: force start/end, |value|

// Meshes: vertex and face-corner indices are 32-bit.
constexpr std::uint64_t kMaxVertices = 0xfffffffeu;

// JSON inputs (rig, scene) are read whole and parsed into a tree several times their size: a
// file above this is refused before it is read.
constexpr std::uint64_t kMaxJsonBytes = 64ull << 20;  // 64 MiB

}  // namespace sweep::limits
