// The flags the signal handlers set, and how an interrupted process ends.
#include <pthread.h>
#include <unistd.h>

#include <csignal>

#include "app/run.h"

namespace cellform::app {

std::atomic<bool> g_interrupt{false};
std::atomic<bool> g_print_after_interrupt{false};
std::atomic<bool> g_reading_script{false};
std::atomic<bool> g_print_cancel{false};
std::atomic<int> g_interrupt_signal{0};
std::atomic<bool> g_print_planned{false};
std::atomic<bool> g_printing{false};

void exit_process(int code) {
  if (g_interrupt_signal.load() == SIGINT) {
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(SIGINT, &dfl, nullptr);
    sigset_t only;
    sigemptyset(&only);
    sigaddset(&only, SIGINT);
    pthread_sigmask(SIG_UNBLOCK, &only, nullptr);  // blocked inside the handler that may call this
    raise(SIGINT);
  }
  ::_exit(code);
}

}  // namespace cellform::app
