#include "lod_peers.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <ctime>

namespace geom::bench {

namespace {
struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
}  // namespace

PeerRun simplify_openmesh(const TriangleArrays& input, std::size_t target_faces) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vs;
  vs.reserve(input.positions.size());
  for (const auto& p : input.positions) vs.push_back(mesh.add_vertex(Mesh::Point(p.x(), p.y(), p.z())));
  for (const auto& t : input.triangles) mesh.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);

  const std::clock_t t0 = std::clock();
  OpenMesh::Decimater::DecimaterT<Mesh> decimater(mesh);
  OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  decimater.initialize();
  decimater.decimate_to_faces(0, target_faces);
  mesh.garbage_collection();
  const std::clock_t t1 = std::clock();

  PeerRun out;
  out.seconds = static_cast<double>(t1 - t0) / CLOCKS_PER_SEC;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out.mesh.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (auto f : mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) if (k < 3) t[k++] = static_cast<std::uint32_t>(v.idx());
    out.mesh.triangles.push_back(t);
  }
  return out;
}

}  // namespace geom::bench
