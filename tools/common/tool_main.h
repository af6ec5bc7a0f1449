#pragma once
// What every tool's main shares: run the tool, turn a sweep::Error into "error: <message>" on
// stderr and its documented exit code (core/error.h), and never let an exception escape.
#include <exception>
#include <functional>
#include <iostream>

#include "core/error.h"

namespace sweep::tools {

inline int guarded_main(const std::function<int()>& body) {
  try {
    return body();
  } catch (const Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return exit_code(e.category());
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory\n";
    return exit_code(ErrorCategory::internal);
  } catch (const std::exception& e) {
    std::cerr << "error: internal: " << e.what() << "\n";
    return exit_code(ErrorCategory::internal);
  }
}

inline void warn(const std::string& message) { std::cerr << "warning: " << message << "\n"; }

}  // namespace sweep::tools
