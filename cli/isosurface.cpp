// geom isosurface: marching cubes on a built-in implicit surface, a grid file, or the signed
// distance to a closed mesh.

#include "commands.h"
#include "common.h"

#include <geom/io/grid.h>
#include <geom/isosurface/implicit.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mesh_sdf.h>

#include <memory>

namespace geom::cli {

namespace {

/// A built-in shape and the half-width of the cube it is sampled in.
std::pair<ScalarFunction, double> implicit_by_name(const std::string& name) {
  if (name == "sphere") return {implicit::Sphere{Eigen::Vector3d::Zero(), 0.8}, 1.0};
  if (name == "torus") return {implicit::Torus{}, 1.0};
  if (name == "gyroid") return {implicit::Gyroid{0.5, 0.9}, 1.0};
  if (name == "genus3") return {implicit::Genus3{}, 1.25};
  if (name == "metaballs") {
    implicit::Metaballs m;
    m.balls = {{Eigen::Vector3d(-0.3, 0, 0), 0.35}, {Eigen::Vector3d(0.3, 0, 0), 0.35},
               {Eigen::Vector3d(0, 0.35, 0.1), 0.3}};
    return {m, 1.0};
  }
  throw UsageError("unknown implicit '" + name +
                   "' (expected sphere, torus, gyroid, genus3 or metaballs)");
}

std::array<std::size_t, 3> parse_dims(const std::string& text) {
  std::array<std::size_t, 3> d{};
  std::size_t pos = 0;
  for (int k = 0; k < 3; ++k) {
    std::size_t end = text.find(',', pos);
    if ((k < 2) != (end != std::string::npos))
      throw UsageError("--dims expects NX,NY,NZ, got '" + text + "'");
    try {
      d[k] = std::stoull(text.substr(pos, end - pos));
    } catch (const std::exception&) {
      throw UsageError("--dims expects NX,NY,NZ, got '" + text + "'");
    }
    pos = end + 1;
  }
  return d;
}

}  // namespace

void add_isosurface_command(CLI::App& app) {
  struct Args {
    std::string input, implicit_name, sdf_mesh, dims, dtype = "<f4", toward = "increasing";
    std::size_t resolution = 128;
    double level = 0.0;
    std::vector<double> spacing, origin;
    bool raw = false, normals = false, serial = false;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "isosurface",
      "Extract an iso-surface (marching cubes) from a built-in implicit, a .npy/raw grid, or "
      "the signed distance to a closed mesh",
      [args] {
        if (int(!args->input.empty()) + int(!args->implicit_name.empty()) +
                int(!args->sdf_mesh.empty()) != 1)
          throw UsageError("give exactly one of a GRID file, --implicit NAME or --sdf MESH");
        MarchingCubesOptions options;
        options.level = args->level;
        options.compute_normals = args->normals;
        options.parallel = !args->serial;
        if (args->toward == "decreasing")
          options.normals_toward = NormalDirection::kDecreasing;
        else if (args->toward != "increasing")
          throw UsageError("--normals-toward expects increasing or decreasing");

        ScalarGrid grid;
        std::string source;
        nlohmann::json sdf_json;
        if (!args->sdf_mesh.empty()) {
          if (args->resolution < 8 || args->resolution > 4096)
            throw UsageError("--resolution must be in [8, 4096] with --sdf");
          Loaded in = load_input(args->sdf_mesh, args->common);
          MeshSdf sdf;
          try {
            sdf = signed_distance_grid(in.mesh, {.resolution = args->resolution, .level = args->level});
          } catch (const InvalidArgument& e) {
            throw Error(args->sdf_mesh + ": " + e.what());
          }
          grid = std::move(sdf.grid);
          source = args->sdf_mesh;
          sdf_json = {{"samples", sdf.stats.samples},
                      {"exact_samples", sdf.stats.exact_samples},
                      {"blocks", sdf.stats.blocks},
                      {"near_blocks", sdf.stats.near_blocks}};
        } else if (!args->implicit_name.empty()) {
          auto [f, half] = implicit_by_name(args->implicit_name);
          if (args->resolution < 2 || args->resolution > 4096)
            throw UsageError("--resolution must be in [2, 4096]");
          grid = sample(f, cube_box(half, args->resolution));
          source = args->implicit_name;
        } else {
          GridData data;
          if (args->raw) {
            if (args->dims.empty()) throw UsageError("--raw needs --dims NX,NY,NZ");
            auto d = parse_dims(args->dims);
            data = read_raw(args->input, {.nx = d[0], .ny = d[1], .nz = d[2], .dtype = args->dtype});
          } else {
            data = read_npy(args->input);
          }
          GridGeometry geo;
          if (!args->spacing.empty()) {
            if (args->spacing.size() != 3) throw UsageError("--spacing expects 3 numbers");
            geo.spacing = Eigen::Vector3d(args->spacing[0], args->spacing[1], args->spacing[2]);
          }
          if (!args->origin.empty()) {
            if (args->origin.size() != 3) throw UsageError("--origin expects 3 numbers");
            geo.origin = Eigen::Vector3d(args->origin[0], args->origin[1], args->origin[2]);
          }
          GridDims dims{data.nx, data.ny, data.nz};
          if (data.nx == 0 || data.ny == 0 || data.nz == 0)
            throw InvalidArgument(args->input + ": the grid is empty (" + std::to_string(data.nx) +
                                  "×" + std::to_string(data.ny) + "×" + std::to_string(data.nz) + " samples)");
          grid = data.is_double ? ScalarGrid(dims, std::move(data.doubles), geo)
                                : ScalarGrid(dims, std::move(data.floats), geo);
          source = args->input;
        }
        MarchingCubesResult r = marching_cubes(grid.view(), options);
        std::vector<std::string> inputs;
        if (!args->input.empty()) inputs.push_back(args->input);
        if (!args->sdf_mesh.empty()) inputs.push_back(args->sdf_mesh);
        write_output(r.mesh, inputs, args->common);
        const auto& s = r.stats;
        const long euler = long(r.mesh.n_vertices()) - long(r.mesh.n_edges()) + long(r.mesh.n_faces());
        nlohmann::json j = {{"source", source},
                            {"dims", {grid.dims().nx, grid.dims().ny, grid.dims().nz}},
                            {"level", args->level},
                            {"vertices", s.vertices},
                            {"triangles", s.triangles},
                            {"edge_vertices", s.edge_vertices},
                            {"centroid_vertices", s.centroid_vertices},
                            {"active_cells", s.active_cells},
                            {"cells", s.cells},
                            {"ambiguous_faces", s.ambiguous_faces},
                            {"tunnels", s.tunnels},
                            {"closed", s.closed},
                            {"euler_characteristic", euler}};
        if (!sdf_json.is_null()) j["signed_distance"] = sdf_json;
        std::string text = source + ": " + std::to_string(s.vertices) + " vertices, " +
                           std::to_string(s.triangles) + " triangles, " +
                           (s.closed ? "closed" : "open at the grid boundary") +
                           ", Euler characteristic " + std::to_string(euler) + "\n";
        CommonOptions out = args->common;
        if (args->common.output == "-") out.quiet = true, out.json = false;
        report(out, j, text);
        return 0;
      });
  cmd->add_option("grid", args->input, "Grid file: .npy (any numeric dtype), or raw with --raw");
  cmd->add_option("--implicit", args->implicit_name,
                  "Built-in surface: sphere, torus, gyroid, genus3, metaballs");
  cmd->add_option("--sdf", args->sdf_mesh,
                  "Closed mesh whose signed distance (negative inside) is contoured; "
                  "--level L > 0 gives an offset surface, L < 0 an inset");
  cmd->add_option("--resolution", args->resolution,
                  "Samples per axis for --implicit, along the longest axis for --sdf (default 128)");
  cmd->add_option("--level", args->level, "Iso level (default 0; value == level counts as above)");
  cmd->add_option("--normals-toward", args->toward,
                  "Triangles face increasing (default) or decreasing values");
  cmd->add_flag("--normals", args->normals, "Write vertex normals from the field gradient");
  cmd->add_flag("--serial", args->serial, "Use one thread");
  cmd->add_flag("--raw", args->raw, "GRID is raw binary samples, x fastest (needs --dims)");
  cmd->add_option("--dims", args->dims, "Raw grid size NX,NY,NZ");
  cmd->add_option("--dtype", args->dtype, "Raw sample type in NumPy notation (default <f4)");
  cmd->add_option("--spacing", args->spacing, "Grid spacing SX SY SZ (default 1 1 1)")->expected(3);
  cmd->add_option("--origin", args->origin, "Grid origin OX OY OZ (default 0 0 0)")->expected(3);
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
