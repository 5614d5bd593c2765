// SPDX-License-Identifier: Apache-2.0
#include "wall_limit.hpp"

#include <signal.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "solve_command.hpp"

namespace dvi::dvisim {
namespace {

// What the handler writes: fixed storage, filled before the timer starts
// (a signal handler may only call async-signal-safe functions).
char g_message[1024];
std::size_t g_message_size = 0;

extern "C" void OnWallLimit(int) {
  const ssize_t ignored = ::write(STDERR_FILENO, g_message, g_message_size);
  (void)ignored;
  ::_exit(kExitNumericalFailure);
}

void SetTimer(double seconds) {
  itimerval timer{};
  const double whole = std::floor(seconds);
  timer.it_value.tv_sec = static_cast<time_t>(whole);
  timer.it_value.tv_usec = static_cast<suseconds_t>((seconds - whole) * 1e6);
  if (seconds > 0 && timer.it_value.tv_sec == 0 && timer.it_value.tv_usec == 0)
    timer.it_value.tv_usec = 1;
  ::setitimer(ITIMER_REAL, &timer, nullptr);
}

}  // namespace

WallClockLimit::~WallClockLimit() { Disarm(); }

void WallClockLimit::Arm(double seconds, const std::string& message) {
  SetTimer(0);
  g_message_size = std::min(message.size(), sizeof(g_message));
  std::memcpy(g_message, message.data(), g_message_size);
  struct sigaction action {};
  action.sa_handler = OnWallLimit;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGALRM, &action, nullptr);
  // setitimer takes at most about 3e15 s; any budget beyond is no limit.
  SetTimer(std::min(seconds, 1e15));
  armed_ = true;
}

void WallClockLimit::Disarm() {
  if (!armed_) return;
  SetTimer(0);
  armed_ = false;
}

}  // namespace dvi::dvisim
