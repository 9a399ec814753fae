#pragma once
/// \file
/// Structural checks of a SurfaceMesh's half-edge invariants.

#include <geom/core/build.h>
#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>
#include <geom/core/topology.h>

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

/// Properties a file's mesh may be required to have (`geom validate --manifold …`).
struct Requirements {
  bool manifold = false, closed = false, oriented = false;
};

struct RequirementCheck {
  TopologyReport topology;  ///< the soup as given
  BuildReport repairs;      ///< what build() would change (orientation left alone)
  /// One line per failure ("not closed: 2 boundary loops (14 boundary edges)"); empty: pass.
  std::vector<std::string> failures;
};

/// Whether `soup` builds into a valid mesh with the required properties, judged on the soup
/// as given (before repairs). What `geom validate` and the batch "validate" step decide.
/// Complexity: O(V + C·d), two builds and one analysis of the soup.
RequirementCheck check_requirements(const PolygonSoup& soup, const Requirements& required);

}  // namespace geom
