// Clean stops: SIGINT (Ctrl-C) and SIGTERM (a cluster scheduler) set a flag
// that long commands poll between runs; they finish or abandon the work in
// flight, keep what is complete, say how far they got and exit 128 + signal
// (130, 143). A second signal of either kind ends the process at once.
#pragma once
#include <csignal>

namespace rocking::app {

// Installs the handlers (for the rest of the process).
void catch_stop_signals();
// The signal that asked to stop, or 0.
int stop_signal();
// "SIGINT" or "SIGTERM", for the note a stopped command prints.
inline const char* stop_signal_name(int signal) { return signal == SIGTERM ? "SIGTERM" : "SIGINT"; }
// 128 + the signal: the shell's code for a process ended by it.
inline int stop_exit_code(int signal) { return 128 + signal; }

}  // namespace rocking::app
