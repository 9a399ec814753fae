// The collapse loop: drain() takes entries from one queue on one core; run() drains the one
// queue of a small mesh, or on a large one the queues of regions on all cores, with the same
// result on any number of cores.
//
// Costs are local, so the greedy order over the whole mesh interleaves independent greedy
// orders over regions far apart. The vertices get kParts fixed labels (median splits of a
// sample of the positions, independent of the thread count); a vertex with a neighbour of
// another label is seam. Invariant: every neighbour of a non-seam vertex has its label.
//
// Why parts need no locks (we have no ThreadSanitizer build; this is the argument): a
// collapse of an edge whose ends are non-seam vertices of part k reads and writes only
// vertices of label k (the two ends and their neighbours, whose triangle lists lose the
// dying triangles) and triangles whose corners all have label k, and it leaves the ends'
// neighbours within label k, so the invariant stands. A part queues again the edges of a
// neighbour only when that neighbour is non-seam (a seam one is left to the seam), and its
// prefetches read the ends of its own entries, label k too. So what a part writes (vertex
// records, stamps, triangles, its queue, its room in refs_, merged_into_) belongs to
// vertices or triangles no other part reads, and label_ and region_ change only between
// steps. The seam worker marks vertices of every label between steps: marks are compared
// for equality only and each worker draws its tokens from a range of its own.
//
// A seam vertex's edges, and an entry whose end became seam, go to the seam's queue,
// collapsed on one thread between steps; such a collapse can join labels, so extend_seam()
// makes the survivor and its neighbours of other labels seam.
//
// The steps are bulk-synchronous: a step collapses, in every part, the entries up to the
// key `limit` (what the global greedy order would collapse up to there, the seam aside),
// at most an equal share of the triangles left to remove each, then the seam's entries up
// to `limit`, then raises the limit. Seam entries wait at most a step; the last triangles
// to remove (at least kTailMin) go in the strict global order, all queues merged into one.
// The order is not the one-core order, but as good: on the 1M-triangle torus and the large
// real meshes the Hausdorff and RMS errors stay within noise of it.

#include <geom/lod/collapse.h>

#include <geom/core/huge_pages.h>

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <limits>

namespace geom::detail {

namespace {

template <class Body>
void for_range(std::size_t n, std::size_t grain, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
                    });
}

constexpr std::uint32_t kNoKey = 0xffffffffu;
// The limit grows by this factor a step: smaller steps delay seam collapses less, at the
// price of more barriers. Over amo, armadillo and nefertiti at 10% and 1% (all parallel),
// the RMS error against the one-core order went from 1.016× (geometric mean, growth 2) to
// 1.004× (√2) and 1.0025× (2^¼); the Hausdorff error, a single worst point, moved by
// 1.09×, 1.06× and 1.056×, as much as the one-core order's moves when its priorities are
// jittered by 1% (1.066×). On the 1M torus at 1%: 77 steps.
constexpr float kStepGrowth = 1.1892071f;
// Below this many triangles to remove (or 1/kTailShare of the input), one global order:
// with about a thousand triangles a part, seams are much of the mesh. Over the six cases
// above, a tail of 10k rather than 1k took the Hausdorff error from 1.054× the one-core
// order's to 0.98× (RMS 0.999× to 0.997×), for at most 5k collapses on one core.
constexpr std::size_t kTailMin = 10000, kTailShare = 100;

}  // namespace

SimplifyStop CollapseEngine::run(std::size_t target) {
  run_start_ = alive_triangles_;
  run_target_ = std::min(target, alive_triangles_);
  if (parts_ > 0) return run_parallel(target);
  const std::size_t faces = alive_triangles_ - std::min(alive_triangles_, target);
  const Drain end = drain(workers_[0], {kNoKey, faces, false});
  if (end == Drain::kCancelled) return SimplifyStop::kCancelled;
  if (end == Drain::kDone) return SimplifyStop::kTargetReached;
  return workers_[0].error_rejected ? SimplifyStop::kMaxError : SimplifyStop::kNoValidCollapse;
}

void CollapseEngine::partition(const std::vector<Point>& pos) {
  const std::size_t n = pos.size();
  // Split planes from a sample: parts need only similar sizes, not exact medians.
  std::vector<std::uint32_t> sample;
  const std::size_t stride = std::max<std::size_t>(1, n / 16384);
  for (std::size_t i = 0; i < n; i += stride) sample.push_back(static_cast<std::uint32_t>(i));
  // A complete binary tree in heap order; leaf kParts - 1 + k is part k.
  struct Split {
    int axis = 0;
    double at = 0;
  };
  std::array<Split, kParts - 1> tree{};
  auto split = [&](auto& self, std::size_t node, std::size_t first, std::size_t last) -> void {
    if (node >= kParts - 1) return;
    if (last - first >= 2) {
      Eigen::AlignedBox3d box;
      box.setEmpty();
      for (std::size_t i = first; i < last; ++i) box.extend(pos[sample[i]]);
      int axis = 0;
      box.sizes().maxCoeff(&axis);
      const std::size_t mid = (first + last) / 2;
      // A strict order even over NaN coordinates (last), ties broken by index: the same split
      // whatever nth_element's internal order.
      auto coord = [&](std::uint32_t v) {
        const double x = pos[v][axis];
        return x == x ? x : std::numeric_limits<double>::infinity();
      };
      std::nth_element(sample.begin() + first, sample.begin() + mid, sample.begin() + last,
                       [&](std::uint32_t a, std::uint32_t b) {
                         return coord(a) != coord(b) ? coord(a) < coord(b) : a < b;
                       });
      tree[node] = {axis, coord(sample[mid])};
    } else {
      tree[node] = {0, std::numeric_limits<double>::infinity()};
    }
    const std::size_t mid = (first + last) / 2;
    self(self, 2 * node + 1, first, mid);
    self(self, 2 * node + 2, mid, last);
  };
  split(split, 0, 0, sample.size());
  label_.resize(n);
  region_.resize(n);
  for_range((n + 4095) / 4096, 1, [&](std::size_t block) {
    for (std::size_t v = block * 4096; v < std::min(n, (block + 1) * 4096); ++v) {
      std::size_t node = 0;
      while (node < kParts - 1) node = 2 * node + 1 + (pos[v][tree[node].axis] >= tree[node].at);
      label_[v] = static_cast<std::uint8_t>(node - (kParts - 1));
    }
  });
  for_range((n + 4095) / 4096, 1, [&](std::size_t block) {
    for (std::size_t v = block * 4096; v < std::min(n, (block + 1) * 4096); ++v) {
      std::uint8_t r = label_[v];
      for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i)
        for (std::uint32_t w : triangles_[refs_[i]])
          if (label_[w] != label_[v]) r = kSeam;
      region_[v] = r;
    }
  });
  parts_ = kParts;
}

void CollapseEngine::start_workers(std::vector<EdgeBlock>& blocks, std::uint32_t first_token,
                                   std::size_t refs_end) {
  workers_ = std::vector<Worker>(parts_ + 1);
  // Disjoint token ranges (see Worker::token); the serial path keeps its one worker's.
  const auto span =
      (0xffffffffu - first_token) / static_cast<std::uint32_t>(workers_.size());
  for (std::size_t k = 0; k < workers_.size(); ++k) {
    workers_[k].queue.watch(stamp_.data());
    workers_[k].part = static_cast<std::uint8_t>(k);
    workers_[k].token = first_token + static_cast<std::uint32_t>(k) * span;
  }
  share_refs(refs_end);
  if (parts_ == 0) {
    workers_[0].queue.assign(blocks);
    return;
  }
  // Each block's entries go, in order, to the queue of their part or to the seam's.
  const std::size_t nq = workers_.size();
  std::vector<std::vector<EdgeBlock>> split(nq);
  for (auto& s : split) s.resize(blocks.size());
  for_range(blocks.size(), 1, [&](std::size_t b) {
    const EdgeBlock& from = blocks[b];
    std::vector<std::size_t> count(nq, 0);
    auto dest = [&](const Candidate& c) -> std::size_t {
      const std::uint8_t r = region_[c.a];
      return r != kSeam && r == region_[c.b] ? r : parts_;
    };
    for (std::size_t i = 0; i < from.size; ++i) ++count[dest(from.edges[i])];
    for (std::size_t q = 0; q < nq; ++q) split[q][b].edges.reset(new Candidate[count[q]]);
    for (std::size_t i = 0; i < from.size; ++i) {
      EdgeBlock& to = split[dest(from.edges[i])][b];
      to.edges[to.size++] = from.edges[i];
    }
  });
  blocks.clear();
  for_range(nq, 1, [&](std::size_t q) { workers_[q].queue.assign(split[q]); });
}

void CollapseEngine::compact_refs(std::size_t capacity) {
  std::unique_ptr<std::uint32_t[]> fresh(new std::uint32_t[capacity]);
  advise_huge_pages(fresh.get(), capacity * sizeof(std::uint32_t));
  std::size_t end = 0;
  for (std::size_t v = 0; v < vd_.size(); ++v) {
    const std::uint32_t begin = vd_[v].ref_begin, size = vd_[v].ref_size;
    vd_[v].ref_begin = static_cast<std::uint32_t>(end);
    std::copy(refs_.get() + begin, refs_.get() + begin + size, fresh.get() + end);
    end += size;
  }
  refs_ = std::move(fresh);
  refs_capacity_ = capacity;
  share_refs(end);
}

void CollapseEngine::share_refs(std::size_t end) {
  // Equal shares of the room after the live lists; the serial path's one worker takes it all.
  const std::size_t share = (refs_capacity_ - end) / workers_.size();
  for (std::size_t k = 0; k < workers_.size(); ++k) {
    workers_[k].ref_end = end + k * share;
    workers_[k].ref_limit = k + 1 < workers_.size() ? end + (k + 1) * share : refs_capacity_;
  }
}

void CollapseEngine::extend_seam(std::uint32_t v) {
  const std::uint8_t own = label_[v];
  bool mixed = false;
  for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i)
    for (std::uint32_t w : triangles_[refs_[i]])
      if (label_[w] != own) {
        region_[w] = kSeam;
        mixed = true;
      }
  if (mixed) region_[v] = kSeam;
}

void CollapseEngine::merge_queues() {
  std::vector<EdgeBlock> blocks;
  for (Worker& w : workers_) blocks.push_back(w.queue.release());
  RadixQueue& seam = workers_[parts_].queue;
  seam.assign(blocks);
  merged_ = true;
}

SimplifyStop CollapseEngine::run_parallel(std::size_t target) {
  Worker& seam = workers_[parts_];
  const std::size_t tail = std::max(kTailMin, triangles_.size() / kTailShare);
  auto lowest_key = [&](std::size_t first, std::size_t last) {
    std::uint32_t k = kNoKey;
    for (std::size_t q = first; q < last; ++q)
      if (const Candidate* c = workers_[q].queue.top()) k = std::min(k, RadixQueue::key(c->cost));
    return k;
  };
  std::uint32_t limit = lowest_key(0, workers_.size());
  std::array<Drain, kParts> ends{};
  std::array<std::size_t, kParts> removed{};
  while (alive_triangles_ > target + tail && limit < 0x7f800000u &&
         lowest_key(0, parts_) != kNoKey) {
    const std::size_t share = (alive_triangles_ - target) / parts_;
    for_range(parts_, 1, [&](std::size_t k) {
      Worker& w = workers_[k];
      const std::size_t before = w.removed;
      w.in_step = true;
      ends[k] = drain(w, {limit, share, true});
      w.in_step = false;
      removed[k] = w.removed - before;
    });
    // The barrier: in part order, so the seam's queue does not depend on the schedule.
    bool cut = false, room = false;
    std::size_t step_removed = 0;
    for (std::size_t k = 0; k < parts_; ++k) {
      Worker& w = workers_[k];
      alive_triangles_ -= removed[k];
      step_removed += removed[k];
      cut |= ends[k] == Drain::kDone || ends[k] == Drain::kRoom;
      room |= ends[k] == Drain::kRoom;
      for (const Candidate& c : w.staged) seam.queue.push(c);
      w.staged.clear();
    }
    for (std::size_t k = 0; k < parts_; ++k) {
      for (std::uint32_t v : workers_[k].staged_retry) push_vertex_edges(seam, v, true);
      workers_[k].staged_retry.clear();
    }
    if (room) {
      std::size_t live = 0;
      for (const VertexData& d : vd_) live += d.ref_size;
      compact_refs(std::max(refs_capacity_, 2 * live + 64 * workers_.size()));
      // Not even a fresh share held the next collapse: leave the rest to the serial order.
      if (step_removed == 0) break;
    }
    if (alive_triangles_ > target &&
        drain(seam, {limit, alive_triangles_ - target, false}) == Drain::kCancelled)
      return SimplifyStop::kCancelled;
    if (options_.progress && !options_.progress(progress())) return SimplifyStop::kCancelled;
    // Every part reached the limit: raise it, at least to the cheapest entry left.
    if (!cut) {
      const float grown = std::bit_cast<float>(limit) * kStepGrowth;
      // (+1: a zero limit does not grow by a factor.)
      limit = std::max({RadixQueue::key(grown), lowest_key(0, workers_.size()), limit + 1});
    }
  }
  // The tail drains one queue, as the serial path does: its collapses are fetched ahead,
  // and no pop compares nine queues' heads. The order is the same up to ties between
  // queues (bench_lod's error matrix: the same to three digits); the tail's time moved
  // within noise (bunny at 10%, 9.6k triangles: 9.3-9.9 ms to 8.8, best of 15).
  merge_queues();
  const Drain end = drain(seam, {kNoKey, alive_triangles_ - std::min(alive_triangles_, target),
                                 false});
  if (end == Drain::kCancelled) return SimplifyStop::kCancelled;
  if (end == Drain::kDone) return SimplifyStop::kTargetReached;
  for (const Worker& w : workers_)
    if (w.error_rejected) return SimplifyStop::kMaxError;
  return SimplifyStop::kNoValidCollapse;
}

}  // namespace geom::detail
