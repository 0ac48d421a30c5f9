#include "apps/interrupt.h"

#include <csignal>

namespace splam::apps {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

volatile std::sig_atomic_t interrupted = 0;
volatile std::sig_atomic_t writing = 0;

extern "C" void OnInterrupt(int signal) {
  if (interrupted && !writing) {  // the second one, while nothing is being written: stop now
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  interrupted = 1;
}

}  // namespace

void CatchInterrupts() {
  for (const int signal : kSignals) {
    // A signal ignored by whoever started splam (nohup ignores SIGHUP) stays ignored.
    if (std::signal(signal, OnInterrupt) == SIG_IGN) std::signal(signal, SIG_IGN);
  }
}

bool Interrupted() { return interrupted != 0; }

WritingResults::WritingResults() { writing = 1; }
WritingResults::~WritingResults() { writing = 0; }

}  // namespace splam::apps
