// libFuzzer target for JSON scenes (geom/render/SCENE.md): any text must parse or throw
// ParseError naming the key, and a scene that parses must render (shrunk to a few pixels so
// that the fuzzer spends its time on the scene, not on pixels): odd cameras, transforms,
// lights and materials may not crash the rasteriser or the ray tracer. Every mesh name
// resolves to one tetrahedron.

#include <geom/core/errors.h>
#include <geom/render/render.h>

#include "../render/meshes.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  geom::Scene scene;
  try {
    // One mesh for every name, made once (the fuzzer calls this millions of times).
    static const std::shared_ptr<const geom::SurfaceMesh> tetrahedron = geom::test::tetrahedron();
    scene = geom::parse_scene(text, "fuzz.json", [](const std::string&) { return tetrahedron; });
  } catch (const geom::ParseError&) {
    return 0;
  }
  scene.width = std::min(scene.width, 8);
  scene.height = std::min(scene.height, 8);
  scene.samples = std::min(scene.samples, 4);
  scene.nodes.resize(std::min<std::size_t>(scene.nodes.size(), 64));
  std::erase_if(scene.roots, [&](int r) { return r >= static_cast<int>(scene.nodes.size()); });
  for (auto& n : scene.nodes)
    std::erase_if(n.children, [&](int c) { return c >= static_cast<int>(scene.nodes.size()); });
  geom::render(scene);  // may not throw: the scene parsed
  return 0;
}
