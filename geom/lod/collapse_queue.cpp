// The collapse engine's priority queue (see collapse.h): a radix heap over the cost's float
// bits, whose buckets hold their entries in chunks of a shared pool.

#include <geom/lod/collapse.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <new>

namespace geom::detail {

inline int CollapseEngine::RadixQueue::bucket(std::uint32_t k) const {
  return k == last_ ? 0 : 32 - std::countl_zero(k ^ last_);
}

void CollapseEngine::RadixQueue::SlabDelete::operator()(Candidate* p) const noexcept {
  ::operator delete(p, std::align_val_t{kHugePageBytes});
}

void CollapseEngine::RadixQueue::grow_pool(std::size_t chunks) {
  // Aligned to a huge page so that the hint covers the whole slab.
  const std::size_t bytes = chunks * kChunk * sizeof(Candidate);
  auto* slab = static_cast<Candidate*>(::operator new(bytes, std::align_val_t{kHugePageBytes}));
  slabs_.emplace_back(slab);
  advise_huge_pages(slab, bytes);
  // Handed out from the lowest address up.
  for (std::size_t k = chunks; k-- > 0;) free_.push_back(slab + k * kChunk);
}

void CollapseEngine::RadixQueue::push(Candidate c) {
  std::uint32_t k = key(c.cost);
  if (k < last_) {
    // Below the entries still in the buckets: its place is among those taken ahead.
    std::size_t at = n_ahead_++;
    for (; at > 0 && key(ahead(at - 1).cost) > k; --at) ahead(at) = ahead(at - 1);
    ahead(at) = c;
    if (n_ahead_ <= kAheadMax) return;
    // Full: the dearest goes back, at last_ (its true cost is at most that).
    c = ahead(--n_ahead_);
    k = last_;
    c.cost = std::bit_cast<float>(k);
  }
  append(buckets_[bucket(k)], c);
  ++size_;
}

void CollapseEngine::RadixQueue::assign(const std::vector<EdgeBlock>& blocks) {
  // What settle() would do with them all in one bucket.
  last_ = 0xffffffffu;
  size_ = 0;
  for (const EdgeBlock& b : blocks) {
    for (std::size_t i = 0; i < b.size; ++i) last_ = std::min(last_, key(b.edges[i].cost));
    size_ += b.size;
  }
  if (size_ == 0) {
    last_ = 0;
    return;
  }
  // One slab for them all, with a partial chunk per bucket to spare.
  grow_pool(size_ / kChunk + buckets_.size());
  for (const EdgeBlock& b : blocks)
    for (std::size_t i = 0; i < b.size; ++i)
      append(buckets_[bucket(key(b.edges[i].cost))], b.edges[i]);
}

CollapseEngine::EdgeBlock CollapseEngine::RadixQueue::release() {
  EdgeBlock out;
  out.edges.reset(new Candidate[n_ahead_ + size_]);
  auto keep = [&](const Candidate& c) {
    if (current(c)) out.edges[out.size++] = c;
  };
  for (std::size_t k = 0; k < n_ahead_; ++k) keep(ahead(k));
  for (const Bucket& b : buckets_)
    for (std::size_t k = 0; k < b.chunks.size(); ++k) {
      const Candidate* chunk = b.chunks[k];
      const Candidate* stop = k + 1 < b.chunks.size() ? chunk + kChunk : b.end;
      for (const Candidate* c = chunk; c != stop; ++c) keep(*c);
    }
  const std::uint32_t* stamps = stamps_;
  *this = RadixQueue();
  watch(stamps);
  return out;
}

void CollapseEngine::RadixQueue::settle() {
  while (buckets_[0].empty() && size_ > 0) {
    int i = 1;
    while (buckets_[i].empty()) ++i;
    // Every entry of bucket i shares the bits above i with last_; the new minimum splits
    // them into lower buckets, each entry moving at least one bucket down. Outdated entries
    // are dropped on the way, their stamps fetched well ahead so that the misses overlap.
    Bucket& from = buckets_[i];
    std::uint32_t lowest = 0xffffffffu;
    const std::size_t n_chunks = from.chunks.size(), n = from.size();
    // Kept entries are written back from the start, at w in chunk wk.
    std::size_t wk = 0;
    Candidate* w = from.chunks[0];
    Candidate* w_limit = w + kChunk;
    for (std::size_t k = 0; k < n_chunks; ++k) {
      const Candidate* chunk = from.chunks[k];
      const Candidate* stop = k + 1 < n_chunks ? chunk + kChunk : from.end;
      // The fetches ahead read on into the next chunk.
      const Candidate* next = k + 1 < n_chunks ? from.chunks[k + 1] : nullptr;
      const Candidate* next_stop = k + 2 < n_chunks ? next + kChunk : from.end;
      for (const Candidate* e = chunk; e != stop; ++e) {
        const Candidate* later = nullptr;
        if (stop - e > 16) later = e + 16;
        else if (next && 16 - (stop - e) < next_stop - next) later = next + (16 - (stop - e));
        if (later) {
          __builtin_prefetch(&stamps_[later->a]);
          __builtin_prefetch(&stamps_[later->b]);
        }
        const Candidate c = *e;
        if (!current(c)) continue;
        lowest = std::min(lowest, key(c.cost));
        if (w == w_limit) {
          w = from.chunks[++wk];
          w_limit = w + kChunk;
        }
        *w++ = c;
      }
    }
    const std::size_t kept = wk * kChunk + static_cast<std::size_t>(w - from.chunks[wk]);
    size_ -= n - kept;
    if (kept > 0) {
      last_ = lowest;
      // Each chunk goes back to the pool once read, for the lower buckets to refill.
      for (std::size_t k = 0; k <= wk; ++k) {
        const Candidate* chunk = from.chunks[k];
        const Candidate* stop = k < wk ? chunk + kChunk : w;
        for (const Candidate* c = chunk; c != stop; ++c) append(buckets_[bucket(key(c->cost))], *c);
        free_.push_back(from.chunks[k]);
      }
      for (std::size_t k = wk + 1; k < n_chunks; ++k) free_.push_back(from.chunks[k]);
    } else {
      for (Candidate* chunk : from.chunks) free_.push_back(chunk);
    }
    from.chunks.clear();
    from.end = from.limit = nullptr;
  }
}

void CollapseEngine::RadixQueue::top_up() {
  Bucket& first = buckets_[0];
  while (n_ahead_ < kAhead) {
    settle();
    if (size_ == 0) return;
    const Candidate c = *--first.end;
    if (first.end == first.chunks.back()) {
      // Its last chunk is empty now.
      free_.push_back(first.chunks.back());
      first.chunks.pop_back();
      first.end = first.limit = first.chunks.empty() ? nullptr : first.chunks.back() + kChunk;
    }
    --size_;
    if (!current(c)) continue;
    // Not cheaper than anything ahead: it goes last.
    ahead(n_ahead_++) = c;
  }
}

const CollapseEngine::Candidate* CollapseEngine::RadixQueue::top() {
  for (;;) {
    top_up();
    if (n_ahead_ == 0) return nullptr;
    if (current(ahead(0))) return &ahead(0);
    drop_top();
  }
}

}  // namespace geom::detail
