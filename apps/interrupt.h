#ifndef SPLAM_APPS_INTERRUPT_H_
#define SPLAM_APPS_INTERRUPT_H_

namespace splam::apps {

// Ctrl-C (SIGINT) and SIGTERM as a request to stop: the first one sets a flag the long loops
// poll (Interrupted), so that a command writes what it has and exits with status 3; a second
// one ends the process at once.
void CatchInterrupts();
bool Interrupted();

}  // namespace splam::apps

#endif  // SPLAM_APPS_INTERRUPT_H_
