#include <geom/core/build_attributes.h>

#include <type_traits>

namespace geom::detail {

namespace {

std::string s(std::size_t x) { return std::to_string(x); }

struct Copier {
  SurfaceMesh& mesh;
  const PolygonSoup& soup;
  const AttributeSources& from;
  std::vector<std::string>& notes;

  std::uint32_t rep(std::uint32_t v) const { return from.weld.empty() ? v : from.weld[v]; }

  // Defaults are explicit zeros: Eigen's default constructor leaves them uninitialised.
  template <class H, class T>
  Property<H, T> add(const std::string& name) {
    if (mesh.has_property<H>(name)) {
      notes.push_back("property '" + name + "' given twice");
      return Property<H, T>();
    }
    if constexpr (std::is_arithmetic_v<T>) return mesh.add_property<H, T>(name, T(0));
    else return mesh.add_property<H, T>(name, T::Zero());
  }

  template <class T>
  void vertex(const std::vector<T>& values, const std::string& name) {
    if (values.empty()) return;
    auto p = add<Vertex, T>(name);
    if (!p) return;
    auto& out = p.vector();
    for (std::size_t v = 0; v < out.size(); ++v) out[v] = values[from.vertex_origin[v]];
  }

  template <class T>
  void corner(const std::vector<T>& values, const std::string& name) {
    if (values.empty()) return;
    auto p = add<Halfedge, T>(name);
    if (!p) return;
    for (std::size_t c = 0; c < from.into_corner.size(); ++c)
      p[Halfedge(from.into_corner[c])] = values[from.corner_origin[c]];
  }

  void face_names(const FaceNames& names, const char* name) {
    if (names.empty()) return;
    if (mesh.has_property<Face>(name)) {
      notes.push_back(std::string("property '") + name + "' given twice");
      return;
    }
    auto p = mesh.add_property<Face, std::string>(name, std::string());
    for (std::size_t f = 0; f < from.face_origin.size(); ++f)
      if (const std::uint32_t i = names.of_face[from.face_origin[f]]; i != FaceNames::kUnnamed)
        p[Face(static_cast<std::uint32_t>(f))] = names.names[i];
  }

  void run() {
    const auto nv = static_cast<std::uint32_t>(soup.positions.size());
    vertex(soup.vertex_normals, prop::kVertexNormal);
    vertex(soup.vertex_colors, prop::kVertexColor);
    vertex(soup.vertex_texcoords, prop::kVertexTexCoord);
    for (const auto& sc : soup.vertex_scalars) vertex(sc.values, "v:" + sc.name);
    corner(soup.corner_texcoords, prop::kCornerTexCoord);
    corner(soup.corner_normals, prop::kCornerNormal);
    for (const auto& sc : soup.face_scalars) {
      auto p = add<Face, double>("f:" + sc.name);
      if (!p) continue;
      for (std::size_t f = 0; f < from.face_origin.size(); ++f)
        p[Face(static_cast<std::uint32_t>(f))] = sc.values[from.face_origin[f]];
    }
    face_names(soup.face_objects, prop::kFaceObject);
    face_names(soup.face_groups, prop::kFaceGroup);
    face_names(soup.face_materials, prop::kFaceMaterial);
    if (!soup.creases.empty()) {
      // A crease names an input edge; every output edge made from it (it may have been
      // split apart) carries the sharpness.
      auto p = add<Edge, double>(prop::kEdgeSharpness);
      if (p)
        for (const auto& cr : soup.creases) {
          if (cr.a >= nv || cr.b >= nv) {
            notes.push_back("crease (" + s(cr.a) + ", " + s(cr.b) + ") names a vertex out of range");
            continue;
          }
          auto [i, j] = from.groups->find(rep(cr.a), rep(cr.b));
          if (i == j) notes.push_back("crease (" + s(cr.a) + ", " + s(cr.b) + ") is not an edge");
          for (std::uint32_t k = i; k < j; ++k)
            p[SurfaceMesh::edge(Halfedge(from.corner_halfedge[from.groups->entries[k].corner]))] = cr.sharpness;
        }
    }
    if (!soup.corners.empty()) {
      auto p = add<Vertex, double>(prop::kVertexSharpness);
      if (p) {
        std::vector<double> in(nv, 0.0);
        for (const auto& co : soup.corners) {
          if (co.v >= nv) {
            notes.push_back("corner tag names vertex " + s(co.v) + " out of range");
            continue;
          }
          in[rep(co.v)] = co.sharpness;
        }
        auto& out = p.vector();
        for (std::size_t v = 0; v < out.size(); ++v) out[v] = in[from.vertex_origin[v]];
      }
    }
  }
};

}  // namespace

void copy_attributes(SurfaceMesh& mesh, const PolygonSoup& soup, const AttributeSources& from,
                     std::vector<std::string>& notes) {
  Copier{mesh, soup, from, notes}.run();
}

}  // namespace geom::detail
