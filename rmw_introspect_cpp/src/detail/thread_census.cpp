// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/thread_census.hpp"

#include <dirent.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace rmw_introspect
{

namespace
{
#if defined(__x86_64__)
constexpr long kFutex = 202;
constexpr long kPause = 34;
constexpr long kRtSigsuspend = 130;
constexpr long kRtSigtimedwait = 128;
constexpr long kClockNanosleep = 230;
constexpr bool kKnownArch = true;
#else
constexpr long kFutex = -2;
constexpr long kPause = -2;
constexpr long kRtSigsuspend = -2;
constexpr long kRtSigtimedwait = -2;
constexpr long kClockNanosleep = -2;
constexpr bool kKnownArch = false;
#endif
// futex operations (op & FUTEX_CMD_MASK) that sleep until woken or until their timeout.
constexpr uint64_t kFutexCmdMask = 0x7f;  // ~(FUTEX_PRIVATE_FLAG | FUTEX_CLOCK_REALTIME)
constexpr uint64_t kFutexClockRealtime = 256;
constexpr uint64_t kFutexWait = 0;           // relative timeout
constexpr uint64_t kFutexLockPi = 6;         // absolute, CLOCK_REALTIME
constexpr uint64_t kFutexWaitBitset = 9;     // absolute
constexpr uint64_t kFutexWaitRequeuePi = 11;  // absolute
constexpr uint64_t kFutexLockPi2 = 13;       // absolute
constexpr uint64_t kTimerAbstime = 1;

std::string read_line(const std::string & path)
{
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  return line;
}

// The one-letter state of /proc/self/task/<tid>/stat (after the parenthesized name).
char thread_state(const std::string & tid)
{
  const std::string stat = read_line("/proc/self/task/" + tid + "/stat");
  const size_t close = stat.rfind(')');
  return close == std::string::npos || close + 2 >= stat.size() ? '?' : stat[close + 2];
}

// A timespec of this process's memory, read without trusting the address.
bool read_timespec(uintptr_t address, timespec * out)
{
  iovec local{out, sizeof(*out)};
  iovec remote{reinterpret_cast<void *>(address), sizeof(*out)};
  return process_vm_readv(getpid(), &local, 1, &remote, 1, 0) == static_cast<ssize_t>(sizeof(*out));
}

int64_t clock_ns(clockid_t clock)
{
  timespec now{};
  clock_gettime(clock, &now);
  return static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

// The deadline of a blocked wait on CLOCK_MONOTONIC, or false when it cannot be read.
bool monotonic_deadline(const SyscallWait & wait, int64_t * deadline_ns)
{
  timespec at{};
  if (!read_timespec(wait.timespec_address, &at)) {
    return false;
  }
  const int64_t ns = static_cast<int64_t>(at.tv_sec) * 1000000000 + at.tv_nsec;
  *deadline_ns = wait.clock == CLOCK_MONOTONIC ?
    ns :
    ns - (clock_ns(CLOCK_REALTIME) - clock_ns(CLOCK_MONOTONIC));
  return true;
}

struct Seen
{
  std::string schedstat;
};
}  // namespace

SyscallWait parse_syscall(const std::string & syscall_line)
{
  SyscallWait wait;
  std::istringstream in(syscall_line);
  long number = -1;
  if (!(in >> number)) {
    wait.name = syscall_line.empty() ? "unknown" : syscall_line;  // "running"
    return wait;
  }
  wait.name = "syscall " + std::to_string(number);
  std::vector<uint64_t> args;
  std::string word;
  while (args.size() < 6 && in >> word) {
    args.push_back(std::strtoull(word.c_str(), nullptr, 16));
  }
  if (!kKnownArch || args.size() < 6) {
    return wait;
  }
  if (number == kPause || number == kRtSigsuspend) {
    wait.name = number == kPause ? "pause" : "sigsuspend";
    wait.blocked = true;
  } else if (number == kRtSigtimedwait) {
    wait.name = "sigtimedwait";
    wait.blocked = args[2] == 0;  // no timeout (a relative one cannot be placed in time)
  } else if (number == kClockNanosleep) {
    wait.name = "clock_nanosleep";
    const auto clock = static_cast<clockid_t>(args[0]);
    if ((args[1] & kTimerAbstime) != 0 && (clock == CLOCK_MONOTONIC || clock == CLOCK_REALTIME)) {
      wait.blocked = true;
      wait.has_deadline = true;
      wait.clock = clock;
      wait.timespec_address = args[2];
    }
  } else if (number == kFutex) {
    wait.name = "futex";
    wait.futex = args[0];
    const uint64_t op = args[1] & kFutexCmdMask;
    const bool absolute = op == kFutexWaitBitset || op == kFutexLockPi ||
      op == kFutexWaitRequeuePi || op == kFutexLockPi2;
    if (op == kFutexWait || absolute) {
      if (args[3] == 0) {
        wait.blocked = true;
      } else if (absolute) {
        wait.blocked = true;
        wait.has_deadline = true;
        const bool realtime = op == kFutexLockPi || (args[1] & kFutexClockRealtime) != 0;
        wait.clock = realtime ? CLOCK_REALTIME : CLOCK_MONOTONIC;
        wait.timespec_address = args[3];
      }
    }
  }
  return wait;
}

pid_t current_tid()
{
  return static_cast<pid_t>(::syscall(SYS_gettid));
}

bool ProcThreadCensus::others_blocked(
  const std::vector<pid_t> & known, int64_t until_ns, std::string * culprit,
  const std::vector<pid_t> * settling, SettingUp * setting_up,
  const std::vector<pid_t> * looping) const
{
  auto say = [culprit](const std::string & why) {
    if (culprit != nullptr) {
      *culprit = why;
    }
    return false;
  };
  if (!kKnownArch) {
    return say("threads are read on x86_64 only");
  }
  std::vector<std::string> tids;
  {
    DIR * dir = opendir("/proc/self/task");
    if (dir == nullptr) {
      return say("/proc/self/task is not readable");
    }
    while (const dirent * entry = readdir(dir)) {
      if (entry->d_name[0] != '.' &&
          std::find(known.begin(), known.end(), std::atoi(entry->d_name)) == known.end())
      {
        tids.emplace_back(entry->d_name);
      }
    }
    closedir(dir);
  }
  // First pass: what each thread waits in.
  std::map<std::string, Seen> seen;
  for (const auto & tid : tids) {
    const std::string base = "/proc/self/task/" + tid;
    const std::string schedstat = read_line(base + "/schedstat");
    const SyscallWait wait = parse_syscall(read_line(base + "/syscall"));
    if (schedstat.empty()) {
      continue;  // the thread ended meanwhile
    }
    if (!wait.blocked) {
      return say("thread " + tid + " is not blocked (" + wait.name + ")");
    }
    if (wait.futex != 0 &&
        std::find(busy_futexes_.begin(), busy_futexes_.end(), wait.futex) != busy_futexes_.end())
    {
      return say("thread " + tid + " waits for the middleware's lock");
    }
    if (wait.has_deadline) {
      int64_t deadline = 0;
      if (!monotonic_deadline(wait, &deadline)) {
        return say("thread " + tid + " waits with a deadline that cannot be read");
      }
      if (deadline < until_ns) {
        return say(
          "thread " + tid + " wakes by itself (" + wait.name + ") before the quiet window ends");
      }
      const pid_t id = static_cast<pid_t>(std::atoi(tid.c_str()));
      if (settling != nullptr &&
          std::find(settling->begin(), settling->end(), id) != settling->end())
      {
        // Not a loop's wait: the thread has not used ROS since the last change (issue 50).
        if (setting_up != nullptr) {
          setting_up->tid = id;
          setting_up->wakes_at_ns = deadline;
        }
        return say(
          "thread " + tid + " waits until a deadline (" + wait.name +
          ") and has not used ROS since the last change: still setting up");
      }
      if (looping != nullptr && setting_up != nullptr &&
          std::find(looping->begin(), looping->end(), id) != looping->end() &&
          (setting_up->loop_wait_ns < 0 || deadline < setting_up->loop_wait_ns))
      {
        setting_up->loop_wait_ns = deadline;
      }
    }
    seen[tid].schedstat = schedstat;
  }
  // Second pass: nobody ran or was woken since (the first pass is one moment's picture).
  for (const auto & entry : seen) {
    const std::string base = "/proc/self/task/" + entry.first;
    if (read_line(base + "/schedstat") != entry.second.schedstat ||
        thread_state(entry.first) == 'R')
    {
      return say("thread " + entry.first + " ran while the threads were read");
    }
  }
  return true;
}

}  // namespace rmw_introspect
