#include "sweep/io/interrupt.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <utility>

namespace sweep::io {
namespace {

constexpr int kSlots = 256;
constexpr std::size_t kPathBytes = 4096;

// A tracked temporary. `state`: 0 free, 1 being filled, 2 live (the handler removes it).
struct Slot {
  std::atomic<int> state{0};
  char temp[kPathBytes];
  char target[kPathBytes];
};
Slot slots[kSlots];
std::atomic<bool> progress_open{false};
// While outputs are being renamed into place (SignalsHeld), a signal waits here, on any thread.
std::atomic<int> holding{0};
std::atomic<int> pending{0};
std::string tool = "sweep";
char declared[kPathBytes];  // "a.glb, a.pc2, r.json" or empty
std::function<void(const std::string&)> note_sink;

// The folders this run made temporaries in: the handler removes every temporary of this process
// there (".*.<tool>-<pid>.tmp-*"), however many, so no count of tracked names caps the cleanup
// (an .obj sequence of thousands of frames). A run writes into a handful of folders.
constexpr int kFolders = 64;
struct Folder {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  char path[kPathBytes];
};
Folder folders[kFolders];
char own_marker[96];  // ".<tool>-<pid>.tmp-": what names this process's temporaries

bool contains(const char* text, const char* part) {
  for (; *text != '\0'; ++text) {
    std::size_t i = 0;
    while (part[i] != '\0' && text[i] == part[i]) ++i;
    if (part[i] == '\0') return true;
  }
  return false;
}

// Async-signal-safe: open, getdents64 (the raw system call: readdir may allocate), unlinkat.
void remove_own_temporaries(const char* folder) {
  if (own_marker[0] == '\0') return;  // no handler installed: nothing is ours by name
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[8192];
  for (;;) {
    const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
    if (n <= 0) break;
    bool removed = false;
    for (long at = 0; at < n;) {
      struct Entry {
        std::uint64_t inode;
        std::int64_t offset;
        unsigned short length;
        unsigned char type;
        char name[1];
      };
      const Entry* e = reinterpret_cast<const Entry*>(buffer + at);
      if (e->name[0] == '.' && contains(e->name, own_marker)) {
        removed = ::unlinkat(fd, e->name, 0) == 0 || removed;
      }
      at += e->length;
    }
    // Removing entries while reading may skip some: read the folder again from its start.
    if (removed) ::lseek(fd, 0, SEEK_SET);
  }
  ::close(fd);
}

void put(const char* text) {
  std::size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t n = ::write(2, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<std::size_t>(n);
  }
}

void put_number(int value) {
  char digits[16];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value > 0 && n < 15);
  char text[16];
  for (int i = 0; i < n; ++i) text[i] = digits[n - 1 - i];
  text[n] = '\0';
  put(text);
}

// Async-signal-safe only: unlink, write, _exit.
extern "C" void on_interrupt(int signal) {
  if (holding.load() > 0) {
    pending.store(signal);
    return;
  }
  constexpr int kListed = 3;
  const char* not_written[kListed] = {};
  int count = 0;
  for (Slot& s : slots) {
    if (s.state.load() != 2) continue;
    ::unlink(s.temp);
    if (count < kListed) not_written[count] = s.target;
    ++count;
  }
  for (Folder& f : folders) {
    if (f.state.load() == 2) remove_own_temporaries(f.path);
  }
  if (progress_open.load()) put("\r\033[K");  // the progress bar's line, cleared
  put("error: interrupted by ");
  put(signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : signal == SIGHUP ? "SIGHUP" : "a signal");
  if (declared[0] != '\0') {
    put("; not written: ");
    put(declared);
    put("\n");
  } else if (count == 0) {
    put("\n");
  } else {
    put("; not written: ");
    for (int i = 0; i < count && i < kListed; ++i) {
      if (i > 0) put(", ");
      put(not_written[i]);
    }
    if (count > kListed) {
      put(" and ");
      put_number(count - kListed);
      put(" more");
    }
    put("\n");
  }
  ::_exit(128 + signal);
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

}  // namespace

void install_interrupt_handlers(const char* tool_name_in) {
  tool = tool_name_in;
  const std::string marker = "." + tool + "-" + std::to_string(::getpid()) + ".tmp-";
  const std::size_t n = std::min(marker.size(), sizeof own_marker - 1);
  std::memcpy(own_marker, marker.c_str(), n);
  own_marker[n] = '\0';
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  for (const int s : kSignals) sigaddset(&action.sa_mask, s);  // one handler at a time
  for (const int s : kSignals) sigaction(s, &action, nullptr);
}

const std::string& tool_name() {
  return tool;
}

namespace {

// Records the folder of `temp` (once) for the handler's sweep of this process's temporaries.
void track_folder(const std::string& temp) noexcept {
  const std::size_t slash = temp.rfind('/');
  const std::string_view folder = slash == std::string::npos ? std::string_view(".")
                                  : slash == 0               ? std::string_view("/")
                                                             : std::string_view(temp).substr(0, slash);
  if (folder.size() >= kPathBytes) return;
  for (Folder& f : folders) {
    if (f.state.load() == 2 && folder == f.path) return;
  }
  for (Folder& f : folders) {
    int expected = 0;
    if (!f.state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(f.path, folder.data(), folder.size());
    f.path[folder.size()] = '\0';
    f.state.store(2);
    return;
  }
}

}  // namespace

int track_temporary(const std::string& temp, const std::string& target) noexcept {
  track_folder(temp);
  if (temp.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slots[i].temp, temp.c_str(), temp.size() + 1);
    const std::size_t n = std::min(target.size(), kPathBytes - 1);
    std::memcpy(slots[i].target, target.c_str(), n);
    slots[i].target[n] = '\0';
    slots[i].state.store(2);
    return i;
  }
  return -1;
}

void untrack_temporary(int slot) noexcept {
  if (slot >= 0 && slot < kSlots) slots[slot].state.store(0);
}

void declare_outputs(const std::vector<std::filesystem::path>& outputs) {
  std::string text;
  for (const auto& o : outputs) {
    if (!o.empty()) text += (text.empty() ? "" : ", ") + o.string();
  }
  if (text.size() >= kPathBytes) text = text.substr(0, kPathBytes - 4) + "...";
  declared[0] = '\0';  // the handler reads it: never half a name
  std::memcpy(declared + 1, text.c_str() + (text.empty() ? 0 : 1), text.size());
  declared[0] = text.empty() ? '\0' : text[0];
}

void set_progress_line_open(bool open) noexcept {
  progress_open.store(open);
}

void set_note_sink(std::function<void(const std::string&)> sink) {
  note_sink = std::move(sink);
}

void note(const std::string& text) {
  if (note_sink) note_sink(text);
}

SignalsHeld::SignalsHeld() {
  holding.fetch_add(1);
}

SignalsHeld::~SignalsHeld() {
  if (holding.fetch_sub(1) == 1) {
    if (const int signal = pending.exchange(0)) on_interrupt(signal);
  }
}

}  // namespace sweep::io
