#ifndef SPLAM_APPS_CLI_H_
#define SPLAM_APPS_CLI_H_

// The splam command line as a library: a program of one's own is its registration lines (a SLAM
// method: estimation::RegisterSlamMethod; an explorer: exploration::RegisterExplorer) and
//   int main(int argc, char** argv) { /* register */ return splam::apps::Main(argc, argv); }
// and then has every subcommand of `splam`, its variants among the choices (examples/cli/).
namespace splam::apps {

// Parses the arguments (argv[0] the program's name), runs the subcommand and returns the exit
// status: 0 done, 2 bad input, 3 stopped early with what was done written, 4 a write failed.
// Everything registered before the call is offered by the subcommands.
int Main(int argc, char** argv);

}  // namespace splam::apps

#endif  // SPLAM_APPS_CLI_H_
