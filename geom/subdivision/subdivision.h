#pragma once
/// \file
/// Uniform subdivision surfaces: Catmull-Clark on any polygon mesh and Loop on triangle
/// meshes, with OpenSubdiv's boundary interpolation modes, semi-sharp and infinitely sharp
/// creases and corners, linear or smooth face-varying data, and limit positions. The
/// numbers are OpenSubdiv's (Far::TopologyRefiner + PrimvarRefiner), vertex for vertex: the
/// refined mesh lists child vertices as face-points, edge-points, then vertex-points, each
/// group in its parent's index order, and the child faces of parent face f (in order, one
/// per corner, plus Loop's middle triangle last) follow those of face f - 1.
///
/// Creases are mesh properties: edge property "e:sharpness" and vertex property
/// "v:sharpness" (double; prop::kEdgeSharpness / prop::kVertexSharpness in core/soup.h).
/// Sharpness 0 is smooth, values in (0, 10) are semi-sharp (they decay by one per level),
/// 10 and above are infinitely sharp — OpenSubdiv's convention, held in single precision
/// internally as OpenSubdiv holds it so fractional sharpness gives the same weights.
///
/// Ref: E. Catmull, J. Clark, "Recursively generated B-spline surfaces on arbitrary
/// topological meshes", CAD 1978. C. Loop, "Smooth subdivision surfaces based on
/// triangles", MS thesis, 1987. T. DeRose, M. Kass, T. Truong, "Subdivision surfaces in
/// character animation", SIGGRAPH 1998 (semi-sharp creases). J. Stam, "Exact evaluation of
/// Catmull-Clark subdivision surfaces at arbitrary parameter values", SIGGRAPH 1998; H.
/// Biermann, A. Levin, D. Zorin, "Piecewise smooth subdivision surfaces with normal
/// control", SIGGRAPH 2000 (limit masks). OpenSubdiv 3 documentation, "Subdivision
/// Surfaces" (Sdc rules).

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

namespace geom {

enum class SubdivisionScheme {
  kCatmullClark,  ///< quads out of any polygons
  kLoop,          ///< triangles; input must be a triangle mesh
};

/// OpenSubdiv's Sdc::Options::VtxBoundaryInterpolation. Boundary edges are always refined
/// as infinitely sharp creases; the modes differ at corners.
enum class BoundaryInterpolation {
  kNone = 0,            ///< OpenSubdiv VTX_BOUNDARY_NONE (there the boundary faces become
                        ///< holes of the limit surface; geom keeps them, refined as kEdges)
  kEdges = 1,           ///< VTX_BOUNDARY_EDGE_ONLY: boundary is a smooth crease curve
  kEdgesAndCorners = 2, ///< VTX_BOUNDARY_EDGE_AND_CORNER: vertices with one face stay put
};

/// OpenSubdiv's Sdc::Options::CreasingMethod.
enum class CreaseMethod {
  kUniform,  ///< semi-sharp sharpness decreases by 1 per level
  kChaikin,  ///< a child edge's sharpness also averages its sharp neighbours'
};

/// OpenSubdiv's Sdc::Options::FVarLinearInterpolation, for face-varying (halfedge) data
/// such as texture coordinates with seams.
enum class FaceVaryingInterpolation {
  kLinearAll,         ///< FVAR_LINEAR_ALL: bilinear everywhere (OpenSubdiv's bare default)
  kLinearBoundaries,  ///< FVAR_LINEAR_BOUNDARIES: smooth inside each UV island, creases
                      ///< included; linear along seams and boundaries, whose vertices stay
};

struct SubdivideOptions {
  SubdivisionScheme scheme = SubdivisionScheme::kCatmullClark;
  /// Uniform refinement levels (0 returns a copy, or its limit when `limit` is set).
  int levels = 1;
  BoundaryInterpolation boundary = BoundaryInterpolation::kEdges;
  CreaseMethod crease_method = CreaseMethod::kUniform;
  /// How halfedge (corner) data is refined. Corners of a vertex with equal values are one
  /// value; a seam is an edge whose two faces disagree at either end. kLinearBoundaries
  /// with the Chaikin crease method can differ from OpenSubdiv where a semi-sharp edge
  /// ends at a seam vertex (geom averages only the edges of the vertex's UV island).
  FaceVaryingInterpolation face_varying = FaceVaryingInterpolation::kLinearAll;
  /// Move the final vertices onto the limit surface (OpenSubdiv's PrimvarRefiner::Limit),
  /// and with kLinearBoundaries face-varying data too (LimitFaceVarying: seam and boundary
  /// values stay, the rest follow the vertex masks); that needs levels >= 1. For
  /// Catmull-Clark with levels = 0 every face must be a quad.
  bool limit = false;
  /// When set, edges whose dihedral angle exceeds this many degrees are made infinitely
  /// sharp (on top of any "e:sharpness" the mesh has). Must be in [0, 180].
  std::optional<double> crease_angle;
  /// Use TBB across faces/edges/vertices on large levels.
  bool parallel = true;
  /// Called after each level with the fraction done; return false to cancel (the call then
  /// throws geom::Error "cancelled").
  std::function<bool(double)> progress;
};

/// Counts of one refinement level (level 0 is the input).
struct LevelCounts {
  std::size_t vertices = 0, edges = 0, faces = 0;
};

struct SubdivideResult {
  SurfaceMesh mesh;
  int levels = 0;
  std::vector<LevelCounts> per_level;  ///< levels + 1 entries
  /// Edges made sharp by options.crease_angle.
  std::size_t angle_creased_edges = 0;
  /// With options.limit: how far the final vertices moved onto the limit surface (the
  /// error of the plain level-k vertices as samples of the limit surface).
  double limit_max_distance = 0.0;
  double limit_rms_distance = 0.0;
};

/// Refine `mesh` uniformly. Every vertex property of type double, float or an Eigen
/// 2/3/4-vector of double or float is refined with the vertex weights (positions, colours,
/// normals as data, ...); halfedge (corner) properties of those types, such as
/// "h:texcoord", are refined as face-varying data by options.face_varying (and taken to
/// the limit with options.limit when smooth; linear data stays); face
/// properties are copied from parent to child faces; "e:sharpness" / "v:sharpness" carry
/// the decayed sharpness of the final level when the input had them. Other properties are
/// dropped. Isolated vertices are kept in place.
/// Pre: `mesh` is valid (validate()); deleted elements are ignored.
/// Throws: TopologyError naming the vertex when the mesh is non-manifold at a vertex (more
/// than one fan); InvalidArgument when Loop is asked for a mesh with a non-triangle face
/// (naming it), when levels is outside [0, 10], when the result would exceed 2^31 elements,
/// when crease_angle is outside [0, 180], when a sharpness is NaN, or when limit is asked at
/// level 0 of a Catmull-Clark mesh with a non-quad face or of a mesh with smooth
/// face-varying data; Error("cancelled") when the
/// progress callback returns false.
/// Complexity: O(output size); memory about 2× the output mesh.
SubdivideResult subdivide(const SurfaceMesh& mesh, const SubdivideOptions& options = {});

struct SoupSubdivideResult {
  /// The refined faces on OpenSubdiv's vertices, in its order (face-points, edge-points,
  /// vertex-points), with the input's attributes refined; crease and corner tags carry
  /// their decayed sharpness when the input had any (non-manifold edges among them).
  PolygonSoup soup;
  int levels = 0;
  std::vector<LevelCounts> per_level;  ///< OpenSubdiv's counts, levels + 1 entries
  std::size_t angle_creased_edges = 0;
  double limit_max_distance = 0.0;
  double limit_rms_distance = 0.0;
  /// What OpenSubdiv refines as non-manifold in the input: edges with 3+ faces or whose two
  /// faces run the same way, the vertices on them or where faces meet in more than one fan
  /// (all infinitely sharp, as OpenSubdiv makes them), and edges from a vertex to itself.
  std::size_t nonmanifold_edges = 0, nonmanifold_vertices = 0, degenerate_edges = 0;
  /// Vertex copies the half-edge core needed (joined again in `soup`).
  std::size_t split_vertices = 0;
  /// Edges OpenSubdiv refines smooth that the split had to leave open: next to them the
  /// result differs from OpenSubdiv's (0 on every regression shape OpenSubdiv ships).
  std::size_t opened_edges = 0;
};

/// Refine a soup as given, as OpenSubdiv refines the same faces: non-manifold edges and
/// vertices, faces that disagree on orientation, repeated corners, duplicate and zero-area
/// faces are refined, none dropped or repaired. The soup's crease/corner tags apply; its
/// "t interpolateboundary" tag does not (options.boundary does). The half-edge core cannot
/// hold non-manifold topology, so the soup is split for it, each copy tagged with
/// OpenSubdiv's sharpness of its original, and the copies are joined again: the output's
/// first levels of vertices are the input's. Manifold input takes subdivide(mesh)'s path.
/// Throws: InvalidArgument naming a face with an index out of range or fewer than 3
/// corners, and as subdivide(mesh).
/// Complexity: O(output size); non-manifold input adds its split copies and the join.
SoupSubdivideResult subdivide(const PolygonSoup& soup, const SubdivideOptions& options = {});

struct LimitOptions {
  SubdivisionScheme scheme = SubdivisionScheme::kCatmullClark;
  BoundaryInterpolation boundary = BoundaryInterpolation::kEdges;
  bool normals = false;  ///< also compute unit limit normals
};

struct LimitResult {
  /// One per live vertex in index order (a mesh with deleted elements is compacted first);
  /// isolated vertices keep their position.
  std::vector<Point> positions;
  /// When asked: OpenSubdiv's limit tangents crossed (PrimvarRefiner::Limit with tan1,
  /// tan2), oriented as the faces; at an interior crease vertex the normal of the side its
  /// first face (lowest index) is on, as OpenSubdiv picks it; zero where degenerate.
  std::vector<Normal> normals;
  double max_distance = 0.0;     ///< largest |limit − vertex|
  double rms_distance = 0.0;
};

/// Limit positions (and normals) of the vertices of `mesh`, taken as a control mesh of the
/// scheme with its "e:sharpness"/"v:sharpness" creases. Catmull-Clark masks assume quads
/// around each vertex, Loop masks triangles (subdivide once first otherwise).
/// Throws: InvalidArgument naming a face that is not a quad (Catmull-Clark) or a triangle
/// (Loop); TopologyError for a non-manifold vertex.
/// Complexity: O(V + E).
/// Ref: OpenSubdiv Sdc limit masks (Halstead, Kass, DeRose, "Efficient, fair interpolation
/// using Catmull-Clark surfaces", SIGGRAPH 1993).
LimitResult limit_positions(const SurfaceMesh& mesh, const LimitOptions& options = {});

}  // namespace geom
