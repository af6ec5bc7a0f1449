#pragma once
// Root and tip seeds of CGAL's diplodocus's tail and neck (mesh units; the model spans x ∈ [-0.5,
// 0.5], head at +x, tail tip at -x, y up): the tail leaves the body's rear at x ≈ -0.29 and hangs
// down to its tip; the neck rises from the front of the body at y ≈ 0.08 to where it meets the
// head (the head lies beyond the tip section and is bound as its cap, so it follows rigidly).
// Shared by the tests and the benchmarks; tools/run-demo.sh passes the same points.
#include "sweep/core/frame.h"
#include "sweep/core/material.h"

namespace sweep::test {

struct Seeds {
  const char* name;
  Vec3 root, tip;
};
inline const Seeds kDiplodocusTail{"tail", {-0.29, -0.16, -0.015}, {-0.5, -0.345, -0.012}};
inline const Seeds kDiplodocusNeck{"neck", {0.26, 0.08, 0.062}, {0.36, 0.45, 0.11}};

// A rubbery animal part for the diplodocus in material mode: the mesh is ~1 unit long, taken as
// 25 m (rigs/diplodocus-tail.material.json).
inline Material diplodocus_flesh() {
  Material m;
  m.youngs_modulus = 5e7;
  m.density = 1000;
  m.metres_per_unit = 25;
  m.damping_ratio = 0.1;
  return m;
}

}  // namespace sweep::test
