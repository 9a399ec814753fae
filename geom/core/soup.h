#pragma once
/// \file
/// PolygonSoup: what a file holds before it is a mesh — positions, faces as index lists,
/// and optional attributes. Readers produce it, build() turns it into a SurfaceMesh, and
/// to_soup() turns a mesh back into it for writers.

#include <geom/core/surface_mesh.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace geom {

/// A named scalar attribute per vertex or per face (PLY's extra properties and the like).
struct NamedScalars {
  std::string name;
  std::vector<double> values;
};

/// A name per face (OBJ's "o" objects, "g" groups, "usemtl" materials): an index into
/// names, or kUnnamed for a face the file gave no name. Empty when the file names none.
struct FaceNames {
  static constexpr std::uint32_t kUnnamed = 0xffffffffu;
  std::vector<std::string> names;
  std::vector<std::uint32_t> of_face;
  bool empty() const { return of_face.empty(); }
};

/// A crease tag: edge (a, b) with a sharpness (OpenSubdiv: 0 smooth … 10 = infinitely sharp).
struct EdgeSharpness {
  std::uint32_t a, b;
  double sharpness;
};
struct VertexSharpness {
  std::uint32_t v;
  double sharpness;
};

struct PolygonSoup {
  std::vector<Point> positions;
  /// Face f has corners face_indices[face_offsets[f] .. face_offsets[f+1]).
  /// face_offsets is empty (no faces) or has F + 1 entries starting at 0.
  std::vector<std::uint32_t> face_offsets;
  std::vector<std::uint32_t> face_indices;

  // Per-vertex attributes: empty, or one per position.
  std::vector<Normal> vertex_normals;
  std::vector<Color> vertex_colors;
  std::vector<TexCoord> vertex_texcoords;
  std::vector<NamedScalars> vertex_scalars;
  // Per-corner attributes: empty, or one per face_indices entry (OBJ's vt / vn).
  std::vector<TexCoord> corner_texcoords;
  std::vector<Normal> corner_normals;
  // Per-face attributes: empty, or one per face.
  std::vector<NamedScalars> face_scalars;
  FaceNames face_objects, face_groups, face_materials;
  std::vector<std::string> material_libraries;  ///< OBJ "mtllib" files, in order
  // Subdivision tags (OBJ "t crease" / "t corner" / "t interpolateboundary").
  std::vector<EdgeSharpness> creases;
  std::vector<VertexSharpness> corners;
  std::optional<int> boundary_interpolation;  ///< OpenSubdiv's VtxBoundaryInterpolation
  /// What the reader skipped or could not hold, one line each, for the caller to show (the
  /// CLI on stderr, Python as warnings). Not data: writers ignore it.
  std::vector<std::string> warnings;

  std::size_t n_faces() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  std::span<const std::uint32_t> face(std::size_t f) const {
    return {face_indices.data() + face_offsets[f], face_offsets[f + 1] - face_offsets[f]};
  }
  void add_face(std::span<const std::uint32_t> corners) {
    if (face_offsets.empty()) face_offsets.push_back(0);
    face_indices.insert(face_indices.end(), corners.begin(), corners.end());
    face_offsets.push_back(static_cast<std::uint32_t>(face_indices.size()));
  }
  void add_face(std::initializer_list<std::uint32_t> corners) {
    add_face(std::span<const std::uint32_t>(corners.begin(), corners.size()));
  }
};

/// Names of the properties that build() creates and to_soup() reads.
namespace prop {
inline constexpr const char* kVertexNormal = "v:normal";      // Normal
inline constexpr const char* kVertexColor = "v:color";        // Color
inline constexpr const char* kVertexTexCoord = "v:texcoord";  // TexCoord
inline constexpr const char* kCornerTexCoord = "h:texcoord";  // TexCoord, on the halfedge
                                                              // that ends at the corner
inline constexpr const char* kCornerNormal = "h:normal";      // Normal, likewise
inline constexpr const char* kEdgeSharpness = "e:sharpness";  // double
inline constexpr const char* kVertexSharpness = "v:sharpness";  // double
// FaceNames become std::string face properties (empty: no name).
inline constexpr const char* kFaceObject = "f:object name";
inline constexpr const char* kFaceGroup = "f:group name";
inline constexpr const char* kFaceMaterial = "f:material name";
// NamedScalars become double properties "v:<name>" / "f:<name>".
}  // namespace prop

/// Check that the soup's arrays agree: face_offsets empty or starting at 0, never
/// decreasing and ending at face_indices.size(); every per-vertex, per-corner and per-face
/// attribute empty or of the right length. Indices are not checked (build() reports those).
/// Throws: InvalidArgument naming the array, the length found and the one expected.
/// Complexity: O(F).
void check_soup(const PolygonSoup& soup);

/// The mesh's live elements as a soup, vertices and faces renumbered densely in index order,
/// with every property build() knows about carried over.
PolygonSoup to_soup(const SurfaceMesh& mesh);

/// Join vertices that are one: every face corner, crease and corner tag at vertex v moves
/// to same[v], and the vertices that are not their own entry are removed, the others keeping
/// their order and their per-vertex attributes. same[v] must be a vertex whose own entry is
/// itself. Tags that come to name one edge or vertex twice become one, of the larger
/// sharpness; creases come out as (lower, higher) vertex pairs in ascending order. Undoes
/// build()'s split of non-manifold edges and vertices (vertices with equal
/// BuildReport::vertex_origin), e.g. with DecompressResult::vertex_representative.
/// Throws: InvalidArgument as check_soup(), when same has not one entry per position, or
/// naming the vertex whose entry is out of range or not its own.
/// Complexity: O(V + corners).
void join_vertices(PolygonSoup& soup, std::span<const std::uint32_t> same);

}  // namespace geom
