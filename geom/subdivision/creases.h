#pragma once
/// \file
/// Crease sharpness: OpenSubdiv's rules for how sharpness decays from level to level and
/// which vertex rule (smooth, dart, crease, corner) applies, plus automatic creases by
/// dihedral angle. Sharpness is single precision here on purpose: OpenSubdiv stores it as
/// float, and fractional weights computed from 2.7f differ from those of 2.7 by 1e-8.
///
/// Ref: T. DeRose, M. Kass, T. Truong, "Subdivision surfaces in character animation",
/// SIGGRAPH 1998; OpenSubdiv 3 Sdc::Crease (uniform and Chaikin creasing).

#include <geom/core/surface_mesh.h>

#include <cstddef>

namespace geom {

/// Make every edge whose dihedral angle (between the normals of its two faces) exceeds
/// `degrees` infinitely sharp in "e:sharpness" (added when absent; existing values are
/// raised, never lowered). Faces with a zero normal are ignored. Returns the edges marked.
/// Throws: InvalidArgument when degrees is outside [0, 180] or NaN.
/// Complexity: O(V + E + F).
std::size_t mark_creases_by_angle(SurfaceMesh& mesh, double degrees);

namespace detail::subdiv {

inline constexpr float kSmooth = 0.0f;
inline constexpr float kInfinite = 10.0f;

enum Rule : unsigned char { kRuleSmooth = 1, kRuleDart = 2, kRuleCrease = 4, kRuleCorner = 8 };

inline bool is_sharp(float s) { return s > kSmooth; }
inline bool is_infinite(float s) { return s >= kInfinite; }
inline bool is_semi_sharp(float s) { return s > kSmooth && s < kInfinite; }

/// Uniform decay of a vertex or edge sharpness by one level.
inline float decrement(float s) {
  if (s <= kSmooth) return kSmooth;
  if (is_infinite(s)) return kInfinite;
  return s > 1.0f ? s - 1.0f : kSmooth;
}

/// The vertex rule from the vertex's sharpness and the count of sharp edges at it.
inline Rule vertex_rule(float vertex_sharpness, int sharp_edges) {
  if (is_sharp(vertex_sharpness)) return kRuleCorner;
  if (sharp_edges > 2) return kRuleCorner;
  return static_cast<Rule>(1 << sharp_edges);
}

/// Chaikin decay of the half of an edge of sharpness `s` at a vertex with `n` incident
/// edges, `semi_count` of them semi-sharp with sharpness summing to `semi_sum` (s among
/// them when it is semi-sharp).
float chaikin_child_sharpness(float s, int n, float semi_sum, int semi_count);

/// The blend weight of the parent rule when a vertex's rule changes between levels: the
/// mean sharpness of the features that decay to zero, clamped to 1. Feed it the vertex and
/// each incident edge (parent and child sharpness), then read value().
class FractionalWeight {
 public:
  FractionalWeight(bool chaikin, float parent_vertex, float child_vertex) : chaikin_(chaikin) {
    if (is_sharp(parent_vertex) && !is_sharp(child_vertex)) {
      count_ = 1;
      sum_ = parent_vertex;
    }
  }
  void add_edge(float parent, float child) {
    // Uniform decay reaches zero exactly for sharpness in (0, 1]; Chaikin needs the child.
    bool decays = chaikin_ ? is_sharp(parent) && !is_sharp(child)
                           : is_sharp(parent) && parent <= 1.0f;
    if (decays) {
      sum_ += parent;
      ++count_;
    }
  }
  float value() const {
    if (count_ == 0) return 0.0f;
    float w = sum_ / static_cast<float>(count_);
    return w > 1.0f ? 1.0f : w;
  }

 private:
  bool chaikin_;
  int count_ = 0;
  float sum_ = 0.0f;
};

}  // namespace detail::subdiv
}  // namespace geom
