#pragma once
// Constants many test files use, defined once: a unity build compiles a folder's test files
// together as one translation unit, where a constant defined in two of them is defined twice.
#include <numbers>

namespace sweep::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kG = 9.81;  // standard gravity, m/s²

}  // namespace sweep::test
