#pragma once
/// \file
/// Mesh files in and out: one reader/writer pair per format (obj.cpp, ply.cpp, off.cpp,
/// stl.cpp, drc.cpp), dispatched here by file name or by sniffing content. Readers produce a
/// PolygonSoup and never repair; load_mesh() builds a mesh from it and reports repairs.
///
/// What each format carries (details at the top of each .cpp):
/// - OBJ: v (with optional "r g b" colours), vt, vn, polygon faces in all four corner forms
///   (an empty slot, as in `1//` or `1/`, is no reference), negative indices, `\`
///   continuations; g/o/s/usemtl/mtllib and unknown keywords skipped.
///   vt/vn become corner_texcoords/corner_normals; when every corner has one and each
///   vertex's corners agree, vertex_texcoords/vertex_normals are filled too. OpenSubdiv tags
///   `t crease`, `t corner`, `t interpolateboundary` are read and written.
/// - PLY: ascii and binary in both byte orders, every scalar type; normals, colours,
///   texture coordinates and other scalar properties; faces and tristrips (as triangles);
///   header lines ending in LF, CR LF or CR; unknown elements skipped. Written
///   binary little-endian (or ascii) with float values where every value is exactly a float
///   and double otherwise, so positions come back bit for bit.
/// - OFF: [ST][C][N]OFF, ascii and "OFF BINARY" (big-endian per the spec, little-endian as
///   pmp writes it: the byte order that accounts for the file exactly wins).
/// - STL: ascii and binary (binary recognised by its size); corners with equal coordinates
///   are welded into one vertex; written as float32 binary or exact ascii, polygons fanned.
/// - DRC: through the Draco library; positions are float32, exact unless
///   WriteOptions::drc_position_bits > 0.
/// Text output uses the shortest decimal that reads back as the same double, so text round
/// trips are bit-exact too. Errors name the file and the line (text) or byte offset.

#include <geom/core/build.h>
#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace geom {

enum class FileFormat { kObj, kPly, kOff, kStl, kDrc, kGltf, kGlb };

/// "obj", "ply", … as used in messages and --format options.
const char* format_name(FileFormat format);
/// The format named by a path's extension (case-insensitive).
/// Throws: InvalidArgument naming the extension when it is unknown.
FileFormat format_from_path(const std::filesystem::path& path);
/// The format of a buffer judged by its first bytes; nullopt when unrecognised.
std::optional<FileFormat> sniff_format(std::span<const std::byte> head);

struct ReadOptions {
  /// Force a format instead of judging by extension/content (needed for "-" = stdin).
  std::optional<FileFormat> format;
};

struct WriteOptions {
  std::optional<FileFormat> format;
  bool binary = true;  ///< PLY, STL: binary (default) or ASCII; OBJ, OFF are always text
  /// Draco only: quantisation bits for positions (0 = lossless floats) and compression
  /// level 0-10.
  int drc_position_bits = 0;
  int drc_level = 7;
  /// OBJ/PLY/OFF: write vertex normals/colours/texcoords when the mesh has them.
  bool attributes = true;
  /// OBJ: the material files ("mtllib") to name when the soup names none. A mesh keeps its
  /// faces' material names, not the files defining them (LoadResult has those).
  std::vector<std::string> material_libraries;
};

/// Read a file ("-" is stdin; then options.format is required) into a soup. The format is
/// options.format, else the extension, else sniffed from the content.
/// Throws: ParseError naming the file and line or byte offset, or naming the file when it
/// holds no vertex and no face (a header declaring zero counts included); geom::Error when
/// the file cannot be opened or read; InvalidArgument when the format cannot be determined.
/// Complexity: O(file size); the file is mapped, not copied.
PolygonSoup read_soup(const std::filesystem::path& path, const ReadOptions& options = {});
/// Read from bytes in memory; `name` is used in error messages. Throws: as above.
PolygonSoup read_soup(std::span<const std::byte> data, FileFormat format,
                      const std::string& name = "<memory>");

/// Write a soup ("-" is stdout; then options.format is required).
/// Throws: Error when the file cannot be written; InvalidArgument when the format cannot
/// hold the data (STL with non-triangles is triangulated, not refused).
void write_soup(const PolygonSoup& soup, const std::filesystem::path& path,
                const WriteOptions& options = {});

/// Write a soup to bytes in memory (what write_soup(soup, path) would put in the file).
/// Throws: as write_soup.
std::vector<std::byte> write_soup(const PolygonSoup& soup, FileFormat format,
                                  const WriteOptions& options = {});

/// How many of the soup's vertices a file of this format leaves out: those no face uses in
/// STL (triangles only) and in a Draco mesh (a point cloud keeps all), every one in glTF when
/// there are no faces (glTF has no mesh without triangles). OBJ, PLY and OFF keep every vertex.
std::size_t unstored_vertices(const PolygonSoup& soup, FileFormat format);

/// What a file of this format written with these options would not hold of the soup, one
/// line each with counts ("4 polygons of more than 3 corners are split into 10 triangles",
/// "vertex scalars 'quality' are not stored"): unused vertices (as unstored_vertices), polygons
/// fanned into triangles, attributes the format has no place for, per-corner values (UV seams,
/// normal creases) where only per-vertex ones are stored, crease tags. What the options turned
/// off (attributes = false) is not listed. Empty when the file keeps everything.
/// Complexity: O(V + corners).
std::vector<std::string> unstored(const PolygonSoup& soup, FileFormat format, const WriteOptions& options = {});

struct LoadResult {
  SurfaceMesh mesh;
  BuildReport report;
  std::vector<std::string> warnings;  ///< the reader's (PolygonSoup::warnings)
  std::vector<std::string> material_libraries;  ///< OBJ "mtllib" files, for save_mesh
};
/// read_soup + build.
LoadResult load_mesh(const std::filesystem::path& path, const ReadOptions& read = {},
                     const BuildOptions& build = {});
/// to_soup + write_soup (with options.material_libraries when the mesh names materials).
void save_mesh(const SurfaceMesh& mesh, const std::filesystem::path& path,
               const WriteOptions& options = {});

}  // namespace geom
