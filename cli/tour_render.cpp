// Tour step "render": the same mesh three ways, each paying only for what it shows.

#include "tour.h"

#include <geom/render/render.h>

#include <fstream>

namespace geom::cli {

void tour_render(TourContext& tour) {
  tour.heading("Rendering");
  tour.text("`geom render`: a scene without shadows or mirrors is rasterised and builds no "
            "BVH; shadows cast rays only toward lights that ask for them, mirror rays leave "
            "only reflective materials.");
  auto mesh = std::make_shared<const SurfaceMesh>(tour.mesh);
  std::vector<std::vector<std::string>> rows;
  nlohmann::json j = nlohmann::json::array();
  const char* names[] = {"raster", "shadows", "mirror"};
  for (int variant = 0; variant < 3; ++variant) {
    Scene s = scene_for_mesh(mesh);
    s.width = 640;
    s.height = 480;
    s.ground = true;
    if (variant >= 1) s.lights.front().shadows = true;
    if (variant == 2) s.materials[0].reflectance = 0.35;
    RenderResult r = render(s);
    const std::string file = tour.stem + "_render_" + names[variant] + ".png";
    const auto p = tour.path(file);
    auto png = encode_png(r.image);
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(png.data()),
                                            static_cast<std::streamsize>(png.size()));
    tour.add_file(p, std::string("render: ") + names[variant]);
    const auto& st = r.stats;
    const double secs = st.seconds_setup + st.seconds_bvh + st.seconds_render + st.seconds_wireframe;
    rows.push_back({names[variant], st.path, st.bvh_built ? "yes" : "no", std::to_string(st.primary_rays),
                    std::to_string(st.shadow_rays), std::to_string(st.reflection_rays), TourContext::number(secs)});
    j.push_back({{"scene", names[variant]}, {"path", st.path}, {"bvh_built", st.bvh_built},
                 {"shadow_rays", st.shadow_rays}, {"reflection_rays", st.reflection_rays}, {"seconds", secs}});
    tour.markdown += "![" + std::string(names[variant]) + "](" + file + ")\n";
  }
  tour.markdown += "\n";
  tour.grid({"scene", "path", "BVH", "primary rays", "shadow rays", "reflection rays", "seconds"}, rows);
  tour.record({{"renders", j}});
}

}  // namespace geom::cli
