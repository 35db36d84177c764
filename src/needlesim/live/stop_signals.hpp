#pragma once
// Ctrl-C and SIGTERM for needlesim serve: the first asks the session to stop (core/progress's
// stop request, which the server watches); while it stops, a further signal does not end the
// process when a recording is to be written: it prints that the recording is being written.
// Without a recording a further signal ends the process at once, as it does for other commands.
#include <string>

namespace needlesim::live {

// Replaces the SIGINT and SIGTERM handlers; `recording`: the folder written on stopping ("" for none).
void installServeStopHandlers(const std::string& recording);
// The session stops for another reason (POST /api/stop): signals from now on are further ones.
void markStopping();
// Signals that arrived while stopping.
int signalsWhileStopping();

}  // namespace needlesim::live
