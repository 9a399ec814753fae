#include "common.h"

#include <geom/core/errors.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <iterator>
#include <map>
#include <mutex>
#include <sstream>

namespace geom::cli {

namespace fs = std::filesystem;

void add_common_options(CLI::App* cmd, CommonOptions& options, unsigned flags) {
  if (flags & kOutput) cmd->add_option("-o,--output", options.output, "Output file");
  if (flags & kJson) cmd->add_flag("--json", options.json, "Print one JSON document on stdout");
  if (flags & kQuiet)
    cmd->add_flag("-q,--quiet", options.quiet, "Print nothing but errors; no progress bar");
  if (flags & kForce)
    cmd->add_flag("--force", options.force, "Allow an output to overwrite an input file");
  if (flags & kFormat) {
    cmd->add_option_function<std::string>(
           "--format", [&options](const std::string& s) { options.output_format = parse_format(s); },
           "Output format (obj, ply, off, stl, drc, gltf, glb); needed when writing to stdout")
        ->check(CLI::IsMember({"obj", "ply", "off", "stl", "drc", "gltf", "glb"}, CLI::ignore_case));
  }
}

CLI::App* add_command(CLI::App& app, const std::string& name, const std::string& description,
                      std::function<int()> run) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->callback([run = std::move(run)] {
    // CLI11 runs callbacks inside parse(); a non-zero code travels out as an exception so
    // that main() stays the only place that decides how the process ends.
    if (int code = run(); code != 0) throw ExitCode{code};
  });
  return cmd;
}

// ---- progress ------------------------------------------------------------------------

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled && ::isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() { finish(); }

void Progress::update(double fraction, const std::string& stage) {
  if (!enabled_) return;
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  const int permille = static_cast<int>(fraction * 1000.0);
  const auto now = std::chrono::steady_clock::now();
  // Redraw at most ~20 times a second unless the stage changes, so a fast loop calling
  // update() does not spend its time writing to the terminal.
  if (stage == last_stage_ &&
      (permille == last_permille_ || now - last_draw_ < std::chrono::milliseconds(50)))
    return;
  last_permille_ = permille;
  last_stage_ = stage;
  last_draw_ = now;
  constexpr int kWidth = 30;
  const int filled = permille * kWidth / 1000;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r\033[K%s [%s] %3d%% %s", label_.c_str(), bar.c_str(), permille / 10,
               stage.c_str());
  std::fflush(stderr);
}

std::function<bool(double)> Progress::callback() {
  return [this](double f) {
    update(f, last_stage_);
    return true;
  };
}

void Progress::finish() {
  if (enabled_ && last_permille_ >= 0) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
  last_permille_ = -1;
}

// ---- input ---------------------------------------------------------------------------

namespace {

PolygonSoup read_soup_or_stdin(const std::string& path) {
  if (path != "-") return read_soup(path);
  std::string bytes((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
  auto data = std::as_bytes(std::span<const char>(bytes.data(), bytes.size()));
  auto format = sniff_format(data);
  if (!format) throw Error("<stdin>: cannot tell the mesh format from its content");
  return read_soup(data, *format, "<stdin>");
}

// The material files (OBJ mtllib) of each input read, for write_output to name again.
std::mutex libraries_mutex;
std::map<std::string, std::vector<std::string>> libraries_read;

std::vector<std::string> material_libraries_of(const std::string& input) {
  const std::lock_guard lock(libraries_mutex);
  const auto it = libraries_read.find(input);
  return it == libraries_read.end() ? std::vector<std::string>{} : it->second;
}

}  // namespace

PolygonSoup read_input(const std::string& path, const CommonOptions& common) {
  PolygonSoup soup = read_soup_or_stdin(path);
  if (!soup.material_libraries.empty()) {
    const std::lock_guard lock(libraries_mutex);
    libraries_read[path] = soup.material_libraries;
  }
  if (!common.quiet)
    for (const std::string& w : soup.warnings)
      std::cerr << "geom: warning: " << (path == "-" ? std::string("<stdin>") : path) << ": " << w << '\n';
  return soup;
}

Loaded load_input(const std::string& path, const CommonOptions& common,
                  const BuildOptions& build_options, bool report_changes) {
  Progress progress(path == "-" ? std::string("<stdin>") : fs::path(path).filename().string(),
                    !common.quiet);
  progress.update(0.0, "reading");
  Loaded loaded;
  loaded.soup = read_input(path, common);
  progress.update(0.6, "building");
  BuildResult built = build(loaded.soup, build_options);
  loaded.mesh = std::move(built.mesh);
  loaded.report = std::move(built.report);
  progress.update(1.0, "done");
  if (report_changes && !common.quiet)
    for (const std::string& m : loaded.report.messages)
      std::cerr << "geom: warning: " << (path == "-" ? std::string("<stdin>") : path)
                << ": building the mesh changed it: " << m << '\n';
  return loaded;
}

BuildOptions repair_defaults() {
  BuildOptions options;
  options.weld_tolerance = 0.0;
  options.orient = true;
  options.drop_unreferenced = true;
  return options;
}

// ---- output --------------------------------------------------------------------------

bool same_file(const std::string& output, const std::string& input) {
  if (output == "-" || input == "-" || output.empty() || input.empty()) return false;
  std::error_code ec;
  const fs::path out(output), in(input);
  if (fs::exists(out, ec) && fs::exists(in, ec)) return fs::equivalent(out, in, ec);
  return fs::weakly_canonical(out, ec) == fs::weakly_canonical(in, ec);
}

void check_not_input(const std::string& output, const std::vector<std::string>& inputs,
                     const CommonOptions& common) {
  if (common.force) return;
  for (const auto& in : inputs)
    if (same_file(output, in))
      throw UsageError("refusing to overwrite the input '" + in +
                       "' with an output (pass --force to allow it)");
}

void require_extension(const std::string& path, std::initializer_list<std::string_view> extensions,
                       const std::string& option) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (std::string_view e : extensions)
    if (ext == e) return;
  std::string expected;
  std::size_t k = 0;
  for (std::string_view e : extensions) {
    if (k > 0) expected += k + 1 == extensions.size() ? " or " : ", ";
    expected += e;
    ++k;
  }
  throw UsageError(option + " '" + path + "' must end in " + expected);
}

void write_output(const SurfaceMesh& mesh, const std::vector<std::string>& inputs,
                  const CommonOptions& common, WriteOptions write, const std::string& path) {
  PolygonSoup soup = to_soup(mesh);
  // A mesh keeps its faces' material names but not the files defining them: those of the
  // inputs it was made from.
  if (!soup.face_materials.empty())
    for (const std::string& input : inputs)
      for (const std::string& lib : material_libraries_of(input))
        if (std::ranges::find(soup.material_libraries, lib) == soup.material_libraries.end())
          soup.material_libraries.push_back(lib);
  write_output(soup, inputs, common, write, path);
}

void write_output(const PolygonSoup& soup, const std::vector<std::string>& inputs,
                  const CommonOptions& common, WriteOptions write, const std::string& path) {
  const std::string out = path.empty() ? common.output : path;
  if (out.empty()) throw UsageError("no output file given (-o/--output)");
  check_not_input(out, inputs, common);
  if (!write.format) write.format = common.output_format;
  if (out == "-" && !write.format)
    throw UsageError("writing to stdout needs --format (obj, ply, off, stl or drc)");
  Progress progress(out == "-" ? std::string("<stdout>") : fs::path(out).filename().string(),
                    !common.quiet);
  progress.update(0.0, "writing");
  write_soup(soup, out, write);
  const FileFormat format = write.format ? *write.format : format_from_path(out);
  if (!common.quiet)
    for (const std::string& line : unstored(soup, format, write))
      std::cerr << "geom: warning: " << out << ": " << line << '\n';
}

void warn_not_carried(const std::string& command, const std::vector<std::string>& names,
                      const CommonOptions& common, const std::string& what) {
  if (common.quiet || names.empty()) return;
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  std::cerr << "geom " << command << ": warning: " << what << ": " << list << '\n';
}

void report(const CommonOptions& common, const nlohmann::json& j, const std::string& text) {
  if (common.json) {
    std::cout << j.dump(2) << '\n';
  } else if (!common.quiet) {
    std::cout << text;
    if (!text.empty() && text.back() != '\n') std::cout << '\n';
  }
  std::cout.flush();
}

// ---- reports -------------------------------------------------------------------------

namespace {

nlohmann::json optional_json(const std::optional<long>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json bounds_json(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return nullptr;
  const auto& lo = box.min();
  const auto& hi = box.max();
  return {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}};
}

std::string yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

nlohmann::json to_json(const TopologyReport& r) {
  nlohmann::json sizes = nlohmann::json::object();
  for (const auto& [corners, count] : r.face_sizes) sizes[std::to_string(corners)] = count;
  nlohmann::json components = nlohmann::json::array();
  for (const auto& c : r.per_component)
    components.push_back({{"vertices", c.vertices},
                          {"edges", c.edges},
                          {"faces", c.faces},
                          {"boundary_loops", c.boundary_loops},
                          {"euler_characteristic", c.euler_characteristic},
                          {"orientable", c.orientable},
                          {"genus", optional_json(c.genus)}});
  return {{"vertices", r.vertices},
          {"edges", r.edges},
          {"faces", r.faces},
          {"isolated_vertices", r.isolated_vertices},
          {"boundary_edges", r.boundary_edges},
          {"boundary_loops", r.boundary_loops},
          {"components", r.components},
          {"euler_characteristic", r.euler_characteristic},
          {"genus", optional_json(r.genus)},
          {"closed", r.closed},
          {"manifold", r.manifold},
          {"orientable", r.orientable},
          {"consistently_oriented", r.consistently_oriented},
          {"out_of_range_faces", r.out_of_range_faces},
          {"nonmanifold_vertices", r.nonmanifold_vertices},
          {"nonmanifold_edges", r.nonmanifold_edges},
          {"degenerate_faces", r.degenerate_faces},
          {"face_sizes", sizes},
          {"bounds", bounds_json(r.bounds)},
          {"per_component", components}};
}

nlohmann::json to_json(const BuildReport& r) {
  return {{"changed", r.changed()},
          {"welded_vertices", r.welded_vertices},
          {"unreferenced_vertices", r.unreferenced_vertices},
          {"dropped_out_of_range", r.dropped_out_of_range},
          {"dropped_degenerate", r.dropped_degenerate},
          {"dropped_duplicate", r.dropped_duplicate},
          {"split_nonmanifold_edges", r.split_nonmanifold_edges},
          {"split_nonmanifold_vertices", r.split_nonmanifold_vertices},
          {"flipped_faces", r.flipped_faces},
          {"collapsed_corners", r.collapsed_corners},
          {"cut_edges", r.cut_edges},
          {"detached_faces", r.detached_faces},
          {"dropped_unreferenced", r.dropped_unreferenced},
          {"orientable", r.orientable},
          {"messages", r.messages}};
}

std::string to_text(const TopologyReport& r) {
  std::ostringstream s;
  auto row = [&s](const char* name, const auto& value) {
    s << "  " << name << std::string(24 - std::min<std::size_t>(23, std::strlen(name)), ' ')
      << value << '\n';
  };
  row("vertices", r.vertices);
  row("edges", r.edges);
  row("faces", r.faces);
  row("boundary loops", r.boundary_loops);
  row("components", r.components);
  row("euler characteristic", r.euler_characteristic);
  row("genus", r.genus ? std::to_string(*r.genus) : std::string("n/a (not an orientable manifold)"));
  row("closed", yes_no(r.closed));
  row("manifold", yes_no(r.manifold));
  row("orientable", yes_no(r.orientable));
  if (r.isolated_vertices) row("isolated vertices", r.isolated_vertices);
  if (r.nonmanifold_vertices) row("non-manifold vertices", r.nonmanifold_vertices);
  if (r.nonmanifold_edges) row("non-manifold edges", r.nonmanifold_edges);
  if (r.degenerate_faces) row("degenerate faces", r.degenerate_faces);
  std::string sizes;
  for (const auto& [corners, count] : r.face_sizes) {
    if (!sizes.empty()) sizes += ", ";
    sizes += std::to_string(count) + " × " + std::to_string(corners) + "-gon";
  }
  row("face sizes", sizes.empty() ? std::string("-") : sizes);
  if (!r.bounds.isEmpty()) {
    std::ostringstream b;
    b << '[' << r.bounds.min().x() << ", " << r.bounds.min().y() << ", " << r.bounds.min().z()
      << "] – [" << r.bounds.max().x() << ", " << r.bounds.max().y() << ", "
      << r.bounds.max().z() << ']';
    row("bounds", b.str());
  }
  return s.str();
}

std::string to_text(const BuildReport& r) {
  if (!r.changed() && r.messages.empty()) return "  nothing to repair\n";
  std::string s;
  for (const auto& m : r.messages) s += "  " + m + '\n';
  if (r.messages.empty()) s += "  repaired (no details reported)\n";
  return s;
}

FileFormat parse_format(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  for (FileFormat f : {FileFormat::kObj, FileFormat::kPly, FileFormat::kOff, FileFormat::kStl,
                       FileFormat::kDrc, FileFormat::kGltf, FileFormat::kGlb})
    if (n == format_name(f)) return f;
  throw UsageError("unknown format '" + name + "' (expected obj, ply, off, stl, drc, gltf or glb)");
}

}  // namespace geom::cli
