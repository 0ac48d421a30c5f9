#ifndef SPLAM_APPS_INTERRUPT_H_
#define SPLAM_APPS_INTERRUPT_H_

namespace splam::apps {

// Ctrl-C (SIGINT), SIGTERM and SIGHUP (a closed terminal) as a request to stop: the first one
// sets a flag the long loops poll (Interrupted), so that a command writes what it has and exits
// with status 3. A second one ends the process at once, except while the results are being
// written (WritingResults): then it is noted and the files are finished first.
void CatchInterrupts();
bool Interrupted();

// While one lives, a signal does not end the process: the command's final files are written
// whole. Construct it where the writing of the results begins.
class WritingResults {
 public:
  WritingResults();
  ~WritingResults();
  WritingResults(const WritingResults&) = delete;
  WritingResults& operator=(const WritingResults&) = delete;
};

}  // namespace splam::apps

#endif  // SPLAM_APPS_INTERRUPT_H_
