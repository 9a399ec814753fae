#pragma once
/// \file
/// Hoppe's attribute quadrics for the collapse engine: each triangle's attributes are an
/// affine function s(x) = G·x + d over its plane, and a vertex pays area × weight × (G·x + d
/// − s)² for its value s. The attribute values are eliminated in closed form (s is the
/// area-weighted mean of the faces' predictions at x), which leaves a 3×3 quadric in the
/// position: placement stays a 3×3 solve, and the attributes of the new vertex follow from
/// its position. Internal to geom/lod.
///
/// Values live on wedges (Hoppe's term): the corners of a vertex with equal corner values.
/// A vertex with two or more wedges lies on an attribute seam. Per-vertex properties form a
/// second channel with one block per vertex (no seams).
///
/// Ref: Hoppe, "New Quadric Metric for Simplifying Meshes with Appearance Attributes", IEEE
/// Visualization 1999; Garland, Heckbert, "Simplifying Surfaces with Color and Texture using
/// Quadric Error Metrics", IEEE Visualization 1998.

#include <geom/core/surface_mesh.h>
#include <geom/lod/quadric.h>
#include <geom/lod/simplify.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace geom::detail {

class AttributeQuadrics {
 public:
  /// Two corner wedges that become one when the triangle holding both corners collapses.
  struct WedgePair {
    std::uint32_t from, to;
  };

  /// triangles[t][k] is dense vertex i = vertex_of[i]; the corner 3t + k ends the mesh
  /// halfedge corner_halfedge[3t + k]; pos are the engine's (normalised) positions.
  /// Throws: InvalidArgument when an enabled attribute is absent, a weight is negative or
  /// not finite, or a value is not finite (naming the vertex or halfedge).
  AttributeQuadrics(const SurfaceMesh& mesh, const SimplifyAttributes& options,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const std::vector<Halfedge>& corner_halfedge,
                    const std::vector<Vertex>& vertex_of, const std::vector<Point>& pos);

  std::uint32_t wedge_count(std::uint32_t v) const { return wedge_count_[v]; }
  std::uint32_t first_wedge(std::uint32_t v) const { return wedge_begin_[v]; }
  std::uint32_t corner_wedge(std::uint32_t corner) const { return corner_wedge_[corner]; }
  void set_corner_wedge(std::uint32_t corner, std::uint32_t w) { corner_wedge_[corner] = w; }

  /// Whether removing vertex u (its wedges are pairs[i].from) keeps every seam: each wedge of
  /// u joins exactly one wedge of the survivor, and no two join the same one.
  bool keeps_seams(std::uint32_t u, const WedgePair* pairs, int n) const;
  /// The attribute error of merging a and b (wedges joined by pairs, either direction), with
  /// the attribute values already chosen optimally for each position: add it to the
  /// geometric quadric before placement.
  Quadric merged(std::uint32_t a, std::uint32_t b, const WedgePair* pairs, int n) const;
  /// Record the collapse of u into v: u's vertex data and each pairs[i].from join their
  /// partner. The caller moves u's surviving corners to the partners.
  void collapse(std::uint32_t u, std::uint32_t v, const WedgePair* pairs, int n);
  /// The partner of wedge w in pairs (w itself when absent).
  static std::uint32_t partner(std::uint32_t w, const WedgePair* pairs, int n);

  /// Write the attribute properties onto `out`, whose vertex i is dense vertex out_vertex[i]
  /// and whose faces are the live triangles live[f], in order.
  void write(SurfaceMesh& out, const std::vector<std::uint32_t>& out_vertex,
             const std::vector<std::uint32_t>& live,
             const std::vector<std::array<std::uint32_t, 3>>& triangles,
             const std::vector<Point>& pos) const;

 private:
  enum class Kind : std::uint8_t { kNormal, kTexCoord, kColor };
  struct Field {
    Kind kind;
    bool corner;            // from the corner channel
    bool vertex_prop;       // the input has the "v:" property (written back)
    bool corner_prop;       // the input has the "h:" property (written back)
    int offset, dims;       // within its channel's values
    double weight;
  };
  // One block: the weighted quadric part q (10), W (1), then B (3m) and e (m) unweighted.
  struct Channel {
    int m = 0;
    std::vector<double> weight;  // per component
    std::vector<double> data;    // stride() per block
    std::vector<double> value;   // m per block: the input value, the fallback without area
    std::vector<double> lo, hi;  // per component: the input's range
    int stride() const { return 11 + 4 * m; }
    double* block(std::size_t i) { return data.data() + i * static_cast<std::size_t>(stride()); }
    const double* block(std::size_t i) const { return data.data() + i * static_cast<std::size_t>(stride()); }
  };

  void add_field(const SurfaceMesh& mesh, Kind kind, const SimplifyAttribute& a);
  void build_wedges(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const std::vector<double>& corner_values, std::size_t n);
  void accumulate(const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<Point>& pos,
                  const std::vector<double>& vertex_values, const std::vector<double>& corner_values);
  Quadric reduce(const Channel& ch, const double* block) const;
  /// The values of block i at position x: normals unit, colours and texture coordinates
  /// within the input's range (a least-squares fit overshoots slightly at chart borders).
  void solve(bool corner, std::size_t i, const Point& x, double* s) const;

  std::vector<Field> fields_;
  Channel vertex_, corner_;
  // Per vertex: its wedges are wedge_begin_[v] .. + wedge_count_[v].
  std::vector<std::uint32_t> wedge_begin_, wedge_count_;
  std::vector<std::uint32_t> corner_wedge_;
};

}  // namespace geom::detail
