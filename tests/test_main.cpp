// GoogleTest main for every test executable. Invalid operations, division by zero and overflow
// raise SIGFPE, so the first NaN or Inf a computation makes stops the test where it is born.
#include <fenv.h>
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
  return RUN_ALL_TESTS();
}
