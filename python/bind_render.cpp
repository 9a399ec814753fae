// Python binding of geom/render: pictures as numpy arrays.

#include "arrays.h"
#include "bindings.h"

#include <geom/io/io.h>
#include <geom/render/render.h>

#include <pybind11/stl.h>

#include <fstream>
#include <iterator>
#include <optional>

namespace geom::python {
namespace {

struct Settings {
  std::optional<std::pair<int, int>> size;
  bool wireframe = false, shadows = false, flat = false, raytrace = false, ground = false;
  std::optional<int> samples;
};

// Flags add to what a scene asks for; they never switch an asked-for effect off.
void apply(const Settings& s, Scene& scene) {
  if (s.size) {
    scene.width = s.size->first;
    scene.height = s.size->second;
  }
  if (s.samples) scene.samples = *s.samples;
  if (s.samples && (*s.samples < 1 || *s.samples > 256)) throw InvalidArgument("samples must be in 1..256");
  scene.wireframe |= s.wireframe;
  scene.ground |= s.ground || s.shadows;
  if (s.flat) scene.shading = Shading::kFlat;
  if (s.shadows) {
    if (scene.lights.empty()) scene.lights = default_lights();
    scene.lights.front().shadows = true;
  }
}

py::tuple run(Scene scene, const Settings& s) {
  apply(s, scene);
  RenderResult r;
  {
    py::gil_scoped_release release;
    r = render(scene, {.path = s.raytrace ? RenderPath::kRayTrace : RenderPath::kAuto});
  }
  py::array_t<std::uint8_t> out({r.image.height(), r.image.width(), 3});
  auto* dst = out.mutable_data();
  for (const Rgb8& p : r.image.pixels()) {
    *dst++ = p.r;
    *dst++ = p.g;
    *dst++ = p.b;
  }
  return py::make_tuple(out, r.stats);
}

Scene scene_from_file(const std::string& path) {
  check_readable(path);
  std::ifstream in(path, std::ios::binary);
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  return parse_scene(text, path, [&](const std::string& ref) {
    std::filesystem::path p = std::filesystem::path(ref).is_absolute() ? std::filesystem::path(ref) : base / ref;
    check_readable(p.string());
    return std::make_shared<const SurfaceMesh>(load_mesh(p).mesh);
  });
}

}  // namespace

void bind_render(py::module_& m) {
  py::class_<RenderStats>(m, "RenderStats")
      .def_readonly("path", &RenderStats::path)
      .def_readonly("bvh_built", &RenderStats::bvh_built)
      .def_readonly("normals_computed", &RenderStats::normals_computed)
      .def_readonly("triangles", &RenderStats::triangles)
      .def_readonly("primary_rays", &RenderStats::primary_rays)
      .def_readonly("shadow_rays", &RenderStats::shadow_rays)
      .def_readonly("reflection_rays", &RenderStats::reflection_rays)
      .def_readonly("seconds_setup", &RenderStats::seconds_setup)
      .def_readonly("seconds_bvh", &RenderStats::seconds_bvh)
      .def_readonly("seconds_render", &RenderStats::seconds_render)
      .def_readonly("seconds_wireframe", &RenderStats::seconds_wireframe);

  auto settings = [](std::optional<std::pair<int, int>> size, bool wireframe, bool shadows,
                     std::optional<int> samples, bool flat, bool raytrace, bool ground) {
    return Settings{size, wireframe, shadows, flat, raytrace, ground, samples};
  };
  m.def(
      "render_mesh",
      [settings](const SurfaceMesh& mesh, std::optional<std::pair<int, int>> size, bool wireframe,
                 bool shadows, std::optional<int> samples, bool flat, bool raytrace, bool ground) {
        return run(scene_for_mesh(std::make_shared<const SurfaceMesh>(mesh)),
                   settings(size, wireframe, shadows, samples, flat, raytrace, ground));
      },
      py::arg("mesh"), py::arg("size"), py::arg("wireframe"), py::arg("shadows"),
      py::arg("samples"), py::arg("flat"), py::arg("raytrace"), py::arg("ground"));
  m.def(
      "render_scene",
      [settings](const std::string& path, std::optional<std::pair<int, int>> size, bool wireframe,
                 bool shadows, std::optional<int> samples, bool flat, bool raytrace, bool ground) {
        return run(scene_from_file(path), settings(size, wireframe, shadows, samples, flat, raytrace, ground));
      },
      py::arg("path"), py::arg("size"), py::arg("wireframe"), py::arg("shadows"),
      py::arg("samples"), py::arg("flat"), py::arg("raytrace"), py::arg("ground"));
}

}  // namespace geom::python
