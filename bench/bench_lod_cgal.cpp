#include "lod_peers.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <ctime>

namespace geom::bench {

PeerRun simplify_cgal(const TriangleArrays& input, std::size_t target_faces) {
  using Kernel = CGAL::Simple_cartesian<double>;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  namespace SMS = CGAL::Surface_mesh_simplification;
  Mesh sm;
  std::vector<Mesh::Vertex_index> vs;
  vs.reserve(input.positions.size());
  for (const auto& p : input.positions) vs.push_back(sm.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& t : input.triangles) sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);

  const std::clock_t t0 = std::clock();
  // CGAL 5.5 stops by edge count: E = 3F/2 on a closed triangle mesh.
  SMS::Count_stop_predicate<Mesh> stop(target_faces * 3 / 2);
  SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> gh(sm);
  SMS::edge_collapse(sm, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
  const std::clock_t t1 = std::clock();

  sm.collect_garbage();
  PeerRun out;
  out.seconds = static_cast<double>(t1 - t0) / CLOCKS_PER_SEC;
  for (auto v : sm.vertices()) {
    const auto& p = sm.point(v);
    out.mesh.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) if (k < 3) t[k++] = static_cast<std::uint32_t>(v.idx());
    out.mesh.triangles.push_back(t);
  }
  return out;
}

}  // namespace geom::bench
