#include "core/cancel.h"

#include <signal.h>

#include <atomic>

namespace mesocap {
namespace {

std::atomic<bool> g_cancel{false};  // lock-free: safe to set from a signal handler
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void OnCancelSignal(int signal) {
  if (g_cancel.exchange(true)) {  // the second one: the default action, now
    ::signal(signal, SIG_DFL);
    ::raise(signal);
  }
}

}  // namespace

void InstallCancelHandler() {
  struct sigaction action {};
  action.sa_handler = OnCancelSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in progress finish; the work stops at its next check
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

bool CancelRequested() { return g_cancel.load(std::memory_order_relaxed); }

}  // namespace mesocap
