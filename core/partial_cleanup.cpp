#include "slamprep/core/partial_cleanup.hpp"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>

namespace slamprep {
namespace {

// Fixed storage: the handler may only read memory, never allocate or lock (signal-safety(7)).
struct Slot {
  std::atomic<bool> claimed{false};  // owned by a PartialInFlight
  std::atomic<bool> ready{false};    // `path` complete: the handler may remove it
  char path[PATH_MAX];
};
std::array<Slot, 16> g_slots;
static_assert(std::atomic<bool>::is_always_lock_free);

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
// A partial is a dataset folder (flat) or one file; deeper trees are left to the user.
constexpr int kMaxDepth = 4;

// The record getdents64(2) fills; glibc has no declaration for the raw system call's type.
struct LinuxDirent64 {
  std::uint64_t d_ino;
  std::int64_t d_off;
  unsigned short d_reclen;
  unsigned char d_type;
  char d_name[1];
};

bool isDotOrDotDot(const char* name) {
  return name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'));
}

// Removes `name` in `parent` with system calls only (async-signal-safe): a file, or a folder
// emptied first, entry by entry, until a pass finds nothing left.
void removeAt(int parent, const char* name, int depth) {
  if (::unlinkat(parent, name, 0) == 0 || errno == ENOENT || depth == 0) return;
  const int fd = ::openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[4096];
  for (int pass = 0; pass < 64; ++pass) {
    bool found = false;
    ::lseek(fd, 0, SEEK_SET);
    for (long n; (n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0;) {
      for (long offset = 0; offset < n;) {
        const auto* entry = reinterpret_cast<const LinuxDirent64*>(buffer + offset);
        if (!isDotOrDotDot(entry->d_name)) {
          found = true;
          removeAt(fd, entry->d_name, depth - 1);
        }
        offset += entry->d_reclen;
      }
    }
    if (!found) break;
  }
  ::close(fd);
  ::unlinkat(parent, name, AT_REMOVEDIR);
}

void onSignal(int signal) {
  const int saved = errno;
  for (Slot& slot : g_slots)
    if (slot.ready.load(std::memory_order_acquire)) removeAt(AT_FDCWD, slot.path, kMaxDepth);
  errno = saved;
  ::signal(signal, SIG_DFL);
  ::raise(signal);  // unblocked on return from this handler: the process ends as signalled
}

}  // namespace

void removePartialsOnSignal() {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  for (int signal : kSignals) sigaddset(&action.sa_mask, signal);  // one cleanup at a time
  for (int signal : kSignals) {
    struct sigaction old {};
    if (::sigaction(signal, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(signal, &action, nullptr);
  }
}

PartialInFlight::PartialInFlight(const std::filesystem::path& path) {
  std::error_code ec;
  const std::string absolute = std::filesystem::absolute(path, ec).string();
  if (ec || absolute.size() >= PATH_MAX) return;
  for (std::size_t i = 0; i < g_slots.size(); ++i) {
    bool expected = false;
    Slot& slot = g_slots[i];
    if (!slot.claimed.compare_exchange_strong(expected, true, std::memory_order_acq_rel)) continue;
    std::memcpy(slot.path, absolute.c_str(), absolute.size() + 1);
    slot.ready.store(true, std::memory_order_release);
    slot_ = static_cast<int>(i);
    return;
  }
}

PartialInFlight::~PartialInFlight() {
  if (slot_ < 0) return;
  g_slots[slot_].ready.store(false, std::memory_order_release);
  g_slots[slot_].claimed.store(false, std::memory_order_release);
}

}  // namespace slamprep
