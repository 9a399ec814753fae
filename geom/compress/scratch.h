#pragma once
/// \file
/// One block of stage-local memory that the decoder's stages hand on to each other. The
/// connectivity step's gates are dead once the degree pass starts, so the pass builds its
/// wedges and vertex records in the pages the gates touched instead of fresh ones: the
/// kernel clears every fresh page, about a tenth of a large decode's time.

#include <geom/core/huge_pages.h>

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

namespace geom::codec::detail {

class Scratch {
 public:
  /// Room for `bytes` from here on; growing discards the contents.
  void reserve(std::size_t bytes) {
    if (bytes <= size_) return;
    // new[] without an initialiser: the pages stay untouched until a stage writes them.
    block_.reset(new std::byte[bytes]);
    size_ = bytes;
    if (bytes >= geom::detail::kHugePageMinBytes)
      geom::detail::advise_huge_pages(block_.get(), bytes);
  }
  /// n uninitialised objects of the trivial type T at byte offset `at` (a multiple of
  /// alignof(T)); whatever an earlier stage kept there is dead. Pre: reserve(at + n·sizeof(T)).
  template <class T>
  T* array(std::size_t at, std::size_t n) {
    static_assert(std::is_trivially_default_constructible_v<T> &&
                  std::is_trivially_destructible_v<T>);
    if (n == 0) return nullptr;  // an empty stage may have no block to place into
    return std::launder(::new (block_.get() + at) T[n]);
  }

 private:
  std::unique_ptr<std::byte[]> block_;
  std::size_t size_ = 0;
};

}  // namespace geom::codec::detail
