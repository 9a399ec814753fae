// What each format keeps of a soup, so that a writer's losses are said rather than silent.
// Kept in step with the writers: obj.cpp, ply_write.cpp, off.cpp, stl.cpp, drc.cpp and
// gltf_write.cpp.

#include <geom/io/io.h>

#include <algorithm>
#include <tuple>

namespace geom {
namespace {

struct Keeps {
  bool polygons, normals, colors, texcoords, corner_values, vertex_scalars, face_scalars, creases;
};

Keeps keeps(FileFormat f) {
  switch (f) {
    case FileFormat::kObj: return {true, true, true, true, true, false, false, true};
    case FileFormat::kPly: return {true, true, true, true, false, true, true, false};
    case FileFormat::kOff: return {true, true, true, true, false, false, false, false};
    case FileFormat::kStl: return {false, false, false, false, false, false, false, false};
    case FileFormat::kDrc: return {false, true, false, true, false, false, false, false};
    case FileFormat::kGltf:
    case FileFormat::kGlb: return {false, true, true, true, true, false, false, false};
  }
  return {};
}

std::string names(const std::vector<NamedScalars>& scalars) {
  std::string out;
  for (const NamedScalars& s : scalars) out += (out.empty() ? "'" : ", '") + s.name + "'";
  return out;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// Corner values that the per-vertex array does not already say (a seam or crease).
bool has_seams(std::size_t corners, std::size_t per_vertex, std::size_t vertices) {
  return corners > 0 && per_vertex != vertices;
}

// glTF asks for unit normals and colours in [0, 1]: the writer leaves out normals when one
// has no direction and clamps colours (gltf_write.cpp).
void gltf_values(const PolygonSoup& soup, std::vector<std::string>& out) {
  std::size_t zero = 0, outside = 0;
  for (const auto* normals : {&soup.vertex_normals, &soup.corner_normals})
    for (const Normal& n : *normals) zero += !n.allFinite() || n.norm() == 0;
  for (const Color& c : soup.vertex_colors) outside += !(c.minCoeff() >= 0 && c.maxCoeff() <= 1);
  if (zero) out.push_back("normals are not stored: " + plural(zero, "is", "are") + " zero or not finite (glTF needs unit normals)");
  if (outside) out.push_back(plural(outside, "colour", "colours") + " outside [0, 1] are clamped (glTF's range)");
}

// Only OBJ names faces' objects, groups and materials and the files that define them; glTF
// keeps the material names (a primitive per material, a material of that name).
void face_names(const PolygonSoup& soup, bool materials_kept, const std::string& in,
                std::vector<std::string>& out) {
  std::string sets;
  for (auto [names, one, many] : {std::tuple{&soup.face_objects, "object", "objects"},
                                  std::tuple{&soup.face_groups, "group", "groups"},
                                  std::tuple{&soup.face_materials, "material", "materials"}})
    if (!names->empty() && !(materials_kept && names == &soup.face_materials))
      sets += (sets.empty() ? "" : ", ") + plural(names->names.size(), one, many);
  if (!sets.empty()) out.push_back("face names (" + sets + ") are not stored" + in);
  std::string libs;
  for (const std::string& lib : soup.material_libraries) libs += (libs.empty() ? "" : ", ") + lib;
  if (!libs.empty()) out.push_back("material libraries (mtllib " + libs + ") are not stored" + in);
}

}  // namespace

std::size_t unstored_vertices(const PolygonSoup& soup, FileFormat format) {
  if (format == FileFormat::kGltf || format == FileFormat::kGlb)
    return soup.n_faces() == 0 ? soup.positions.size() : 0;
  if (format != FileFormat::kStl && !(format == FileFormat::kDrc && soup.n_faces() > 0)) return 0;
  std::vector<bool> used(soup.positions.size(), false);
  for (std::uint32_t v : soup.face_indices) used[v] = true;
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
}

std::vector<std::string> unstored(const PolygonSoup& soup, FileFormat format, const WriteOptions& options) {
  std::vector<std::string> out;
  const Keeps k = keeps(format);
  const std::string in = std::string(" (") + format_name(format) + " has no place for them)";
  if (const std::size_t n = unstored_vertices(soup, format))
    out.push_back(plural(n, "vertex that no face uses is", "vertices that no face uses are") + " not stored (" +
                  format_name(format) + " keeps only vertices of triangles)");
  if (!k.polygons) {
    std::size_t polygons = 0, triangles = 0;
    for (std::size_t f = 0; f < soup.n_faces(); ++f)
      if (const std::size_t c = soup.face(f).size(); c > 3) ++polygons, triangles += c - 2;
    if (polygons)
      out.push_back(plural(polygons, "polygon", "polygons") + " of more than 3 corners " +
                    (polygons == 1 ? "is" : "are") + " split into " + plural(triangles, "triangle", "triangles") +
                    " (" + format_name(format) + " holds triangles only)");
  }
  if (options.attributes) {
    const std::size_t nv = soup.positions.size();
    auto lost = [&](bool present, bool kept, const char* what) {
      if (present && !kept) out.push_back(std::string(what) + " are not stored" + in);
    };
    lost(!soup.vertex_normals.empty() || !soup.corner_normals.empty(), k.normals, "normals");
    lost(!soup.vertex_colors.empty(), k.colors, "colours");
    lost(!soup.vertex_texcoords.empty() || !soup.corner_texcoords.empty(), k.texcoords, "texture coordinates");
    if (k.texcoords && !k.corner_values && has_seams(soup.corner_texcoords.size(), soup.vertex_texcoords.size(), nv))
      out.push_back("texture coordinates per face corner (UV seams) are not stored (" + std::string(format_name(format)) +
                    " keeps one per vertex)");
    if (k.normals && !k.corner_values && has_seams(soup.corner_normals.size(), soup.vertex_normals.size(), nv))
      out.push_back("normals per face corner (creases) are not stored (" + std::string(format_name(format)) +
                    " keeps one per vertex)");
    if (!soup.vertex_scalars.empty() && !k.vertex_scalars)
      out.push_back("vertex properties " + names(soup.vertex_scalars) + " are not stored" + in);
    if (!soup.face_scalars.empty() && !k.face_scalars)
      out.push_back("face properties " + names(soup.face_scalars) + " are not stored" + in);
    if (format == FileFormat::kGltf || format == FileFormat::kGlb) gltf_values(soup, out);
  }
  if (format != FileFormat::kObj)
    face_names(soup, format == FileFormat::kGltf || format == FileFormat::kGlb, in, out);
  if (!k.creases && (!soup.creases.empty() || !soup.corners.empty() || soup.boundary_interpolation))
    out.push_back("subdivision tags (" + plural(soup.creases.size(), "crease", "creases") + ", " +
                  plural(soup.corners.size(), "corner", "corners") + ") are not stored" + in);
  return out;
}

}  // namespace geom
