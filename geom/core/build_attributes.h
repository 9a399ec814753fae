#pragma once
/// \file
/// Internal to build.cpp: carrying a soup's attributes onto the built mesh's properties,
/// given where each output element came from.

#include <geom/core/edge_groups.h>
#include <geom/core/soup.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace geom::detail {

struct AttributeSources {
  std::span<const std::uint32_t> weld;           ///< input vertex → representative; empty: identity
  std::span<const std::uint32_t> vertex_origin;  ///< output vertex → input vertex
  std::span<const std::uint32_t> face_origin;    ///< output face → input face
  /// Per kept corner: its input corner and the halfedge ending at it (both empty when the
  /// soup has no corner attributes).
  std::span<const std::uint32_t> corner_origin, into_corner;
  std::span<const std::uint32_t> corner_halfedge;  ///< per kept corner: the halfedge leaving it
  const EdgeGroups* groups = nullptr;              ///< the kept corners' edges
};

/// Adds the properties named in soup.h prop:: and fills them. Appends one note per
/// attribute it could not carry (a name taken twice, a crease that is not an edge).
void copy_attributes(SurfaceMesh& mesh, const PolygonSoup& soup, const AttributeSources& from,
                     std::vector<std::string>& notes);

}  // namespace geom::detail
