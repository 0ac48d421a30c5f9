// splam: 2-D laser SLAM and exploration in complex environments. One binary, one subcommand
// per job; `splam <command> --help` documents each. The command line itself is the library
// splam::cli (apps/cli.h).
#include "apps/cli.h"

int main(int argc, char** argv) { return splam::apps::Main(argc, argv); }
