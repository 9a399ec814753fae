#pragma once
// Peer simplifiers for bench_lod, each in its own translation unit (CGAL's compile time
// stays out of the main benchmark file).

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace geom::bench {

struct TriangleArrays {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

struct PeerRun {
  TriangleArrays mesh;
  double seconds = 0;  ///< CPU seconds of the simplification call only (no conversions)
  double wall = 0;     ///< its wall seconds; 0: not measured (the slow single-threaded peers)
};

/// CGAL Surface_mesh_simplification::edge_collapse with GarlandHeckbert_plane_policies.
PeerRun simplify_cgal(const TriangleArrays& input, std::size_t target_faces);
/// OpenMesh DecimaterT + ModQuadricT (no error bound).
PeerRun simplify_openmesh(const TriangleArrays& input, std::size_t target_faces);

class Table;
/// bench_lod_attributes.cpp: a UV-textured torus of `faces` triangles at 50/10/1%, ours with
/// attributes against meshoptimizer's attribute simplifier; adds rows to `table` (columns:
/// input, faces, target, method, seconds, ratio, achieved, hausdorff_rel, rms_rel, uv_max,
/// uv_rms). Methods run when named in peers: ours_attr, meshopt_attr.
void run_attribute_bench(std::size_t faces, double weight, const std::set<std::string>& peers, Table& table);

}  // namespace geom::bench
