#pragma once
/// \file
/// Transparent huge pages for the big flat arrays of the mesh algorithms. Refinement,
/// simplification and decoding fill or read hundreds of megabytes of fresh arrays; on 4 KiB
/// pages the first-touch page faults and TLB misses cost a quarter to a third of their time.
/// Linux maps 2 MiB pages only into memory that asks (the usual THP "madvise" setting), so
/// these arrays ask here, in one place; arrays that are filled as soon as they are sized
/// (SurfaceMesh::resize) have their pages mapped in one call instead (prefault). Hints only:
/// contents and behaviour never change, and on other systems they do nothing.

#include <cstddef>
#include <vector>

namespace geom::detail {

/// The size (and alignment) of a huge page on x86-64 and most AArch64 Linux systems.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Arrays smaller than this gain nothing from the hint.
inline constexpr std::size_t kHugePageMinBytes = std::size_t{4} << 20;

/// Ask for huge pages on the whole 2 MiB pages inside [data, data + bytes).
void advise_huge_pages(const void* data, std::size_t bytes) noexcept;

/// Map the whole pages inside [data, data + bytes) now, writable, in one system call: the
/// kernel still clears every page, but skips the fault taken on the first write to each
/// 4 KiB page, about a third of the cost of filling fresh memory. Unlike the huge-page
/// hint it asks for nothing the machine may be short of (no 2 MiB blocks, no compaction),
/// so it pays in a cold process as much as in a warm one. A hint only, like the above.
void prefault(void* data, std::size_t bytes) noexcept;

/// v.reserve(n), with the hint on the new capacity when it is large.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  const std::size_t bytes = v.capacity() * sizeof(T);
  if (bytes >= kHugePageMinBytes) advise_huge_pages(v.data(), bytes);
}

/// v.resize(n, fill...) for arrays that grow by megabytes in one step (builders sizing a
/// whole mesh): the new elements' pages are mapped by prefault() before the fill writes
/// them. Capacity grows as resize would grow it (at least doubling), so repeated calls
/// stay amortised O(1) per element.
template <class T, class... Fill>
void resize_prefaulted(std::vector<T>& v, std::size_t n, const Fill&... fill) {
  const std::size_t old = v.size();
  if (n > v.capacity() && (n - old) * sizeof(T) >= kHugePageMinBytes) {
    v.reserve(n > 2 * old ? n : 2 * old);
    prefault(v.data() + old, (n - old) * sizeof(T));
  }
  v.resize(n, fill...);
}

}  // namespace geom::detail
