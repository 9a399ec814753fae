#pragma once
/// \file
/// glTF 2.0 (.gltf with embedded or external buffers, .glb): meshes with positions, normals,
/// texture coordinates, colours and indices, and the node hierarchy with its transforms — kept
/// as a document, or flattened into one soup for conversion. glTF splits a vertex wherever a
/// normal or texture coordinate changes; each mesh is read as one welded mesh instead
/// (vertices at one position with one colour are one, their differing normals and texture
/// coordinates become corner values), so seams do not cut it into pieces. Writing splits
/// vertices again per corner value, and marks them with a "_GEOM_VERTEX" attribute when
/// welding by position would join vertices the soup keeps apart (coincident instances). Reading also takes
/// Draco-compressed primitives, quantized attributes, meshopt-compressed buffer views and
/// sparse accessors; point and line primitives are skipped with a warning, as are required
/// extensions that change only materials, textures or lights. LOD chains are written with the
/// MSFT_lod extension.
///
/// Ref: Khronos, "glTF 2.0 Specification", 2021; Khronos, "KHR_draco_mesh_compression",
/// "KHR_mesh_quantization"; "EXT_meshopt_compression"; Microsoft, "MSFT_lod" extension.

#include <geom/core/soup.h>

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace geom {

struct GltfNode {
  std::string name;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  ///< local transform
  int mesh = -1;                                         ///< index into meshes, or −1
  std::vector<int> children;
  /// MSFT_lod: nodes showing this one at lower detail, finest first (empty when none).
  std::vector<int> lods;
};

struct GltfDocument {
  std::vector<PolygonSoup> meshes;  ///< one per glTF mesh, its primitives merged
  std::vector<std::string> mesh_names;
  std::vector<GltfNode> nodes;
  std::vector<int> roots;  ///< the default scene's nodes
  /// What reading skipped or could not keep, one line each (primitives, extensions).
  std::vector<std::string> warnings;
};

/// Parse glTF JSON or GLB bytes. External buffer URIs are resolved against `base_dir`
/// (empty: only embedded data is allowed).
/// Throws: ParseError naming `name` and the offending element ("accessors[3]: byteStride 2
/// is smaller than the element size 12"): malformed JSON or GLB framing, missing or
/// out-of-range buffers, views and accessors, bad strides, indices ≥ the vertex count,
/// compressed data that does not decode, required extensions that change geometry in ways
/// geom does not read (e.g. EXT_mesh_gpu_instancing).
GltfDocument read_gltf(std::span<const std::byte> data, const std::string& name,
                       const std::filesystem::path& base_dir = {});

/// Encode as GLB (binary = true) or as .gltf JSON with the buffer as a data URI. Polygons are
/// fan-triangulated; vertex normals and texture coordinates are written when present.
/// Throws: InvalidArgument for a node referring to a missing mesh or node.
std::string write_gltf(const GltfDocument& doc, bool binary);

/// One soup with every mesh instance transformed to world space (normals with the inverse
/// transpose), following the default scene; for LOD nodes only the finest level is used.
/// The document's warnings are carried over, with one for each attribute that only some
/// instances have (and so is not kept).
PolygonSoup flatten(const GltfDocument& doc);

/// A document holding one mesh in one node.
GltfDocument gltf_from_soup(PolygonSoup soup, const std::string& name = "mesh");

/// A document holding an LOD chain (finest first) as MSFT_lod: the first node is shown, the
/// others are its lower levels.
GltfDocument gltf_lod_chain(std::vector<PolygonSoup> levels);

}  // namespace geom
