#pragma once
// Internal: a scene flattened to world-space triangles for both render paths.

#include <geom/render/scene.h>

#include <array>
#include <cstdint>
#include <vector>

namespace geom::detail {

struct FlatScene {
  std::vector<Point> positions;                     // world space
  std::vector<Normal> normals;                      // smooth shading only
  std::vector<std::array<std::uint32_t, 3>> tris;   // into positions
  std::vector<std::array<std::uint32_t, 3>> tri_normals;  // into normals (smooth only)
  std::vector<std::uint32_t> tri_material;
  std::vector<std::uint8_t> tri_cullable;           // closed mesh, one-sided material
  std::vector<std::array<Point, 2>> edges;          // polygon edges, for the wireframe
  std::vector<Material> materials;
  Eigen::AlignedBox3d bounds;
  bool smooth = false;
};

/// Flatten the node hierarchy. Corner normals are derived only for smooth shading (or read
/// from "h:normal" / "v:normal" when the mesh has them); wireframe edges only when asked.
/// Throws: InvalidArgument for bad references or a cycle.
FlatScene flatten(const Scene& scene, bool want_edges);

/// The camera the scene uses: its own, or one framing the bounds.
Camera scene_camera(const Scene& scene, const FlatScene& flat);

}  // namespace geom::detail

namespace geom::detail {

struct SurfacePoint {
  Point position;
  Normal normal;      ///< shading normal (unit)
  Normal geometric;   ///< face normal (unit, winding order)
};

/// Position and normals at barycentric coordinates b on flat triangle t.
inline SurfacePoint surface_at(const FlatScene& s, std::uint32_t t, const Eigen::Vector3d& b) {
  const auto& v = s.tris[t];
  const Point &p0 = s.positions[v[0]], &p1 = s.positions[v[1]], &p2 = s.positions[v[2]];
  SurfacePoint sp;
  sp.position = b[0] * p0 + b[1] * p1 + b[2] * p2;
  Normal g = (p1 - p0).cross(p2 - p0);
  double len = g.norm();
  sp.geometric = len > 0 ? Normal(g / len) : Normal::UnitZ();
  sp.normal = sp.geometric;
  if (s.smooth) {
    const auto& n = s.tri_normals[t];
    Normal sn = b[0] * s.normals[n[0]] + b[1] * s.normals[n[1]] + b[2] * s.normals[n[2]];
    double l = sn.norm();
    if (l > 0) sp.normal = sn / l;
  }
  return sp;
}

}  // namespace geom::detail
