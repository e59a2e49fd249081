#include "commands.hpp"  // rocking.plot
#include "stop_signals.hpp"
#include <csignal>
#include <unistd.h>
import rocking.plot;

namespace rocking::app {

namespace {

volatile std::sig_atomic_t requested = 0;

extern "C" void on_stop_signal(int signal) {
  if (requested != 0) {  // the second one: stop now
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  requested = signal;
}

}  // namespace

void catch_stop_signals() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  // A shell starts a script's background job (cmd &) with SIGINT ignored, so
  // that a Ctrl-C meant for the script does not reach it: by convention the
  // program keeps it ignored, and stops on SIGTERM alone.
  for (int signal : {SIGINT, SIGTERM}) {
    struct sigaction before {};
    if (sigaction(signal, nullptr, &before) == 0 && before.sa_handler == SIG_IGN) continue;
    sigaction(signal, &action, nullptr);
  }
  // gnuplot and ffmpeg are ended within 20 ms of a stop, their figure removed.
  plot::set_interrupt([] { return requested != 0; });
}

int stop_signal() { return requested; }

}  // namespace rocking::app
