// Ctrl-C (SIGINT, SIGTERM) for long jobs: the first signal sets a flag that captures check
// between frames, so they stop cleanly with everything written journaled; a second signal
// ends the process at once.
#pragma once

#include <atomic>

namespace zbrdf {

// Installs the handlers (once) and returns the flag they set.
const std::atomic<bool>* InstallInterruptHandler();

}  // namespace zbrdf
