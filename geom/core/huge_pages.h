#pragma once
/// \file
/// Transparent huge pages for the big flat arrays of the mesh algorithms. Refinement,
/// simplification and decoding fill or read hundreds of megabytes of fresh arrays; on 4 KiB
/// pages the first-touch page faults and TLB misses cost a quarter to a third of their time.
/// Linux maps 2 MiB pages only into memory that asks (the usual THP "madvise" setting), so
/// these arrays ask here, in one place. A hint only: contents and behaviour never change, and
/// on other systems it does nothing.

#include <cstddef>
#include <vector>

namespace geom::detail {

/// Arrays smaller than this gain nothing from the hint.
inline constexpr std::size_t kHugePageMinBytes = std::size_t{4} << 20;

/// Ask for huge pages on the whole 2 MiB pages inside [data, data + bytes).
void advise_huge_pages(const void* data, std::size_t bytes) noexcept;

/// v.reserve(n), with the hint on the new capacity when it is large.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  const std::size_t bytes = v.capacity() * sizeof(T);
  if (bytes >= kHugePageMinBytes) advise_huge_pages(v.data(), bytes);
}

}  // namespace geom::detail
