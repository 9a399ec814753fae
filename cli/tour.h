#pragma once
/// \file
/// `geom tour`: takes one mesh through everything geom can do and writes the results and a
/// summary (summary.md, summary.json) into an output folder.
///
/// HOW A CAPABILITY JOINS THE TOUR (one file, two lines):
///  1. Write `cli/tour_<capability>.cpp` defining `void tour_<capability>(TourContext& tour)`.
///     It calls library functions on `tour.mesh` (never computes geometry itself), writes its
///     results with tour.write_mesh()/tour.path(), and describes them:
///
///        void tour_lod(TourContext& tour) {
///          tour.heading("Simplification");
///          auto result = simplify(tour.mesh, {.target_faces = tour.mesh.n_faces() / 4});
///          tour.write_mesh("simplified.obj", result.mesh, "a quarter of the faces");
///          tour.table({{"faces", std::to_string(result.mesh.n_faces())},
///                      {"max error", TourContext::number(result.max_error)}});
///          tour.record({{"faces", result.mesh.n_faces()}, {"max_error", result.max_error}});
///        }
///
///  2. Declare it below and add `{"<capability>", tour_<capability>}` to kTourSteps in
///     cli/tour.cpp; add the file to GEOM_CLI_SOURCES in cli/CMakeLists.txt.
///
/// A step that throws is reported as failed in the summary (the tour goes on and exits 1 at
/// the end). Keep a step to a few seconds on the bundled sample.

#include "common.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace geom::cli {

class TourContext {
 public:
  TourContext(std::string input, std::filesystem::path out_dir, CommonOptions common);

  // ---- what every step starts from (filled before the first step) -------------------
  std::string input;               ///< the toured file, as given
  std::filesystem::path out_dir;   ///< where results go
  CommonOptions common;
  PolygonSoup soup;                ///< the input as read
  SurfaceMesh mesh;                ///< built from soup with default options (repaired)
  BuildReport build_report;        ///< what that build changed
  std::string stem;                ///< the input's file name without extension ("sample")

  // ---- writing results -----------------------------------------------------------------
  /// out_dir / file_name, refusing (UsageError) to name an input file.
  std::filesystem::path path(const std::string& file_name) const;
  /// Saves `mesh` as out_dir / file_name and lists it in the summary. Returns the path.
  std::filesystem::path write_mesh(const std::string& file_name, const SurfaceMesh& mesh,
                                   const std::string& description, const WriteOptions& = {});
  /// Lists a file a step wrote itself (an image, a CSV) in the summary.
  void add_file(const std::filesystem::path& path, const std::string& description);
  /// Renders `mesh` to out_dir / file_name (PNG, with its polygon edges), lists it and shows
  /// it in summary.md. (cli/tour_preview.cpp)
  void preview(const std::string& file_name, const SurfaceMesh& mesh, const std::string& caption);
  /// Several meshes side by side, each labelled; one camera when they are of one size.
  void preview_montage(const std::string& file_name,
                       const std::vector<std::pair<std::string, const SurfaceMesh*>>& tiles,
                       const std::string& caption);

  // ---- describing them (summary.md and summary.json) ------------------------------------
  void heading(const std::string& title);
  void text(const std::string& paragraph);
  void table(const std::vector<std::pair<std::string, std::string>>& rows);
  /// A table with a header row and several columns.
  void grid(const std::vector<std::string>& header,
            const std::vector<std::vector<std::string>>& rows);
  /// Merges `j` into this step's object in summary.json.
  void record(const nlohmann::json& j);
  /// A progress line on stderr (unless --quiet).
  void log(const std::string& line) const;
  /// Shortest round-trip formatting of a double, for tables.
  static std::string number(double value);

  // ---- used by the runner --------------------------------------------------------------
  void begin_step(const std::string& name);
  void end_step(double seconds, const std::string& error);
  nlohmann::json summary;          ///< {"input":…, "steps": {name: {...}}, "files": [...]}
  std::string markdown;
  bool failed = false;

 private:
  std::string step_;
};

using TourStep = void (*)(TourContext&);

void tour_core(TourContext& tour);         // info, validate, repair (cli/tour_core.cpp)
void tour_io(TourContext& tour);           // every format, written and read back (cli/tour_io.cpp)
void tour_isosurface(TourContext& tour);   // marching cubes of implicits (cli/tour_isosurface.cpp)
void tour_subdivision(TourContext& tour);  // Catmull-Clark levels and limit (cli/tour_subdivision.cpp)
void tour_lod(TourContext& tour);          // an LOD chain with measured error (cli/tour_lod.cpp)
void tour_compress(TourContext& tour);     // the codec at several bit depths (cli/tour_compress.cpp)
void tour_compgeom(TourContext& tour);     // hull and Delaunay of the vertices (cli/tour_compgeom.cpp)
void tour_render(TourContext& tour);       // effects on demand: raster, shadows, mirror (cli/tour_render.cpp)
void tour_batch(TourContext& tour);        // five formats and a broken file, one pipeline (cli/tour_batch.cpp)

}  // namespace geom::cli
