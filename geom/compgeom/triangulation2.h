#pragma once
/// \file
/// The compact triangle structure behind delaunay_2d (internal to compgeom): flat arrays of
/// triangles, each with three vertices (counter-clockwise) and the three neighbours across
/// the edges opposite them. The convex hull is closed by "infinite" triangles that share
/// the vertex kInfinite, so every triangle has three neighbours.

#include <geom/compgeom/delaunay2.h>

#include <array>
#include <cstdint>
#include <vector>

namespace geom::detail {

constexpr std::uint32_t kInfinite = 0xFFFFFFFFu;
constexpr std::uint32_t kNoTriangle = 0xFFFFFFFFu;

struct Triangulation2 {
  /// One triangle: vertices counter-clockwise and nb[i], the triangle across the edge
  /// opposite v[i]. Kept together so a visit touches one cache line.
  struct Tri {
    std::array<std::uint32_t, 3> v;
    std::array<std::uint32_t, 3> nb;
  };
  /// v[t] and nb[t] read as two arrays over `tri`.
  template <bool kNeighbours>
  struct View {
    std::vector<Tri>* tri;
    std::array<std::uint32_t, 3>& operator[](std::size_t t) const {
      return kNeighbours ? (*tri)[t].nb : (*tri)[t].v;
    }
    std::size_t size() const { return tri->size(); }
  };

  Triangulation2() = default;
  Triangulation2(const Triangulation2&) = delete;
  Triangulation2& operator=(const Triangulation2&) = delete;

  const double* xy = nullptr;  ///< input coordinates, two per point
  std::size_t n_points = 0;
  std::vector<Tri> tri;
  View<false> v{&tri};                   ///< vertices, counter-clockwise
  View<true> nb{&tri};                   ///< nb[t][i]: across the edge opposite v[t][i]
  std::vector<std::uint8_t> dead;        ///< slot is free
  std::vector<std::uint32_t> vertex_of;  ///< representative per input point
  std::vector<std::uint32_t> order;      ///< distinct points in insertion order
  bool collinear = false;
  std::vector<std::uint32_t> chain;
  std::size_t cocircular = 0;
  PredicateStats stats;

  /// Index that Simulation of Simplicity uses for vertex i: its insertion rank. During the
  /// build vertex ids are ranks (sos is null); afterwards ids are input indices and sos
  /// points to `rank`.
  const std::uint32_t* sos = nullptr;
  std::vector<std::uint32_t> rank;

  const double* p(std::uint32_t i) const { return xy + 2 * std::size_t(i); }
  std::uint32_t sos_index(std::uint32_t i) const { return sos ? sos[i] : i; }
  bool infinite(std::uint32_t t) const {
    return v[t][0] == kInfinite || v[t][1] == kInfinite || v[t][2] == kInfinite;
  }
  /// Index (0..2) of vertex x in triangle t; 3 if absent.
  int index_of(std::uint32_t t, std::uint32_t x) const {
    return v[t][0] == x ? 0 : v[t][1] == x ? 1 : v[t][2] == x ? 2 : 3;
  }
  /// Index in nb[n] pointing back to t.
  int back_index(std::uint32_t n, std::uint32_t t) const {
    return nb[n][0] == t ? 0 : nb[n][1] == t ? 1 : 2;
  }
  /// Live finite triangles, counter-clockwise.
  std::vector<std::array<std::uint32_t, 3>> finite_triangles() const;
};

/// Builds the Delaunay triangulation (Bowyer-Watson with SoS); fills vertex_of, order,
/// collinear/chain. Throws as delaunay_2d documents.
void build_delaunay(Triangulation2& tr, const double* xy, std::size_t n, bool exact);

/// Flips the edge opposite v[t][i] (shared with its neighbour) and keeps the adjacency
/// consistent. Pre: both triangles finite and the quadrilateral strictly convex.
void flip(Triangulation2& tr, std::uint32_t t, int i);

}  // namespace geom::detail
