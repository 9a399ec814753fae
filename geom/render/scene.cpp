#include <geom/render/scene.h>

#include <geom/core/errors.h>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <numbers>

namespace geom {

Scene scene_for_mesh(std::shared_ptr<const SurfaceMesh> mesh) {
  Scene s;
  s.meshes.push_back(std::move(mesh));
  SceneNode node;
  node.name = "mesh";
  node.mesh = 0;
  s.nodes.push_back(node);
  s.roots.push_back(0);
  s.lights = default_lights();
  return s;
}

std::vector<Light> default_lights() {
  Light key;
  key.direction = Eigen::Vector3d(0.45, -0.8, -0.55);
  key.intensity = 0.85;
  Light fill;
  fill.direction = Eigen::Vector3d(-0.6, -0.2, 0.7);
  fill.intensity = 0.35;
  return {key, fill};
}

namespace {

using nlohmann::json;

// Reads typed values out of the JSON, naming the key path in every error.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw ParseError(source_, ParseError::Unit::kNone, 0, path + ": " + what);
  }
  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number, found " + std::string(j.type_name()));
    double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "must be finite");
    return v;
  }
  double number_in(const json& j, const std::string& path, double lo, double hi) const {
    double v = number(j, path);
    if (v < lo || v > hi) fail(path, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  int integer_in(const json& j, const std::string& path, int lo, int hi) const {
    if (!j.is_number_integer()) fail(path, "expected an integer");
    long long v = j.get<long long>();
    if (v < lo || v > hi) fail(path, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, "expected true or false");
    return j.get<bool>();
  }
  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string");
    return j.get<std::string>();
  }
  Eigen::Vector3d vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "expected an array of 3 numbers");
    return {number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]")};
  }
  Color color(const json& j, const std::string& path) const {
    Eigen::Vector3d c = vec3(j, path);
    if (c.minCoeff() < 0) fail(path, "colour components must be >= 0");
    return c;
  }
  const json& object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, "expected an object");
    return j;
  }
  const json& array(const json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, "expected an array");
    return j;
  }
  // Unknown keys are errors: a misspelt "shadow" must not silently do nothing.
  void only_keys(const json& j, const std::string& path, std::initializer_list<const char*> keys) const {
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool known = false;
      for (const char* k : keys) known |= it.key() == k;
      if (!known) fail(path + "." + it.key(), "unknown key");
    }
  }

 private:
  std::string source_;
};

Material parse_material(const Reader& r, const json& j, const std::string& name, const std::string& path) {
  r.object(j, path);
  r.only_keys(j, path, {"diffuse", "specular", "shininess", "reflectance", "two_sided"});
  Material m;
  m.name = name;
  if (j.contains("diffuse")) m.diffuse = r.color(j["diffuse"], path + ".diffuse");
  if (j.contains("specular")) m.specular = r.color(j["specular"], path + ".specular");
  if (j.contains("shininess")) m.shininess = r.number_in(j["shininess"], path + ".shininess", 0, 1e4);
  if (j.contains("reflectance")) m.reflectance = r.number_in(j["reflectance"], path + ".reflectance", 0, 1);
  if (j.contains("two_sided")) m.two_sided = r.boolean(j["two_sided"], path + ".two_sided");
  return m;
}

Light parse_light(const Reader& r, const json& j, const std::string& path) {
  r.object(j, path);
  r.only_keys(j, path, {"type", "direction", "position", "color", "intensity", "shadows"});
  Light l;
  std::string type = j.contains("type") ? r.string(j["type"], path + ".type") : "directional";
  if (type == "directional") {
    l.kind = Light::Kind::kDirectional;
    if (j.contains("direction")) l.direction = r.vec3(j["direction"], path + ".direction");
    if (l.direction.squaredNorm() == 0) r.fail(path + ".direction", "must not be zero");
  } else if (type == "point") {
    l.kind = Light::Kind::kPoint;
    if (!j.contains("position")) r.fail(path + ".position", "a point light needs a position");
    l.position = r.vec3(j["position"], path + ".position");
  } else {
    r.fail(path + ".type", "unknown light type '" + type + "' (directional, point)");
  }
  if (j.contains("color")) l.color = r.color(j["color"], path + ".color");
  if (j.contains("intensity")) l.intensity = r.number_in(j["intensity"], path + ".intensity", 0, 1e6);
  if (j.contains("shadows")) l.shadows = r.boolean(j["shadows"], path + ".shadows");
  return l;
}

Eigen::Matrix4d parse_transform(const Reader& r, const json& j, const std::string& path) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (j.contains("matrix")) {
    const json& m = r.array(j["matrix"], path + ".matrix");
    if (m.size() != 16) r.fail(path + ".matrix", "expected 16 numbers (row-major)");
    Eigen::Matrix4d out;
    for (int i = 0; i < 16; ++i) out(i / 4, i % 4) = r.number(m[i], path + ".matrix[" + std::to_string(i) + "]");
    return out;
  }
  // Applied to points as scale, then rotate, then translate.
  if (j.contains("translate")) t.translate(r.vec3(j["translate"], path + ".translate"));
  if (j.contains("rotate")) {
    const json& a = r.array(j["rotate"], path + ".rotate");
    if (a.size() != 4) r.fail(path + ".rotate", "expected [axis x, y, z, degrees]");
    Eigen::Vector3d axis(r.number(a[0], path + ".rotate[0]"), r.number(a[1], path + ".rotate[1]"),
                         r.number(a[2], path + ".rotate[2]"));
    if (axis.squaredNorm() == 0) r.fail(path + ".rotate", "axis must not be zero");
    double deg = r.number(a[3], path + ".rotate[3]");
    t.rotate(Eigen::AngleAxisd(deg * std::numbers::pi / 180, axis.normalized()));
  }
  if (j.contains("scale")) {
    const json& s = j["scale"];
    Eigen::Vector3d v = s.is_array() ? r.vec3(s, path + ".scale")
                                     : Eigen::Vector3d::Constant(r.number(s, path + ".scale"));
    if ((v.array() == 0).any()) r.fail(path + ".scale", "must not be zero");
    t.scale(v);
  }
  return t.matrix();
}

struct Context {
  const Reader& r;
  std::map<std::string, int> meshes, materials;
  Scene& scene;
};

int parse_node(Context& c, const json& j, const std::string& path, int depth) {
  const Reader& r = c.r;
  if (depth > 64) r.fail(path, "nodes nested deeper than 64 levels");
  r.object(j, path);
  r.only_keys(j, path, {"name", "mesh", "material", "matrix", "translate", "rotate", "scale", "children"});
  SceneNode node;
  if (j.contains("name")) node.name = r.string(j["name"], path + ".name");
  if (j.contains("mesh")) {
    std::string m = r.string(j["mesh"], path + ".mesh");
    auto it = c.meshes.find(m);
    if (it == c.meshes.end()) r.fail(path + ".mesh", "unknown mesh '" + m + "'");
    node.mesh = it->second;
  }
  if (j.contains("material")) {
    std::string m = r.string(j["material"], path + ".material");
    auto it = c.materials.find(m);
    if (it == c.materials.end()) r.fail(path + ".material", "unknown material '" + m + "'");
    node.material = it->second;
  }
  node.transform = parse_transform(r, j, path);
  int index = static_cast<int>(c.scene.nodes.size());
  c.scene.nodes.push_back(node);
  if (j.contains("children")) {
    const json& kids = r.array(j["children"], path + ".children");
    for (std::size_t i = 0; i < kids.size(); ++i) {
      int child = parse_node(c, kids[i], path + ".children[" + std::to_string(i) + "]", depth + 1);
      c.scene.nodes[index].children.push_back(child);
    }
  }
  return index;
}

void parse_image(const Reader& r, const json& j, Scene& s) {
  r.object(j, "image");
  r.only_keys(j, "image", {"width", "height", "samples", "background", "wireframe", "shading",
                           "crease_angle", "ambient", "max_reflection_depth", "ground"});
  if (j.contains("width")) s.width = r.integer_in(j["width"], "image.width", 1, 16384);
  if (j.contains("height")) s.height = r.integer_in(j["height"], "image.height", 1, 16384);
  if (j.contains("samples")) s.samples = r.integer_in(j["samples"], "image.samples", 1, 256);
  if (j.contains("background")) s.background = r.color(j["background"], "image.background");
  if (j.contains("wireframe")) s.wireframe = r.boolean(j["wireframe"], "image.wireframe");
  if (j.contains("ground")) s.ground = r.boolean(j["ground"], "image.ground");
  if (j.contains("ambient")) s.ambient = r.number_in(j["ambient"], "image.ambient", 0, 1);
  if (j.contains("crease_angle"))
    s.crease_angle_degrees = r.number_in(j["crease_angle"], "image.crease_angle", 0, 180);
  if (j.contains("max_reflection_depth"))
    s.max_reflection_depth = r.integer_in(j["max_reflection_depth"], "image.max_reflection_depth", 0, 16);
  if (j.contains("shading")) {
    std::string sh = r.string(j["shading"], "image.shading");
    if (sh == "flat") s.shading = Shading::kFlat;
    else if (sh == "smooth") s.shading = Shading::kSmooth;
    else r.fail("image.shading", "expected 'flat' or 'smooth', found '" + sh + "'");
  }
}

Camera parse_camera(const Reader& r, const json& j) {
  r.object(j, "camera");
  r.only_keys(j, "camera", {"eye", "at", "up", "fov"});
  Camera cam;
  if (!j.contains("eye") || !j.contains("at")) r.fail("camera", "needs 'eye' and 'at'");
  cam.eye = r.vec3(j["eye"], "camera.eye");
  cam.at = r.vec3(j["at"], "camera.at");
  if ((cam.eye - cam.at).squaredNorm() == 0) r.fail("camera", "eye and at coincide");
  if (j.contains("up")) cam.up = r.vec3(j["up"], "camera.up");
  if (j.contains("fov")) cam.fov_y_degrees = r.number_in(j["fov"], "camera.fov", 1, 170);
  return cam;
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source, const MeshResolver& resolve) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw ParseError(source, ParseError::Unit::kByte, e.byte, std::string("invalid JSON: ") + e.what());
  } catch (const json::exception& e) {  // a number beyond a double's range ("1e999")
    throw ParseError(source, ParseError::Unit::kNone, 0, std::string("invalid JSON: ") + e.what());
  }
  Reader r(source);
  r.object(j, "scene");
  r.only_keys(j, "scene", {"image", "camera", "materials", "meshes", "nodes", "lights"});
  Scene s;
  s.materials.clear();
  s.materials.push_back(Material{});
  Context c{r, {}, {}, s};
  c.materials["default"] = 0;
  if (j.contains("image")) parse_image(r, j["image"], s);
  if (j.contains("camera")) s.camera = parse_camera(r, j["camera"]);
  if (j.contains("materials")) {
    for (auto& [name, m] : r.object(j["materials"], "materials").items()) {
      c.materials[name] = static_cast<int>(s.materials.size());
      s.materials.push_back(parse_material(r, m, name, "materials." + name));
    }
  }
  if (!j.contains("meshes")) r.fail("meshes", "a scene needs at least one mesh");
  for (auto& [name, m] : r.object(j["meshes"], "meshes").items()) {
    std::string path = r.string(m, "meshes." + name);
    c.meshes[name] = static_cast<int>(s.meshes.size());
    s.meshes.push_back(resolve(path));
  }
  if (j.contains("nodes")) {
    const json& nodes = r.array(j["nodes"], "nodes");
    for (std::size_t i = 0; i < nodes.size(); ++i)
      s.roots.push_back(parse_node(c, nodes[i], "nodes[" + std::to_string(i) + "]", 0));
  } else {
    for (int m = 0; m < static_cast<int>(s.meshes.size()); ++m) {  // one node per mesh
      SceneNode n;
      n.mesh = m;
      s.roots.push_back(static_cast<int>(s.nodes.size()));
      s.nodes.push_back(n);
    }
  }
  if (j.contains("lights")) {
    const json& lights = r.array(j["lights"], "lights");
    for (std::size_t i = 0; i < lights.size(); ++i)
      s.lights.push_back(parse_light(r, lights[i], "lights[" + std::to_string(i) + "]"));
  } else {
    s.lights = default_lights();
  }
  return s;
}

}  // namespace geom
