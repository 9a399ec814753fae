// geom tour [FILE] [-o out/]: every capability in turn, on the bundled sample by default.

#include "tour.h"

#include "commands.h"

#include <charconv>
#include <cmath>
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>

#include <unistd.h>

namespace geom::cli {

namespace fs = std::filesystem;

namespace {

struct NamedStep {
  const char* name;
  TourStep run;
};

// One line per capability, in tour order.
constexpr NamedStep kTourSteps[] = {
    {"core", tour_core},
    {"io", tour_io},
    {"isosurface", tour_isosurface},
    {"subdivision", tour_subdivision},
    {"lod", tour_lod},
    {"compress", tour_compress},
    {"compgeom", tour_compgeom},
    {"render", tour_render},
    {"batch", tour_batch},
};

// The bundled sample: next to the sources in a build tree, in <prefix>/share/geom when
// installed (found relative to the executable, so a relocated install still works).
fs::path find_sample() {
  std::vector<fs::path> candidates;
#ifdef GEOM_SOURCE_DATA_DIR
  candidates.emplace_back(fs::path(GEOM_SOURCE_DATA_DIR) / "sample.obj");
#endif
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share/geom/sample.obj");
#ifdef GEOM_INSTALL_DATA_DIR
  candidates.emplace_back(fs::path(GEOM_INSTALL_DATA_DIR) / "sample.obj");
#endif
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) return c;
  std::string tried;
  for (const auto& c : candidates) tried += (tried.empty() ? "" : ", ") + c.string();
  throw Error("cannot find the bundled sample mesh (looked for " + tried +
              "); pass a mesh file to tour");
}

std::string md_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

// ---- TourContext --------------------------------------------------------------------------

TourContext::TourContext(std::string input_, fs::path out_dir_, CommonOptions common_)
    : input(std::move(input_)), out_dir(std::move(out_dir_)), common(std::move(common_)) {
  stem = input == "-" ? std::string("stdin") : fs::path(input).stem().string();
  summary = {{"input", input}, {"output_dir", out_dir.string()},
             {"steps", nlohmann::json::object()}, {"files", nlohmann::json::array()}};
}

fs::path TourContext::path(const std::string& file_name) const {
  fs::path p = out_dir / file_name;
  check_not_input(p.string(), {input}, common);
  return p;
}

fs::path TourContext::write_mesh(const std::string& file_name, const SurfaceMesh& m,
                                 const std::string& description, const WriteOptions& options) {
  fs::path p = path(file_name);
  save_mesh(m, p, options);
  add_file(p, description);
  return p;
}

void TourContext::add_file(const fs::path& p, const std::string& description) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  const std::string rel = fs::relative(p, out_dir, ec).string();
  summary["files"].push_back({{"path", ec ? p.string() : rel},
                              {"bytes", size},
                              {"step", step_},
                              {"description", description}});
}

void TourContext::heading(const std::string& title) { markdown += "\n## " + title + "\n\n"; }

void TourContext::text(const std::string& paragraph) { markdown += paragraph + "\n\n"; }

void TourContext::table(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::vector<std::vector<std::string>> cells;
  for (const auto& [k, v] : rows) cells.push_back({k, v});
  grid({"property", "value"}, cells);
}

void TourContext::grid(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows) {
  auto line = [this](const std::vector<std::string>& cells) {
    markdown += '|';
    for (const auto& c : cells) markdown += ' ' + md_escape(c) + " |";
    markdown += '\n';
  };
  line(header);
  markdown += '|';
  for (std::size_t i = 0; i < header.size(); ++i) markdown += "---|";
  markdown += '\n';
  for (const auto& r : rows) line(r);
  markdown += '\n';
}

void TourContext::record(const nlohmann::json& j) {
  auto& step = summary["steps"][step_];
  if (j.is_object())
    step.update(j);
  else
    step["value"] = j;
}

void TourContext::log(const std::string& line) const {
  // Progress, like the bar: only for a person watching, so stderr stays one line on failure.
  if (!common.quiet && ::isatty(STDERR_FILENO) == 1) std::cerr << "tour: " << line << '\n';
}

std::string TourContext::number(double value) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

void TourContext::begin_step(const std::string& name) {
  step_ = name;
  summary["steps"][name] = nlohmann::json::object();
}

void TourContext::end_step(double seconds, const std::string& error) {
  auto& step = summary["steps"][step_];
  step["seconds"] = seconds;
  step["ok"] = error.empty();
  if (!error.empty()) {
    step["error"] = error;
    markdown += "\n**Step `" + step_ + "` failed:** " + error + "\n\n";
    failed = true;
  }
}

// ---- the command ----------------------------------------------------------------------

namespace {

int run_tour(const std::string& input_arg, const std::string& out_arg, const CommonOptions& common) {
  const std::string input = input_arg.empty() ? find_sample().string() : input_arg;
  const fs::path out_dir = out_arg.empty() ? fs::path("out") : fs::path(out_arg);
  if (same_file(out_dir.string(), input))
    throw UsageError("the output folder '" + out_dir.string() + "' is the input file");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (!fs::is_directory(out_dir))
    throw Error("cannot create the output folder '" + out_dir.string() + "'" +
                (ec ? ": " + ec.message() : std::string()));

  TourContext tour(input, out_dir, common);
  tour.log("reading " + input);
  Loaded loaded = load_input(input, common);
  tour.soup = std::move(loaded.soup);
  tour.mesh = std::move(loaded.mesh);
  tour.build_report = std::move(loaded.report);
  tour.markdown = "# geom tour of `" + input + "`\n\nEverything geom can do, applied to one mesh. "
                  "Files named here are in this folder; summary.json holds the same figures.\n";

  for (const auto& step : kTourSteps) {
    tour.log(step.name);
    tour.begin_step(step.name);
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    try {
      step.run(tour);
    } catch (const UsageError&) {
      throw;
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "unknown error";
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    tour.end_step(seconds, error);
    if (!error.empty()) std::cerr << "geom: tour step " << step.name << " failed: " << error << '\n';
  }

  const fs::path md = tour.path("summary.md");
  const fs::path js = tour.path("summary.json");
  tour.summary["ok"] = !tour.failed;
  {
    std::ofstream f(md);
    f << tour.markdown;
    if (!f) throw Error("cannot write '" + md.string() + "'");
  }
  {
    std::ofstream f(js);
    f << tour.summary.dump(2) << '\n';
    if (!f) throw Error("cannot write '" + js.string() + "'");
  }

  std::string text = "geom tour of " + input + ": " +
                     std::to_string(tour.summary["files"].size()) + " files in " +
                     out_dir.string() + "/\n";
  for (const auto& [name, step] : tour.summary["steps"].items())
    text += "  " + name + ": " + (step.value("ok", false) ? "ok" : "FAILED") + " (" +
            TourContext::number(std::round(step.value("seconds", 0.0) * 1000.0) / 1000.0) +
            " s)\n";
  text += "summary: " + md.string() + ", " + js.string() + '\n';
  report(common, tour.summary, text);
  return tour.failed ? 1 : 0;
}

}  // namespace

void add_tour_command(CLI::App& app) {
  struct Args {
    std::string input;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "tour",
      "Take a mesh (default: the bundled sample) through everything geom can do; write the "
      "results and summary.md/summary.json into the output folder (default: out/)",
      [args] { return run_tour(args->input, args->common.output, args->common); });
  cmd->add_option("file", args->input, "Mesh file (default: the bundled data/sample.obj)");
  cmd->add_option("-o,--output", args->common.output, "Output folder (default: out)");
  add_common_options(cmd, args->common, kJson | kQuiet | kForce);
}

}  // namespace geom::cli
