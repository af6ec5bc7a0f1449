#pragma once
// Stopping a run halfway leaves nothing behind. Every named temporary (TempFile) is tracked while
// it exists; SIGINT, SIGTERM and SIGHUP remove them all, end an open progress line, say what was
// not written and exit with 128 + the signal (130, 143, 129, as shells report a process they
// stopped). Nothing in the handler allocates or locks: the names it lists live in fixed slots, and
// besides them it removes every temporary of this process (named by its tool and pid) in each
// folder a temporary was made in, read with the raw getdents64 call: no count of temporaries
// (an .obj sequence of thousands of frames) escapes it.
//
// Temporaries are named ".<output name>.<tool>-<pid>.tmp-XXXXXX" beside the output, so a later run
// writing the same output can tell one whose process is gone (SIGKILL, a power cut) and remove it.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace sweep::io {

// Called once by each tool before any work: installs the handlers, names the tool in temporaries.
void install_interrupt_handlers(const char* tool_name);

// The tool's name as used in temporaries ("sweep" until install_interrupt_handlers is called).
const std::string& tool_name();

// Tracks a temporary (`temp`) standing for `target`; returns its slot, or -1 when every slot is
// taken (the temporary is then still removed by its owner, and on a signal by its name: its
// folder is recorded either way).
int track_temporary(const std::string& temp, const std::string& target) noexcept;
void untrack_temporary(int slot) noexcept;

// The outputs this run is to write, named in the message of an interrupt ("not written: ...").
void declare_outputs(const std::vector<std::filesystem::path>& outputs);

// The progress bar says when its line is open, so that an interrupt ends the line first.
void set_progress_line_open(bool open) noexcept;

// Where notes about removed leftovers go (sweep-* -v prints them); none by default.
void set_note_sink(std::function<void(const std::string&)> sink);
void note(const std::string& text);

// While one is alive, SIGINT, SIGTERM and SIGHUP (on any thread) wait, and take effect when the
// last is destroyed: a set of outputs is renamed into place whole.
class SignalsHeld {
 public:
  SignalsHeld();
  ~SignalsHeld();
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;
};

}  // namespace sweep::io
