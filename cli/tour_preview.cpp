// Pictures for the tour: every step shows what it made.

#include "tour.h"

#include <geom/render/render.h>

#include <fstream>

namespace geom::cli {
namespace {

void write_png(const Image& image, const std::filesystem::path& path) {
  auto bytes = encode_png(image);
  std::ofstream out(path, std::ios::binary);
  if (!out || !out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    throw Error("cannot write '" + path.string() + "'");
}

Image picture(const SurfaceMesh& mesh, int width, int height, const std::optional<Camera>& camera) {
  Scene s = scene_for_mesh(std::make_shared<const SurfaceMesh>(mesh));
  s.width = width;
  s.height = height;
  s.wireframe = true;
  s.camera = camera;
  return render(s).image;
}

}  // namespace

void TourContext::preview(const std::string& file_name, const SurfaceMesh& mesh, const std::string& caption) {
  const auto p = path(file_name);
  write_png(picture(mesh, 640, 480, std::nullopt), p);
  add_file(p, "preview: " + caption);
  markdown += "![" + caption + "](" + file_name + ")\n\n";
}

void TourContext::preview_montage(const std::string& file_name,
                                  const std::vector<std::pair<std::string, const SurfaceMesh*>>& tiles,
                                  const std::string& caption) {
  // One camera for meshes of one size (levels of one shape), so the pictures compare.
  Eigen::AlignedBox3d all;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& [label, m] : tiles) {
    Eigen::AlignedBox3d b;
    for (Vertex v : m->vertices()) b.extend(m->position(v));
    boxes.push_back(b);
    all.extend(b);
  }
  bool shared = !all.isEmpty();
  for (const auto& b : boxes) shared &= !b.isEmpty() && b.diagonal().norm() >= 0.5 * all.diagonal().norm();
  const int w = 320, h = 240;
  std::optional<Camera> camera;
  if (shared) camera = frame_box(all, static_cast<double>(w) / h);
  std::vector<Image> images;
  std::vector<std::string> labels;
  for (const auto& [label, m] : tiles) {
    images.push_back(picture(*m, w, h, camera));
    labels.push_back(label);
  }
  const auto p = path(file_name);
  write_png(montage(images, labels, {.columns = std::min<int>(4, static_cast<int>(tiles.size()))}), p);
  add_file(p, "preview: " + caption);
  markdown += "![" + caption + "](" + file_name + ")\n\n";
}

}  // namespace geom::cli
