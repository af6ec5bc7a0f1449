#pragma once
// Runs a stretch of code with every floating-point exception masked and the caller's environment
// (flags and traps) restored afterwards: traps a caller enabled are paused, and the flags raised
// inside are dropped, as the C standard's feholdexcept/fesetenv pair is meant for. Libraries that
// raise flags by design are called under it: CGAL's interval arithmetic, and assimp's importers,
// whose number parsing raises overflow and invalid on legitimate input such as
// 1.7976931348623157e308 read into a float (what they produce is checked afterwards:
// validate_mesh). So callers that trap FP exceptions (the tests) trap only what is born in our
// own code.
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
