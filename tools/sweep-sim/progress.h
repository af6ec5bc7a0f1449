#pragma once
// A progress bar on stderr, drawn only when stderr is a terminal (scripts and CI logs get none).
#include <chrono>
#include <string>

namespace sweep::tools {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  void update(int done, int total);  // redraws at most ~20 times a second
  void finish();                     // clears the line

 private:
  std::string label_;
  bool enabled_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace sweep::tools
