#pragma once
// Per-thread scratch vectors that outlive the call (the camera edge field's buffers, the window's row blocks).
#include <cstddef>
#include <vector>

namespace quasiloc::estimation::detail
{
/** `v` holds at least n elements afterwards; their values are whatever was there (the caller writes every
 *  element it reads). It never shrinks: the calls alternate between sizes (the pyramid levels change threads from
 *  frame to frame, the window's edge and surface blocks take turns), and a resize down then up would zero the
 *  regrown part, megabytes per call. */
template <class T>
void growScratch(std::vector<T>& v, size_t n)
{
    if (v.size() < n) v.resize(n);
}
}  // namespace quasiloc::estimation::detail
