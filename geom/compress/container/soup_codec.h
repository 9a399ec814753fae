#pragma once
/// \file
/// The codec on what a file holds: a PolygonSoup in, the same soup out. A half-edge mesh
/// cannot hold every face a file may (degenerate and duplicate faces, non-manifold edges and
/// vertices, faces whose orientations disagree), so the soup is built without repair and
/// the stream records what the mesh leaves out (FORMAT.md, extension kinds 3–5).

#include <geom/compress/container/codec.h>
#include <geom/core/soup.h>

namespace geom {

/// Compress a soup so that to_soup(decompress(bytes)) gives back every face whose indices
/// are in range, with its corners in order from the same first corner (triangles: from the
/// same first corner only with keep_triangle_corners), and the soup's vertices, within the
/// grid's error. Faces and vertices come back in another order unless preserve_order.
/// The soup is built with no welding and no reorienting (faces that disagree are split
/// apart instead, and joined again on decoding); faces with a repeated index, zero area or
/// another face's vertex set travel as loose faces (options.loose_faces is replaced, as is
/// options.vertex_origin). Per-corner and per-face attributes of loose faces are not kept;
/// stats.dropped_properties names the corner values lost, with the count of loose faces.
/// stats.unstorable_faces counts faces with an index beyond the vertices: they are not
/// stored. The permutations in the result refer to the mesh built from the soup.
/// Throws: InvalidArgument as check_soup() and compress(const SurfaceMesh&, …).
/// Complexity: that of build() and compress().
CompressResult compress(const PolygonSoup& soup, const CompressOptions& options = {});

/// The decoded mesh as a soup with the stream's loose faces (at their places when the order
/// was preserved, else after the mesh's faces) and its split vertices joined.
/// Loose faces get zero per-corner values where the soup has per-corner attributes.
PolygonSoup to_soup(const DecompressResult& decoded);

}  // namespace geom
