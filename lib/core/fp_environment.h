#pragma once
// Runs a stretch of code with every floating-point exception masked and the caller's environment
// (flags and traps) restored afterwards. Libraries that raise flags by design (CGAL's interval
// arithmetic, assimp's importers) are called under it, so callers that trap FP exceptions (the
// tests) trap only what is born in our own code.
#include <cfenv>

namespace sweep {

class QuietFpEnvironment {
 public:
  QuietFpEnvironment() { std::feholdexcept(&saved_); }
  ~QuietFpEnvironment() { std::fesetenv(&saved_); }
  QuietFpEnvironment(const QuietFpEnvironment&) = delete;
  QuietFpEnvironment& operator=(const QuietFpEnvironment&) = delete;

 private:
  std::fenv_t saved_;
};

}  // namespace sweep
