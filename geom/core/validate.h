#pragma once
/// \file
/// Structural checks of a SurfaceMesh's half-edge invariants.

#include <geom/core/surface_mesh.h>

#include <string>
#include <vector>

namespace geom {

struct ValidationReport {
  /// One line per broken invariant, naming the element ("halfedge 12: next(prev(h)) != h").
  std::vector<std::string> problems;
  bool ok() const { return problems.empty(); }
  /// All problems joined by newlines.
  std::string to_string() const;
};

/// Check: next/prev are inverse; opposite is an involution without fixed points; face loops
/// are closed and agree on their face; to_vertex/from_vertex agree along loops; a vertex's
/// halfedge leaves it and is a boundary one when the vertex has any; no live element
/// references a deleted one; property arrays match element counts. Stops listing after
/// max_problems.
/// Complexity: O(V + E + F).
ValidationReport validate(const SurfaceMesh& mesh, std::size_t max_problems = 100);

}  // namespace geom
