#include "tools/interrupt.h"

#include <csignal>
#include <cstdlib>
#include <unistd.h>

namespace zbrdf {

namespace {
std::atomic<bool> g_interrupted{false};

extern "C" void OnSignal(int) {
  if (g_interrupted.exchange(true)) _exit(130);
  static const char kMessage[] =
      "\nzbrdf: stopping after the frame in flight (Ctrl-C again to quit at once)\n";
  (void)!write(2, kMessage, sizeof(kMessage) - 1);
}
}  // namespace

const std::atomic<bool>* InstallInterruptHandler() {
  static bool installed = false;
  if (!installed) {
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    installed = true;
  }
  return &g_interrupted;
}

}  // namespace zbrdf
