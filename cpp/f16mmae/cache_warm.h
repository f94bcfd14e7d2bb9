// Cache warm-up: bring an object's bytes into this core's caches ahead of a step that has a
// deadline. A frame-driven estimator idles between frames (15.6 ms at 64 Hz) while other
// processes run; its working set (the on-line filters' matrices and states) is evicted and
// the next step runs from memory, several times slower than warm. Touching the working set
// shortly before the frame is due makes the step run from cache again.
//
//   touch_lines(p, n)  one read per 64-byte line of [p, p + n): a volatile load, not a
//                      prefetch hint, so it is neither dropped on a TLB miss nor elided.
//   touch(obj)         touch_lines(&obj, sizeof obj), for objects that hold their data
//                      inline (fixed-size Eigen matrices, std::array).
// Reads only; noexcept; allocation-free.
#pragma once

#include <cstddef>

namespace f16mmae {

inline constexpr std::size_t kCacheLine = 64;

inline void touch_lines(const void* p, std::size_t bytes) noexcept {
  const volatile unsigned char* b = static_cast<const volatile unsigned char*>(p);
  for (std::size_t i = 0; i < bytes; i += kCacheLine) (void)b[i];
  if (bytes > 0) (void)b[bytes - 1];  // the last line, when bytes is not a multiple of a line
}

template <class T>
void touch(const T& obj) noexcept {
  touch_lines(&obj, sizeof(T));
}

}  // namespace f16mmae
