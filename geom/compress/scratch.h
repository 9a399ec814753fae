#pragma once
/// \file
/// Big decoder arrays on transparent huge pages. A 1M-triangle decode fills ~150 MB of fresh
/// arrays; mapped 4 KiB at a time, first-touch page faults and the release cost about a
/// quarter of the decode. Linux maps 2 MiB pages only into memory that asks (the usual THP
/// "madvise" setting), so the codec asks for its large arrays here.

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace geom::codec::detail {

/// reserve(n), then hint huge pages for the whole 2 MiB pages of the new capacity (only
/// for arrays of 4 MiB and more; a hint: contents and behaviour do not change).
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const std::size_t bytes = v.capacity() * sizeof(T);
  if (bytes < 2 * kHuge) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}

}  // namespace geom::codec::detail
