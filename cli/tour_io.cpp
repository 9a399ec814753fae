// Tour step "io": the mesh written in every format geom supports and read back.

#include "tour.h"

#include <chrono>
#include <cmath>

namespace geom::cli {

void tour_io(TourContext& tour) {
  struct Variant {
    const char* file_suffix;
    const char* label;
    FileFormat format;
    bool binary;
    int drc_bits;
  };
  const Variant variants[] = {
      {".obj", "OBJ", FileFormat::kObj, false, 0},
      {".ply", "PLY binary", FileFormat::kPly, true, 0},
      {"_ascii.ply", "PLY ASCII", FileFormat::kPly, false, 0},
      {".off", "OFF", FileFormat::kOff, false, 0},
      {".stl", "STL binary (triangulated)", FileFormat::kStl, true, 0},
      {"_ascii.stl", "STL ASCII (triangulated)", FileFormat::kStl, false, 0},
      {".drc", "Draco, lossless", FileFormat::kDrc, true, 0},
      {"_14bit.drc", "Draco, 14-bit positions", FileFormat::kDrc, true, 14},
      {".glb", "glTF binary (triangulated, float positions)", FileFormat::kGlb, true, 0},
      {".gltf", "glTF JSON with an embedded buffer", FileFormat::kGltf, false, 0},
  };

  tour.heading("Every file format");
  tour.text("`geom convert` to each format, then read back as the file holds it (`geom info`). "
            "What a format cannot hold is named, with counts, in the last column: `geom convert` "
            "prints the same lines as warnings.");
  const PolygonSoup given = to_soup(tour.mesh);
  std::vector<std::vector<std::string>> rows;
  nlohmann::json formats = nlohmann::json::array();
  for (const Variant& v : variants) {
    WriteOptions options;
    options.format = v.format;
    options.binary = v.binary;
    options.drc_position_bits = v.drc_bits;
    const std::string name = tour.stem + v.file_suffix;
    const auto t0 = std::chrono::steady_clock::now();
    const auto path = tour.write_mesh(name, tour.mesh, v.label, options);
    const auto t1 = std::chrono::steady_clock::now();
    const PolygonSoup back = read_soup(path);
    const auto t2 = std::chrono::steady_clock::now();
    std::string lost;
    for (const std::string& line : unstored(given, v.format, options)) lost += (lost.empty() ? "" : "; ") + line;
    const auto bytes = std::filesystem::file_size(path);
    const double write_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    const double read_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    rows.push_back({name, v.label, std::to_string(bytes), std::to_string(back.positions.size()),
                    std::to_string(back.n_faces()),
                    TourContext::number(std::round(write_ms * 100) / 100),
                    TourContext::number(std::round(read_ms * 100) / 100), lost.empty() ? "nothing" : lost});
    formats.push_back({{"file", name},
                       {"format", format_name(v.format)},
                       {"binary", v.binary},
                       {"drc_position_bits", v.drc_bits},
                       {"bytes", bytes},
                       {"vertices_read_back", back.positions.size()},
                       {"faces_read_back", back.n_faces()},
                       {"not_stored", unstored(given, v.format, options)},
                       {"write_ms", write_ms},
                       {"read_ms", read_ms}});
  }
  tour.grid({"file", "format", "bytes", "vertices read back", "faces read back", "write ms",
             "read ms", "not stored"},
            rows);
  const LoadResult glb = load_mesh(tour.out_dir / (tour.stem + ".glb"));
  tour.preview(tour.stem + "_from_glb.png", glb.mesh, "the mesh read back from its .glb");
  tour.record({{"formats", formats}});
}

}  // namespace geom::cli
