#pragma once
// OpenSubdiv Far as the oracle: the same control mesh, creases and options through
// TopologyRefinerFactory<TopologyDescriptor>, RefineUniform with child vertices ordered
// face-points first (geom's order), and PrimvarRefinerReal<double> for the numbers.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>
#include <geom/subdivision/subdivision.h>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <Eigen/Core>

#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace geom::test {

struct OsdParams {
  SubdivisionScheme scheme = SubdivisionScheme::kCatmullClark;
  BoundaryInterpolation boundary = BoundaryInterpolation::kEdges;
  CreaseMethod crease_method = CreaseMethod::kUniform;
  FaceVaryingInterpolation face_varying = FaceVaryingInterpolation::kLinearAll;
  int levels = 1;
};

struct OsdRun {
  bool accepted = true;  ///< false when Far refused the topology
  std::vector<std::vector<Eigen::Vector3d>> positions;     // per level 0..levels
  std::vector<std::vector<std::vector<int>>> faces;        // per level: corner vertex lists
  std::vector<Eigen::Vector3d> limit;                      // of the last level
  std::vector<std::vector<Eigen::Vector2d>> corner_uv;     // last level: per face, per corner
  std::vector<std::vector<Eigen::Vector2d>> corner_uv_limit;  // LimitFaceVarying of those
};

namespace osd_detail {
struct Vec3 {
  double p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0; }
  void AddWithWeight(const Vec3& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
};
struct Vec2 {
  double p[2];
  void Clear(void* = nullptr) { p[0] = p[1] = 0.0; }
  void AddWithWeight(const Vec2& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
  }
};
}  // namespace osd_detail

/// A control mesh as OpenSubdiv's TopologyDescriptor takes it.
struct OsdInput {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int> counts, indices, crease_pairs, corner_ids, fvar_indices;
  std::vector<float> crease_weights, corner_weights;
  std::vector<osd_detail::Vec2> fvar_values;
  bool uvs = false;
};

inline OsdInput osd_input(const SurfaceMesh& mesh) {
  using osd_detail::Vec2;
  OsdInput in;
  for (Vertex v : mesh.vertices()) in.positions.push_back(mesh.position(v));
  for (Face f : mesh.faces()) {
    int n = 0;
    for (Vertex v : mesh.vertices(f)) {
      in.indices.push_back(static_cast<int>(v.idx()));
      ++n;
    }
    in.counts.push_back(n);
  }
  if (auto es = mesh.get_property<Edge, double>(prop::kEdgeSharpness))
    for (Edge e : mesh.edges())
      if (es[e] > 0.0) {
        in.crease_pairs.push_back(static_cast<int>(mesh.vertex(e, 1).idx()));
        in.crease_pairs.push_back(static_cast<int>(mesh.vertex(e, 0).idx()));
        in.crease_weights.push_back(static_cast<float>(es[e]));
      }
  if (auto vs = mesh.get_property<Vertex, double>(prop::kVertexSharpness))
    for (Vertex v : mesh.vertices())
      if (vs[v] > 0.0) {
        in.corner_ids.push_back(static_cast<int>(v.idx()));
        in.corner_weights.push_back(static_cast<float>(vs[v]));
      }
  // Face-varying: share a value among the corners of a vertex with identical UVs.
  auto uvs = mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  if (uvs) {
    in.uvs = true;
    std::map<std::pair<std::uint32_t, std::pair<double, double>>, int> ids;
    for (Face f : mesh.faces())
      for (Halfedge h : mesh.halfedges(f)) {
        const TexCoord& t = uvs[h];
        auto key = std::make_pair(mesh.to_vertex(h).idx(), std::make_pair(t.x(), t.y()));
        auto [it, fresh] = ids.emplace(key, static_cast<int>(in.fvar_values.size()));
        if (fresh) in.fvar_values.push_back({{t.x(), t.y()}});
        in.fvar_indices.push_back(it->second);
      }
  }
  return in;
}

/// The soup as given: faces, crease and corner tags (no face-varying data).
inline OsdInput osd_input(const PolygonSoup& soup) {
  OsdInput in;
  in.positions = soup.positions;
  for (std::size_t f = 0; f < soup.n_faces(); ++f) {
    for (std::uint32_t v : soup.face(f)) in.indices.push_back(static_cast<int>(v));
    in.counts.push_back(static_cast<int>(soup.face(f).size()));
  }
  for (const EdgeSharpness& c : soup.creases) {
    in.crease_pairs.push_back(static_cast<int>(c.a));
    in.crease_pairs.push_back(static_cast<int>(c.b));
    in.crease_weights.push_back(static_cast<float>(c.sharpness));
  }
  for (const VertexSharpness& c : soup.corners) {
    in.corner_ids.push_back(static_cast<int>(c.v));
    in.corner_weights.push_back(static_cast<float>(c.sharpness));
  }
  return in;
}

inline OsdRun run_osd(const OsdInput& in, const OsdParams& params) {
  using namespace OpenSubdiv;
  using Descriptor = Far::TopologyDescriptor;
  using osd_detail::Vec2;
  using osd_detail::Vec3;

  Descriptor desc;
  desc.numVertices = static_cast<int>(in.positions.size());
  desc.numFaces = static_cast<int>(in.counts.size());
  desc.numVertsPerFace = in.counts.data();
  desc.vertIndicesPerFace = in.indices.data();
  desc.numCreases = static_cast<int>(in.crease_weights.size());
  desc.creaseVertexIndexPairs = in.crease_pairs.data();
  desc.creaseWeights = in.crease_weights.data();
  desc.numCorners = static_cast<int>(in.corner_weights.size());
  desc.cornerVertexIndices = in.corner_ids.data();
  desc.cornerWeights = in.corner_weights.data();
  Descriptor::FVarChannel channel;
  const bool uvs = in.uvs;
  if (uvs) {
    channel.numValues = static_cast<int>(in.fvar_values.size());
    channel.valueIndices = in.fvar_indices.data();
    desc.numFVarChannels = 1;
    desc.fvarChannels = &channel;
  }

  Sdc::Options options;
  switch (params.boundary) {
    case BoundaryInterpolation::kNone:
      options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_NONE);
      break;
    case BoundaryInterpolation::kEdges:
      options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
      break;
    case BoundaryInterpolation::kEdgesAndCorners:
      options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
      break;
  }
  options.SetCreasingMethod(params.crease_method == CreaseMethod::kChaikin
                                ? Sdc::Options::CREASE_CHAIKIN
                                : Sdc::Options::CREASE_UNIFORM);
  options.SetFVarLinearInterpolation(
      params.face_varying == FaceVaryingInterpolation::kLinearBoundaries
          ? Sdc::Options::FVAR_LINEAR_BOUNDARIES
          : Sdc::Options::FVAR_LINEAR_ALL);
  const Sdc::SchemeType type = params.scheme == SubdivisionScheme::kLoop ? Sdc::SCHEME_LOOP
                                                                        : Sdc::SCHEME_CATMARK;
  std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Descriptor>::Create(
      desc, Far::TopologyRefinerFactory<Descriptor>::Options(type, options)));
  OsdRun run;
  if (!refiner) {
    run.accepted = false;
    return run;
  }
  Far::TopologyRefiner::UniformOptions uniform(params.levels);
  uniform.orderVerticesFromFacesFirst = true;
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);

  std::vector<std::vector<Vec3>> pos(params.levels + 1);
  for (const Eigen::Vector3d& p : in.positions) pos[0].push_back({{p.x(), p.y(), p.z()}});
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  std::vector<Vec2> fv = in.fvar_values;
  for (int l = 1; l <= params.levels; ++l) {
    pos[l].resize(refiner->GetLevel(l).GetNumVertices());
    primvar.Interpolate(l, pos[l - 1], pos[l]);
    if (uvs) {
      std::vector<Vec2> next(refiner->GetLevel(l).GetNumFVarValues(0));
      primvar.InterpolateFaceVarying(l, fv, next, 0);
      fv.swap(next);
    }
  }
  for (int l = 0; l <= params.levels; ++l) {
    std::vector<Eigen::Vector3d> out;
    for (const Vec3& v : pos[l]) out.emplace_back(v.p[0], v.p[1], v.p[2]);
    run.positions.push_back(out);
    const Far::TopologyLevel& level = refiner->GetLevel(l);
    std::vector<std::vector<int>> faces;
    for (int f = 0; f < level.GetNumFaces(); ++f) {
      auto fv_ids = level.GetFaceVertices(f);
      faces.emplace_back(fv_ids.begin(), fv_ids.end());
    }
    run.faces.push_back(faces);
  }
  std::vector<Vec3> lim(pos[params.levels].size());
  primvar.Limit(pos[params.levels], lim);
  for (const Vec3& v : lim) run.limit.emplace_back(v.p[0], v.p[1], v.p[2]);
  if (uvs) {
    const Far::TopologyLevel& level = refiner->GetLevel(params.levels);
    for (int f = 0; f < level.GetNumFaces(); ++f) {
      std::vector<Eigen::Vector2d> corners;
      for (int id : level.GetFaceFVarValues(f, 0)) corners.emplace_back(fv[id].p[0], fv[id].p[1]);
      run.corner_uv.push_back(corners);
    }
    std::vector<Vec2> fv_limit(fv.size());
    primvar.LimitFaceVarying(fv, fv_limit, 0);
    for (int f = 0; f < level.GetNumFaces(); ++f) {
      std::vector<Eigen::Vector2d> corners;
      for (int id : level.GetFaceFVarValues(f, 0))
        corners.emplace_back(fv_limit[id].p[0], fv_limit[id].p[1]);
      run.corner_uv_limit.push_back(corners);
    }
  }
  return run;
}

inline OsdRun run_osd(const SurfaceMesh& mesh, const OsdParams& params) {
  return run_osd(osd_input(mesh), params);
}

/// Unit limit normals (tan1 × tan2 from PrimvarRefiner::Limit) of the vertices of `mesh`
/// taken as a control mesh without refinement, with its "e:sharpness"/"v:sharpness".
inline std::vector<Eigen::Vector3d> osd_limit_normals(
    const SurfaceMesh& mesh, SubdivisionScheme scheme,
    BoundaryInterpolation boundary = BoundaryInterpolation::kEdges) {
  using namespace OpenSubdiv;
  using osd_detail::Vec3;
  std::vector<int> counts, indices;
  for (Face f : mesh.faces()) {
    int n = 0;
    for (Vertex v : mesh.vertices(f)) {
      indices.push_back(static_cast<int>(v.idx()));
      ++n;
    }
    counts.push_back(n);
  }
  std::vector<int> crease_pairs, corner_ids;
  std::vector<float> crease_weights, corner_weights;
  if (auto es = mesh.get_property<Edge, double>(prop::kEdgeSharpness))
    for (Edge e : mesh.edges())
      if (es[e] > 0.0) {
        crease_pairs.push_back(static_cast<int>(mesh.vertex(e, 1).idx()));
        crease_pairs.push_back(static_cast<int>(mesh.vertex(e, 0).idx()));
        crease_weights.push_back(static_cast<float>(es[e]));
      }
  if (auto vs = mesh.get_property<Vertex, double>(prop::kVertexSharpness))
    for (Vertex v : mesh.vertices())
      if (vs[v] > 0.0) {
        corner_ids.push_back(static_cast<int>(v.idx()));
        corner_weights.push_back(static_cast<float>(vs[v]));
      }
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(mesh.vertices_size());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  desc.numCreases = static_cast<int>(crease_weights.size());
  desc.creaseVertexIndexPairs = crease_pairs.data();
  desc.creaseWeights = crease_weights.data();
  desc.numCorners = static_cast<int>(corner_weights.size());
  desc.cornerVertexIndices = corner_ids.data();
  desc.cornerWeights = corner_weights.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(boundary == BoundaryInterpolation::kEdgesAndCorners
                                          ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                          : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(
      desc, Factory::Options(scheme == SubdivisionScheme::kLoop ? Sdc::SCHEME_LOOP
                                                               : Sdc::SCHEME_CATMARK,
                             options)));
  std::vector<Vec3> pos, lim(mesh.vertices_size()), t1(lim.size()), t2(lim.size());
  for (Vertex v : mesh.vertices()) {
    const Point& p = mesh.position(v);
    pos.push_back({{p.x(), p.y(), p.z()}});
  }
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  primvar.Limit(pos, lim, t1, t2);
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t i = 0; i < lim.size(); ++i) {
    Eigen::Vector3d a(t1[i].p[0], t1[i].p[1], t1[i].p[2]), b(t2[i].p[0], t2[i].p[1], t2[i].p[2]);
    normals.push_back(a.cross(b).normalized());
  }
  return normals;
}

}  // namespace geom::test
