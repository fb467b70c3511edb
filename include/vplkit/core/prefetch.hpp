// SPDX-License-Identifier: MIT
#pragma once
// A hint to bring the cache line at p towards the core before it is read: for loops that know
// several independent addresses ahead of their arithmetic (RIS candidates: a batch of texels drawn
// first, evaluated after), so that the memory latencies overlap instead of queueing one after the
// other. No effect on any value; nothing on compilers without the builtin. (No GLSL counterpart:
// a GPU hides latency with other threads.)

// Functions made only of prefetches have no effect that GCC's analysis counts: left out of line,
// their calls are removed as dead code. So they are always inlined (the prefetch then stays).
#if defined(__GNUC__) || defined(__clang__)
#define VPLKIT_PREFETCH_INLINE inline __attribute__((always_inline))
#else
#define VPLKIT_PREFETCH_INLINE inline
#endif

namespace vplkit {

template <class P>
VPLKIT_PREFETCH_INLINE void prefetch_read(const P* p) noexcept {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(static_cast<const void*>(p), 0, 3);
#else
  (void)p;
#endif
}

namespace detail {
template <class D, class T>
VPLKIT_PREFETCH_INLINE auto distribution_prefetch_impl(const D& d, T u, int) -> decltype(d.prefetch_sample(u), void()) {
  d.prefetch_sample(u);
}
template <class D, class T>
VPLKIT_PREFETCH_INLINE void distribution_prefetch_impl(const D&, T, long) {}
}  // namespace detail

// d.prefetch_sample(u) where the distribution has one (it asks for the first memory that
// d.sample(u) reads), else nothing.
template <class D, class T>
VPLKIT_PREFETCH_INLINE void distribution_prefetch(const D& d, T u) {
  detail::distribution_prefetch_impl(d, u, 0);
}

}  // namespace vplkit
