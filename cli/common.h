#pragma once
/// \file
/// Helpers every `geom` subcommand uses, so that options, errors, progress and output files
/// behave the same way everywhere. See cli/commands.h for the pattern.

#include <Eigen/Geometry>  // topology.h's AlignedBox3d

#include <geom/core/build.h>
#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>
#include <geom/core/topology.h>
#include <geom/io/io.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace geom::cli {

/// A mistake in how the command was called (exit 2), as opposed to bad input (exit 1).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Options shared by all subcommands; each subcommand adds the ones it uses.
struct CommonOptions {
  std::string output;  ///< -o/--output
  bool json = false;   ///< --json: one JSON document on stdout instead of text
  bool quiet = false;  ///< --quiet: no text output and no progress (errors still go to stderr)
  bool force = false;  ///< --force: allow an output to overwrite an input
  /// --format: output format when it cannot come from the name (stdout "-").
  std::optional<FileFormat> output_format;
};

enum CommonFlags : unsigned {
  kOutput = 1u << 0,
  kJson = 1u << 1,
  kQuiet = 1u << 2,
  kForce = 1u << 3,
  kFormat = 1u << 4,
};

/// Adds the selected shared options (-o/--output, --json, --quiet, --force, --format).
void add_common_options(CLI::App* cmd, CommonOptions& options, unsigned flags);

/// Registers subcommand `name`. `run` is called after a successful parse; its return value is
/// the process's exit code.
CLI::App* add_command(CLI::App& app, const std::string& name, const std::string& description,
                      std::function<int()> run);

/// Thrown by the runner wrapper to carry a non-zero exit code out of CLI11's parse().
struct ExitCode {
  int code;
};

/// A one-line progress bar on stderr; silent when stderr is not a terminal or when disabled.
class Progress {
 public:
  Progress(std::string label, bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// fraction in [0, 1]; stage is a short word shown after the bar ("reading", "building").
  void update(double fraction, const std::string& stage = {});
  /// A callback for library functions that take a progress function (return false cancels).
  std::function<bool(double)> callback();
  void finish();

 private:
  std::string label_;
  bool enabled_;
  int last_permille_ = -1;
  std::string last_stage_;
  std::chrono::steady_clock::time_point last_draw_{};
};

/// Reads a mesh file as given ("-" reads stdin and judges the format by content).
/// Throws: ParseError, Error.
PolygonSoup read_input(const std::string& path, const CommonOptions& common);

struct Loaded {
  PolygonSoup soup;  ///< the input as given
  SurfaceMesh mesh;  ///< built from it
  BuildReport report;
};
/// read_input + build, with a progress bar. What the build changed is printed on stderr as
/// warnings (unless --quiet), except where the command prints the report itself
/// (report_changes = false).
Loaded load_input(const std::string& path, const CommonOptions& common,
                  const BuildOptions& build_options = {}, bool report_changes = true);

/// True when `output` names the same file as one of `inputs` (existing files compared by
/// identity, others by normalised path). "-" never collides.
bool same_file(const std::string& output, const std::string& input);
/// Throws UsageError when `output` would overwrite one of `inputs` and --force was not given.
void check_not_input(const std::string& output, const std::vector<std::string>& inputs,
                     const CommonOptions& common);
/// Throws UsageError naming `option` and `path` unless `path` ends in one of `extensions`
/// (lower case, with the dot; compared case-insensitively), so that a PNG is never written
/// to "x.obj". Mesh-only outputs need not call it: write_output refuses an unknown extension.
void require_extension(const std::string& path, std::initializer_list<std::string_view> extensions,
                       const std::string& option);

/// What `geom repair` does with its default flags (weld exact duplicates, orient, drop
/// unreferenced vertices); `geom info` previews exactly this and `convert --repair` applies it.
BuildOptions repair_defaults();

/// Writes `mesh` to `path` (or common.output when path is empty) after check_not_input.
/// Throws: UsageError (no output given, or it is an input), Error (cannot write).
void write_output(const SurfaceMesh& mesh, const std::vector<std::string>& inputs,
                  const CommonOptions& common, WriteOptions write = {},
                  const std::string& path = {});
/// The same for a soup (what a mesh cannot hold, e.g. a non-manifold vertex).
void write_output(const PolygonSoup& soup, const std::vector<std::string>& inputs,
                  const CommonOptions& common, WriteOptions write = {},
                  const std::string& path = {});

/// Prints "geom <command>: warning: <what>: a, b" on stderr (unless --quiet) when `names`
/// (properties, as missing_properties() gives them) is not empty.
void warn_not_carried(const std::string& command, const std::vector<std::string>& names,
                      const CommonOptions& common,
                      const std::string& what = "not carried to the output");

/// Prints `j` (with --json) or `text` (otherwise) on stdout, nothing with --quiet unless --json.
void report(const CommonOptions& common, const nlohmann::json& j, const std::string& text);

/// JSON forms of the core reports; keys are the C++ field names.
nlohmann::json to_json(const TopologyReport& report);
nlohmann::json to_json(const BuildReport& report);
/// Human-readable forms.
std::string to_text(const TopologyReport& report);
std::string to_text(const BuildReport& report);

/// Parses a format name ("obj", "ply", …). Throws UsageError.
FileFormat parse_format(const std::string& name);

}  // namespace geom::cli
