#pragma once
// What every tool's main shares: run the tool, turn a sweep::Error into "error: <message>" on
// stderr and its documented exit code (core/error.h), and never let an exception escape.
//  - Out of memory is exit 6 with a message, never an abort: a reserve is set aside at start and
//    given back by the first failed allocation, so that the std::bad_alloc it raises can unwind
//    (destructors remove temporaries; some allocate) and be reported; should memory run out again
//    before that, the message is written with no allocation and the process exits 6 at once.
//  - SIGINT, SIGTERM and SIGHUP remove the run's temporaries, end the progress line, say what was
//    not written and exit 130, 143 and 129 (io/interrupt.h).
//  - A closed stdout (`sweep-sim ... | head -1`) is not an error: SIGPIPE is ignored and what
//    would have been printed is dropped; outputs and the exit code are those of the run.
#include <errno.h>  // program_invocation_short_name (GNU)
#include <sys/mman.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <exception>
#include <functional>
#include <iostream>
#include <new>
#include <optional>

#include "sweep/core/error.h"
#include "sweep/io/interrupt.h"

namespace sweep::tools {

namespace detail {
inline void* memory_reserve = nullptr;
constexpr std::size_t kMemoryReserveBytes = std::size_t{32} << 20;

inline void out_of_memory_again() {
  constexpr char kMessage[] = "error: out of memory\n";
  [[maybe_unused]] const ssize_t n = ::write(2, kMessage, sizeof kMessage - 1);
  ::_exit(exit_code(ErrorCategory::internal));
}

inline void out_of_memory() {
  if (memory_reserve != nullptr) ::munmap(memory_reserve, kMemoryReserveBytes);
  memory_reserve = nullptr;
  std::set_new_handler(out_of_memory_again);
  throw std::bad_alloc();
}
}  // namespace detail

inline int guarded_main(const std::function<int()>& body) {
  std::signal(SIGPIPE, SIG_IGN);
  // SIGINT, SIGTERM, SIGHUP: temporaries removed, "error: interrupted ...", exit 130/143/129.
  io::install_interrupt_handlers(program_invocation_short_name);
  // Notes (a killed run's leftovers removed) go to stderr; -q turns them off.
  io::set_note_sink([](const std::string& text) { std::cerr << "note: " << text << "\n"; });
  // The reserve really held (an untouched block may be only promised), its pages given in one call
  // (MAP_POPULATE): touching them one by one took 86-90 ms on a VM, 6-8 ms so, at every start of
  // every tool, a window in which an interrupt could not yet name the run's outputs.
  void* reserve = ::mmap(nullptr, detail::kMemoryReserveBytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
  detail::memory_reserve = reserve == MAP_FAILED ? nullptr : reserve;
  std::set_new_handler(detail::out_of_memory);
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

// Parses the command line. Returns the exit code when the tool should stop here: 0 after --help or
// --version, 1 (usage) after a bad command line, reported as "error: ..." (CLI11's own exit codes,
// 105, 106, 109, ..., are not ours: every bad command line is usage).
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "error: " << e.what() << " (run with --help for more information)\n";
    return exit_code(ErrorCategory::usage);
  }
  return std::nullopt;
}

inline void warn(const std::string& message) {
  std::cerr << "warning: " << message << "\n";
}

}  // namespace sweep::tools
