// SPDX-License-Identifier: MIT
#pragma once
// CPU time of the calling thread, for the CPU passes' own cost (the JSON's `*_cpu_ms`): unlike the
// stages' wall times it does not grow when the machine's other processes take the cores, so the
// ratio of two passes' CPU times is their cost ratio on a loaded machine too.
#include <ctime>

namespace vplrender {

// Seconds of CPU time the calling thread has used (POSIX CLOCK_THREAD_CPUTIME_ID); 0 where the
// clock is missing (then the `*_cpu_ms` values read 0).
inline double thread_cpu_seconds() {
#if defined(CLOCK_THREAD_CPUTIME_ID)
  timespec t{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) == 0) return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
#endif
  return 0.0;
}

}  // namespace vplrender
