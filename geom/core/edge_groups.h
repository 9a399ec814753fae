#pragma once
/// \file
/// Internal to geom/core (build.cpp, topology.cpp): the undirected edges of an indexed face
/// list, grouped in flat arrays. Each corner c of face f stands for the halfedge from its
/// vertex to the next corner's. Halfedges are bucketed by their smaller endpoint (a counting
/// sort, CSR) and sorted inside the short bucket by the larger one, so the halfedges of one
/// undirected edge sit side by side, in corner order. No hashing, no per-element allocation.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace geom::detail {

struct EdgeEntry {
  std::uint32_t other;   ///< the larger endpoint
  std::uint32_t corner;  ///< the corner whose halfedge this is
};

struct EdgeGroups {
  std::vector<std::uint32_t> start;  ///< bucket of smaller endpoint v: [start[v], start[v+1])
  std::vector<EdgeEntry> entries;

  /// Calls fn(key, first, last) for each undirected edge (key, entries[first].other) whose
  /// halfedges are entries[first .. last).
  template <class Fn>
  void for_each_edge(Fn&& fn) const {
    std::uint32_t nv = start.empty() ? 0 : static_cast<std::uint32_t>(start.size() - 1);
    for (std::uint32_t v = 0; v < nv; ++v) {
      std::uint32_t i = start[v], end = start[v + 1];
      while (i < end) {
        std::uint32_t j = i + 1;
        while (j < end && entries[j].other == entries[i].other) ++j;
        fn(v, i, j);
        i = j;
      }
    }
  }
  /// The [first, last) range of edge (a, b) in entries, or an empty range.
  std::pair<std::uint32_t, std::uint32_t> find(std::uint32_t a, std::uint32_t b) const {
    if (a > b) std::swap(a, b);
    if (a + 1 >= start.size()) return {0, 0};
    auto first = entries.begin() + start[a], last = entries.begin() + start[a + 1];
    auto lo = std::lower_bound(first, last, b, [](const EdgeEntry& e, std::uint32_t x) { return e.other < x; });
    auto hi = lo;
    while (hi != last && hi->other == b) ++hi;
    return {static_cast<std::uint32_t>(lo - entries.begin()),
            static_cast<std::uint32_t>(hi - entries.begin())};
  }
};

/// Group the halfedges of faces `offsets`/`corners` (vertex ids < n_vertices). Halfedges
/// from a vertex to itself are left out.
inline EdgeGroups group_edges(std::uint32_t n_vertices, std::span<const std::uint32_t> offsets,
                              std::span<const std::uint32_t> corners) {
  EdgeGroups g;
  g.start.assign(static_cast<std::size_t>(n_vertices) + 1, 0);
  std::size_t nf = offsets.empty() ? 0 : offsets.size() - 1;
  auto each_halfedge = [&](auto&& fn) {
    for (std::size_t f = 0; f < nf; ++f) {
      std::uint32_t b = offsets[f], e = offsets[f + 1];
      if (b == e) continue;
      for (std::uint32_t c = b; c < e; ++c) {
        std::uint32_t a = corners[c], z = corners[c + 1 == e ? b : c + 1];
        if (a != z) fn(c, a, z);
      }
    }
  };
  // Counting sort without a second offsets array: after the prefix sum start[v + 1] is the
  // end of bucket v; the scatter fills each bucket from its end down, leaving start[v + 1]
  // at the bucket's begin, and a rotate moves it to start[v].
  each_halfedge([&](std::uint32_t, std::uint32_t a, std::uint32_t z) { ++g.start[std::min(a, z) + 1]; });
  for (std::uint32_t v = 0; v < n_vertices; ++v) g.start[v + 1] += g.start[v];
  g.entries.resize(g.start[n_vertices]);
  // Filling backwards over corners in reverse keeps each bucket in corner order.
  for (std::size_t f = nf; f-- > 0;) {
    std::uint32_t b = offsets[f], e = offsets[f + 1];
    for (std::uint32_t c = e; c-- > b;) {
      std::uint32_t a = corners[c], z = corners[c + 1 == e ? b : c + 1];
      if (a != z) g.entries[--g.start[std::min(a, z) + 1]] = {std::max(a, z), c};
    }
  }
  // Now start[v + 1] is the begin of bucket v; shift to make start[v] the begin of bucket v.
  std::rotate(g.start.begin(), g.start.begin() + 1, g.start.end());
  g.start.back() = static_cast<std::uint32_t>(g.entries.size());
  // Buckets are short (about the valence); insertion sort keeps corner order among equals.
  for (std::uint32_t v = 0; v < n_vertices; ++v) {
    EdgeEntry* first = g.entries.data() + g.start[v];
    EdgeEntry* last = g.entries.data() + g.start[v + 1];
    if (last - first < 2) continue;  // (and first + 1 below would offset a null pointer)
    if (last - first > 32) {
      std::stable_sort(first, last, [](const EdgeEntry& x, const EdgeEntry& y) { return x.other < y.other; });
      continue;
    }
    for (EdgeEntry* i = first + 1; i < last; ++i) {
      EdgeEntry x = *i;
      EdgeEntry* j = i;
      while (j > first && (j - 1)->other > x.other) {
        *j = *(j - 1);
        --j;
      }
      *j = x;
    }
  }
  return g;
}

}  // namespace geom::detail
