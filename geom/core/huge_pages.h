#pragma once
/// \file
/// Transparent huge pages for the big flat arrays of the mesh algorithms. Refinement,
/// simplification and decoding fill or read hundreds of megabytes of fresh arrays; on 4 KiB
/// pages the first-touch page faults and TLB misses cost a quarter to a third of their time.
/// Linux maps 2 MiB pages only into memory that asks (the usual THP "madvise" setting), so
/// these arrays ask here, in one place; arrays that are filled as soon as they are sized
/// (SurfaceMesh::resize) have their pages mapped in one call instead (prefault). Hints only:
/// contents and behaviour never change, and on other systems they do nothing. Arrays that
/// are written whole right after sizing can also skip the clearing (UninitialisedVector).

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
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

/// An allocator whose value-less construct() leaves the element uninitialised, so that
/// resize() of a buffer about to be overwritten whole does not clear it first: decoders'
/// outputs, written once in full (for a 1M-triangle mesh, 18 MB not written twice).
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <class U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A vector whose resize() without a value leaves the new elements uninitialised.
template <class T>
using UninitialisedVector = std::vector<T, UninitialisedAllocator<T>>;

/// v.reserve(n), with the hint on the new capacity when it is large.
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
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
