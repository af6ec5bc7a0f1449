#pragma once
// Floating-point traps are on in every test (test_main.cpp). Code that makes NaN or Inf on purpose
// (a test feeding NaN to a loader, or a library such as CGAL whose interval arithmetic overflows by
// design) turns them off for its scope with this guard.
#include <fenv.h>

namespace sweep::test {

class FpTrapsOff {
 public:
  FpTrapsOff() : saved_(fegetexcept()) { fedisableexcept(FE_ALL_EXCEPT); }
  ~FpTrapsOff() {
    feclearexcept(FE_ALL_EXCEPT);
    feenableexcept(saved_);
  }
  FpTrapsOff(const FpTrapsOff&) = delete;
  FpTrapsOff& operator=(const FpTrapsOff&) = delete;

 private:
  int saved_;
};

}  // namespace sweep::test
