#include "framework/interrupt.h"

#include <csignal>

namespace rome {

namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void RecordInterrupt(int signal) {
  received = signal;
  std::signal(signal, SIG_DFL);  // async-signal-safe; the next one of this kind ends the process
}

}  // namespace

void InstallInterruptHandlers() {
  std::signal(SIGINT, RecordInterrupt);
  std::signal(SIGTERM, RecordInterrupt);
}

int InterruptSignal() { return received; }

}  // namespace rome
