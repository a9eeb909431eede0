#include "framework/interrupt.h"

#include <signal.h>

namespace rome {

namespace {

volatile sig_atomic_t received = 0;

extern "C" void RecordInterrupt(int signal) {
  if (received == 0) received = signal;  // the first one decides the exit code
  ::signal(signal, SIG_DFL);             // async-signal-safe; the next one of this kind ends the process
}

// Installs the handler unless the signal is ignored (as a shell ignores SIGINT for a background job without job
// control): an ignored signal stays ignored.
void Install(int signal) {
  struct sigaction old {};
  if (::sigaction(signal, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) return;
  struct sigaction action {};
  action.sa_handler = RecordInterrupt;
  sigemptyset(&action.sa_mask);
  ::sigaction(signal, &action, nullptr);
}

}  // namespace

void InstallInterruptHandlers() {
  Install(SIGINT);
  Install(SIGTERM);
}

int InterruptSignal() { return received; }

}  // namespace rome
