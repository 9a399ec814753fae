#pragma once
/// \file
/// What a picture shows: meshes placed by a node hierarchy (instancing allowed), materials,
/// lights, a camera, and image settings. The JSON form is documented in SCENE.md beside
/// this file.

#include <geom/core/surface_mesh.h>
#include <geom/render/camera.h>

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geom {

/// Blinn-Phong with an optional mirror term.
struct Material {
  std::string name = "default";
  Color diffuse{0.70, 0.72, 0.78};
  Color specular{0.25, 0.25, 0.25};
  double shininess = 48;
  double reflectance = 0;  ///< 0 = no mirror rays for this material
  bool two_sided = false;  ///< never back-face culled
};

struct Light {
  enum class Kind { kDirectional, kPoint };
  Kind kind = Kind::kDirectional;
  Eigen::Vector3d direction{-0.4, -1.0, -0.6};  ///< directional: where the light travels
  Eigen::Vector3d position{0, 10, 0};          ///< point
  Color color{1, 1, 1};
  double intensity = 1.0;
  bool shadows = false;  ///< cast shadow rays for this light
};

struct SceneNode {
  std::string name;
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  ///< relative to the parent
  int mesh = -1;      ///< index into Scene::meshes, or −1 for a pure group
  int material = 0;   ///< index into Scene::materials
  std::vector<int> children;
};

enum class Shading { kFlat, kSmooth };

struct Scene {
  std::vector<std::shared_ptr<const SurfaceMesh>> meshes;
  std::vector<Material> materials{Material{}};
  std::vector<SceneNode> nodes;
  std::vector<int> roots;  ///< top-level nodes
  std::vector<Light> lights;
  std::optional<Camera> camera;  ///< empty: frame the scene's bounding box
  Color background{1, 1, 1};
  double ambient = 0.18;
  int width = 800, height = 600;
  int samples = 4;          ///< per pixel (the rasteriser rounds up to a square)
  bool wireframe = false;
  Shading shading = Shading::kSmooth;
  double crease_angle_degrees = 60;  ///< smooth shading keeps edges sharper than this
  int max_reflection_depth = 3;
  bool ground = false;  ///< a floor under the scene's bounding box (to catch shadows)
};

/// A scene showing one mesh: one node, default material and a key + fill light.
Scene scene_for_mesh(std::shared_ptr<const SurfaceMesh> mesh);
/// The default lighting used when a scene names no lights: a key light from the upper left
/// and a dimmer fill, both without shadows.
std::vector<Light> default_lights();

/// Resolves a mesh reference (a path, as written in the scene file) to a mesh; supplied by
/// the caller so that the renderer never reads files itself.
using MeshResolver = std::function<std::shared_ptr<const SurfaceMesh>(const std::string&)>;

/// Parse a JSON scene. Throws: ParseError naming `source` and the offending key path (e.g.
/// "nodes[2].material: unknown material 'gold'") for malformed JSON, wrong types, unknown
/// references or values out of range; whatever the resolver throws for a missing mesh.
Scene parse_scene(const std::string& json_text, const std::string& source,
                  const MeshResolver& resolve);

}  // namespace geom
