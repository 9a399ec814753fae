#include <geom/render/flatten.h>

#include <geom/core/errors.h>

#include <cmath>
#include <numbers>
#include <unordered_map>

namespace geom::detail {
namespace {

// What one mesh contributes, whatever number of instances place it.
struct MeshGeometry {
  std::vector<std::array<Halfedge, 3>> tris;  // fan triangles as corner halfedges
  std::vector<Normal> corner_normals;          // by halfedge index (smooth only)
  bool closed = true;
};

// Newell normal: 2·area·n for planar polygons, robust for non-planar ones.
Normal newell(const SurfaceMesh& m, Face f) {
  Normal n = Normal::Zero();
  for (Halfedge h : m.halfedges(f)) {
    const Point& a = m.position(m.from_vertex(h));
    const Point& b = m.position(m.to_vertex(h));
    n += Normal((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                (a.x() - b.x()) * (a.y() + b.y()));
  }
  return n;
}

// Per-corner normals: the area-weighted average of the faces around the corner's vertex
// whose normals lie within the crease angle of the corner's own face.
std::vector<Normal> corner_normals(const SurfaceMesh& m, double crease_degrees) {
  std::vector<Normal> out(m.halfedges_size(), Normal::Zero());
  if (auto hn = m.get_property<Halfedge, Normal>("h:normal")) {
    for (Halfedge h : m.halfedges()) out[h.idx()] = hn[h];
    return out;
  }
  if (auto vn = m.get_property<Vertex, Normal>("v:normal")) {
    for (Halfedge h : m.halfedges()) out[h.idx()] = vn[m.to_vertex(h)];
    return out;
  }
  std::vector<Normal> fn(m.faces_size(), Normal::Zero());
  for (Face f : m.faces()) fn[f.idx()] = newell(m, f);
  const double cos_crease = std::cos(crease_degrees * std::numbers::pi / 180);
  std::vector<Halfedge> ring;
  for (Vertex v : m.vertices()) {
    ring.clear();
    for (Halfedge h : m.incoming(v))
      if (!m.is_boundary(h)) ring.push_back(h);
    for (Halfedge h : ring) {
      const Normal& a = fn[m.face(h).idx()];
      Normal sum = Normal::Zero();
      for (Halfedge g : ring) {
        const Normal& b = fn[m.face(g).idx()];
        if (g == h || a.dot(b) >= cos_crease * a.norm() * b.norm()) sum += b;
      }
      out[h.idx()] = sum;
    }
  }
  return out;
}

MeshGeometry prepare(const SurfaceMesh& m, bool smooth, double crease) {
  MeshGeometry g;
  for (Face f : m.faces()) {
    Halfedge h0 = m.halfedge(f);
    for (Halfedge h = m.next(m.next(h0)); h != h0; h = m.next(h)) g.tris.push_back({h0, m.prev(h), h});
  }
  for (Halfedge h : m.halfedges())
    if (m.is_boundary(h)) {
      g.closed = false;
      break;
    }
  if (smooth) g.corner_normals = corner_normals(m, crease);
  return g;
}

class Flattener {
 public:
  Flattener(const Scene& s, bool want_edges) : s_(s), want_edges_(want_edges) {
    out_.smooth = s.shading == Shading::kSmooth;
    out_.materials = s.materials;
    if (out_.materials.empty()) out_.materials.push_back(Material{});
  }

  FlatScene run() {
    std::vector<std::uint8_t> on_path(s_.nodes.size(), 0);
    for (int r : s_.roots) visit(r, Eigen::Matrix4d::Identity(), on_path);
    if (s_.ground && !out_.bounds.isEmpty()) add_ground();
    return std::move(out_);
  }

 private:
  void visit(int index, const Eigen::Matrix4d& parent, std::vector<std::uint8_t>& on_path) {
    if (index < 0 || index >= static_cast<int>(s_.nodes.size()))
      throw InvalidArgument("scene: node index " + std::to_string(index) + " does not exist");
    if (on_path[index]) throw InvalidArgument("scene: node " + std::to_string(index) + " is its own ancestor");
    const SceneNode& node = s_.nodes[index];
    Eigen::Matrix4d world = parent * node.transform;
    if (node.mesh >= 0) add_instance(node, world);
    on_path[index] = 1;
    for (int c : node.children) visit(c, world, on_path);
    on_path[index] = 0;
  }

  const MeshGeometry& geometry(int mesh) {
    auto it = cache_.find(mesh);
    if (it != cache_.end()) return it->second;
    return cache_.emplace(mesh, prepare(*s_.meshes[mesh], out_.smooth, s_.crease_angle_degrees)).first->second;
  }

  void add_instance(const SceneNode& node, const Eigen::Matrix4d& world) {
    if (node.mesh >= static_cast<int>(s_.meshes.size()) || !s_.meshes[node.mesh])
      throw InvalidArgument("scene: node '" + node.name + "' refers to missing mesh " + std::to_string(node.mesh));
    if (node.material < 0 || node.material >= static_cast<int>(out_.materials.size()))
      throw InvalidArgument("scene: node '" + node.name + "' refers to missing material " +
                            std::to_string(node.material));
    const SurfaceMesh& m = *s_.meshes[node.mesh];
    const MeshGeometry& g = geometry(node.mesh);
    const Eigen::Matrix3d linear = world.block<3, 3>(0, 0);
    const Eigen::Vector3d offset = world.block<3, 1>(0, 3);
    const auto base = static_cast<std::uint32_t>(out_.positions.size());
    for (std::uint32_t i = 0; i < m.vertices_size(); ++i) {
      Point p = linear * m.position(Vertex(i)) + offset;
      out_.positions.push_back(p);
      if (!m.is_deleted(Vertex(i))) out_.bounds.extend(p);
    }
    const auto nbase = static_cast<std::uint32_t>(out_.normals.size());
    if (out_.smooth) {
      const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
      for (const Normal& n : g.corner_normals) {
        Normal w = normal_matrix * n;
        double len = w.norm();
        out_.normals.push_back(len > 0 ? Normal(w / len) : Normal::Zero());
      }
    }
    const bool cullable = g.closed && !out_.materials[node.material].two_sided;
    // A mirroring transform flips the winding; the geometric normal must flip with it.
    const bool mirrored = linear.determinant() < 0;
    for (const auto& t : g.tris) {
      std::array<std::uint32_t, 3> v{base + m.to_vertex(t[0]).idx(), base + m.to_vertex(t[1]).idx(),
                                     base + m.to_vertex(t[2]).idx()};
      std::array<std::uint32_t, 3> n{nbase + t[0].idx(), nbase + t[1].idx(), nbase + t[2].idx()};
      if (mirrored) {
        std::swap(v[1], v[2]);
        std::swap(n[1], n[2]);
      }
      out_.tris.push_back(v);
      if (out_.smooth) out_.tri_normals.push_back(n);
      out_.tri_material.push_back(static_cast<std::uint32_t>(node.material));
      out_.tri_cullable.push_back(cullable ? 1 : 0);
    }
    if (want_edges_)
      for (Edge e : m.edges())
        out_.edges.push_back({out_.positions[base + m.vertex(e, 0).idx()], out_.positions[base + m.vertex(e, 1).idx()]});
  }

  void add_ground() {
    const Eigen::AlignedBox3d b = out_.bounds;
    const double extent = 2.0 * std::max(b.sizes().x(), b.sizes().z()) + 1e-12;
    const double y = b.min().y() - 1e-3 * b.diagonal().norm();
    const Eigen::Vector3d c = b.center();
    auto base = static_cast<std::uint32_t>(out_.positions.size());
    out_.positions.push_back({c.x() - extent, y, c.z() - extent});
    out_.positions.push_back({c.x() - extent, y, c.z() + extent});
    out_.positions.push_back({c.x() + extent, y, c.z() + extent});
    out_.positions.push_back({c.x() + extent, y, c.z() - extent});
    Material floor;
    floor.name = "ground";
    floor.diffuse = Color(0.82, 0.82, 0.80);
    floor.specular = Color::Zero();
    floor.two_sided = true;
    auto mat = static_cast<std::uint32_t>(out_.materials.size());
    out_.materials.push_back(floor);
    auto nbase = static_cast<std::uint32_t>(out_.normals.size());
    if (out_.smooth)
      for (int i = 0; i < 4; ++i) out_.normals.push_back(Normal::UnitY());
    for (std::array<std::uint32_t, 3> t : {std::array<std::uint32_t, 3>{0, 1, 2}, {0, 2, 3}}) {
      out_.tris.push_back({base + t[0], base + t[1], base + t[2]});
      if (out_.smooth) out_.tri_normals.push_back({nbase + t[0], nbase + t[1], nbase + t[2]});
      out_.tri_material.push_back(mat);
      out_.tri_cullable.push_back(0);
    }
  }

  const Scene& s_;
  bool want_edges_;
  FlatScene out_;
  std::unordered_map<int, MeshGeometry> cache_;
};

}  // namespace

FlatScene flatten(const Scene& scene, bool want_edges) { return Flattener(scene, want_edges).run(); }

Camera scene_camera(const Scene& scene, const FlatScene& flat) {
  if (scene.camera) return *scene.camera;
  Eigen::AlignedBox3d box = flat.bounds;
  if (box.isEmpty()) box = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  return frame_box(box, static_cast<double>(scene.width) / scene.height);
}

}  // namespace geom::detail
