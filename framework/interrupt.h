#pragma once
// Interrupting a run with SIGINT (Ctrl-C) or SIGTERM: the handlers only record the signal; a running Simulator stops
// at its next step with SimulatorStatus::Reason::kInterrupted, so the program can write its outputs (atomically) with
// a summary that says "interrupted" and exit 128 + the signal (130, 143). A second signal of the same kind ends the
// process at once, as without the handlers. A signal the process was started with ignored stays ignored. Only the
// simulation checks the flag: a signal during planning (an NLP) takes effect when the simulation starts.

namespace rome {

/// Installs the handlers for SIGINT and SIGTERM.
void InstallInterruptHandlers();
/// The signal received since InstallInterruptHandlers (SIGINT or SIGTERM), or 0.
int InterruptSignal();

}  // namespace rome
