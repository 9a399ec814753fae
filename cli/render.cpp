// `geom render` and `geom montage`: pictures of meshes and scenes.

#include "commands.h"
#include "common.h"

#include <geom/render/render.h>

#include <fstream>
#include <iterator>
#include <sstream>

namespace geom::cli {
namespace {

struct Size {
  int width = 800, height = 600;
};

Size parse_size(const std::string& text) {
  Size s;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> s.width >> x >> s.height) || (x != 'x' && x != 'X') || !in.eof() || s.width < 1 ||
      s.height < 1 || s.width > 16384 || s.height > 16384)
    throw UsageError("--size expects WIDTHxHEIGHT (1..16384), got '" + text + "'");
  return s;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Checked before anything is read or drawn.
void check_png_output(const std::string& output, const std::vector<std::string>& inputs,
                      const CommonOptions& common) {
  if (output.empty()) throw UsageError("an output file is required (-o OUT.png)");
  require_extension(output, {".png"}, "-o/--output");
  check_not_input(output, inputs, common);
}

void write_png(const Image& image, const std::string& output) {
  auto bytes = encode_png(image);
  std::ofstream out(output, std::ios::binary);
  if (!out || !out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    throw Error("cannot write '" + output + "'");
}

bool is_scene(const std::string& path) {
  return std::filesystem::path(path).extension() == ".json";
}

// A scene file's meshes are paths relative to the scene file.
Scene load_scene(const std::string& path, const CommonOptions& common) {
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  return parse_scene(read_text(path), path, [&](const std::string& ref) {
    std::filesystem::path p = std::filesystem::path(ref).is_absolute() ? std::filesystem::path(ref) : base / ref;
    return std::make_shared<const SurfaceMesh>(load_input(p.string(), common).mesh);
  });
}

struct RenderArgs {
  std::string input;
  std::string size;
  bool wireframe = false, shadows = false, flat = false, raytrace = false, ground = false;
  int samples = 0;
  CommonOptions common;
};

nlohmann::json stats_json(const RenderStats& s) {
  return {{"path", s.path},
          {"bvh_built", s.bvh_built},
          {"normals_computed", s.normals_computed},
          {"triangles", s.triangles},
          {"primary_rays", s.primary_rays},
          {"shadow_rays", s.shadow_rays},
          {"reflection_rays", s.reflection_rays},
          {"seconds", {{"setup", s.seconds_setup}, {"bvh", s.seconds_bvh}, {"render", s.seconds_render},
                       {"wireframe", s.seconds_wireframe}}}};
}

int run_render(const RenderArgs& a) {
  check_png_output(a.common.output, {a.input}, a.common);
  Scene scene = is_scene(a.input)
                    ? load_scene(a.input, a.common)
                    : scene_for_mesh(std::make_shared<const SurfaceMesh>(load_input(a.input, a.common).mesh));
  // Flags add to what the scene asks for; they never switch an asked-for effect off.
  if (!a.size.empty()) {
    Size s = parse_size(a.size);
    scene.width = s.width;
    scene.height = s.height;
  }
  if (a.samples > 0) scene.samples = a.samples;
  scene.wireframe |= a.wireframe;
  scene.ground |= a.ground || a.shadows;
  if (a.flat) scene.shading = Shading::kFlat;
  if (a.shadows) {
    if (scene.lights.empty()) scene.lights = default_lights();
    scene.lights.front().shadows = true;
  }
  RenderResult r = render(scene, {.path = a.raytrace ? RenderPath::kRayTrace : RenderPath::kAuto});
  write_png(r.image, a.common.output);
  nlohmann::json j = stats_json(r.stats);
  j["output"] = a.common.output;
  j["width"] = r.image.width();
  j["height"] = r.image.height();
  std::ostringstream text;
  text << "wrote " << a.common.output << " (" << r.image.width() << "x" << r.image.height() << ", "
       << r.stats.path << ", " << r.stats.triangles << " triangles";
  if (r.stats.bvh_built)
    text << ", " << r.stats.primary_rays << " primary / " << r.stats.shadow_rays << " shadow / "
         << r.stats.reflection_rays << " reflection rays";
  text << ")";
  report(a.common, j, text.str());
  return 0;
}

struct MontageArgs {
  std::vector<std::string> inputs;
  std::vector<std::string> labels;
  std::string size = "320x240";
  int columns = 0;
  bool wireframe = false;
  CommonOptions common;
};

int run_montage(const MontageArgs& a) {
  if (!a.labels.empty() && a.labels.size() != a.inputs.size())
    throw UsageError("--labels needs one label per input (" + std::to_string(a.inputs.size()) + ")");
  check_png_output(a.common.output, a.inputs, a.common);
  Size size = parse_size(a.size);
  // Meshes of one size (a LOD chain, subdivision levels) share a camera so that they compare;
  // meshes of very different sizes are framed one by one. PNGs are taken as they are.
  std::vector<std::shared_ptr<const SurfaceMesh>> meshes(a.inputs.size());
  std::vector<Eigen::AlignedBox3d> boxes(a.inputs.size());
  Eigen::AlignedBox3d all;
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    if (std::filesystem::path(a.inputs[i]).extension() == ".png") continue;
    meshes[i] = std::make_shared<const SurfaceMesh>(load_input(a.inputs[i], a.common).mesh);
    for (Vertex v : meshes[i]->vertices()) boxes[i].extend(meshes[i]->position(v));
    all.extend(boxes[i]);
  }
  bool shared_camera = !all.isEmpty();
  for (std::size_t i = 0; i < a.inputs.size(); ++i)
    if (meshes[i] && (boxes[i].isEmpty() || boxes[i].diagonal().norm() < 0.5 * all.diagonal().norm()))
      shared_camera = false;
  std::vector<Image> images;
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    std::string label = a.labels.empty() ? std::filesystem::path(a.inputs[i]).filename().string() : a.labels[i];
    if (!meshes[i]) {
      std::string bytes = read_text(a.inputs[i]);
      images.push_back(decode_png({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()}, a.inputs[i]));
    } else {
      Scene s = scene_for_mesh(meshes[i]);
      s.width = size.width;
      s.height = size.height;
      s.wireframe = a.wireframe;
      if (shared_camera) s.camera = frame_box(all, static_cast<double>(size.width) / size.height);
      images.push_back(render(s).image);
      if (a.labels.empty()) label += "  F=" + std::to_string(meshes[i]->n_faces());
    }
    labels.push_back(label);
  }
  Image out = montage(images, labels, {.columns = a.columns});
  write_png(out, a.common.output);
  report(a.common, {{"output", a.common.output}, {"width", out.width()}, {"height", out.height()}},
         "wrote " + a.common.output + " (" + std::to_string(out.width()) + "x" + std::to_string(out.height()) + ")");
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = add_command(app, "render",
                              "Render a mesh or a JSON scene to PNG (ray traced only when shadows or mirrors are asked for)",
                              [a] { return run_render(*a); });
  cmd->add_option("input", a->input, "Mesh file, or a scene .json (see geom/render/SCENE.md)")->required();
  cmd->add_option("--size", a->size, "Image size WIDTHxHEIGHT (default 800x600, or the scene's)");
  cmd->add_flag("--wireframe", a->wireframe, "Overlay the polygon edges");
  cmd->add_flag("--shadows", a->shadows, "The key light casts shadows (adds a ground plane)");
  cmd->add_flag("--ground", a->ground, "Add a ground plane under the scene");
  cmd->add_flag("--flat", a->flat, "Flat shading (no vertex normals are computed)");
  cmd->add_flag("--raytrace", a->raytrace, "Ray trace even when nothing needs it");
  cmd->add_option("--samples", a->samples, "Samples per pixel (rounded to a square)")->check(CLI::Range(1, 256));
  add_common_options(cmd, a->common, kOutput | kJson | kQuiet | kForce);
}

void add_montage_command(CLI::App& app) {
  auto a = std::make_shared<MontageArgs>();
  CLI::App* cmd = add_command(app, "montage", "Render meshes (or take PNGs) side by side, labelled, into one PNG",
                              [a] { return run_montage(*a); });
  cmd->add_option("inputs", a->inputs, "Mesh files or PNG images")->required();
  cmd->add_option("--labels", a->labels, "One label per input (default: file name and face count)");
  cmd->add_option("--size", a->size, "Size of each tile WIDTHxHEIGHT (default 320x240)");
  cmd->add_option("--columns", a->columns, "Tiles per row (default: all in one row)")->check(CLI::Range(0, 64));
  cmd->add_flag("--wireframe", a->wireframe, "Overlay the polygon edges");
  add_common_options(cmd, a->common, kOutput | kJson | kQuiet | kForce);
}

}  // namespace geom::cli
