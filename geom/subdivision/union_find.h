#pragma once
/// \file
/// Internal: union-find over dense indices (face corners), with path halving.

#include <cstdint>
#include <numeric>
#include <vector>

namespace geom::detail::subdiv {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace geom::detail::subdiv
