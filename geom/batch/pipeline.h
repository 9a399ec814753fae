#pragma once
/// \file
/// A batch pipeline: the steps applied to every mesh of a batch run, written with the `geom`
/// subcommands' own names and option names, so a step means the same thing in a pipeline as
/// on the command line. The JSON form is specified in geom/batch/PIPELINE.md:
///
///     {"steps": ["repair --weld 1e-6", "simplify --ratio 0.25", "compress --bits 12"]}
///
/// A step is a string (the command line of that subcommand without its files) or an object
/// {"simplify": {"ratio": 0.25, "keep-boundary": true}}; both parse to the same Step.

#include <geom/compress/container/codec.h>
#include <geom/core/build.h>
#include <geom/io/io.h>
#include <geom/lod/simplify.h>
#include <geom/subdivision/subdivision.h>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace geom::batch {

/// `validate [--manifold] [--closed] [--oriented] [--all]`: the file fails unless the mesh
/// at this point (the input as read, when it is the first step) builds into a valid mesh and
/// has the asked properties, as `geom validate` decides.
struct ValidateStep {
  bool manifold = false, closed = false, oriented = false;
};
/// `repair [--weld TOL] [--keep-unreferenced] [--no-orient]`, as `geom repair`.
struct RepairStep {
  BuildOptions options;
};
/// `simplify (--ratio R | --faces N | --max-error E) [--keep-boundary] [--boundary-weight W]
/// [--min-quality Q]`, as `geom simplify`.
struct SimplifyStep {
  SimplifyOptions options;
};
/// `subdivide [--scheme catmull-clark|loop] [--levels N] [--boundary none|edges|corners]
/// [--crease-method uniform|chaikin] [--limit] [--crease-angle DEG]`, as `geom subdivide`.
struct SubdivideStep {
  SubdivideOptions options;
};
/// `compress [--bits B | --precision P] [--level L] [--preserve-order]`, as `geom compress`;
/// last step only: the output is a .gmc stream.
struct CompressStep {
  CompressOptions options;
};
/// `convert --format obj|ply|off|stl|drc|gltf|glb [--ascii]`: last step only; the format of
/// the output files (without it they keep their input's format).
struct ConvertStep {
  FileFormat format = FileFormat::kPly;
  bool ascii = false;
};

using StepOptions =
    std::variant<ValidateStep, RepairStep, SimplifyStep, SubdivideStep, CompressStep, ConvertStep>;

struct Step {
  std::string name;  ///< the subcommand: "simplify"
  std::string text;  ///< the step as written, normalised to command-line form, for reports
  StepOptions options;
};

struct Pipeline {
  std::vector<Step> steps;

  /// Extension of the output for an input with extension `input_ext` (".obj"): ".gmc" after
  /// compress, the convert step's format, else the input's own.
  std::string output_extension(const std::string& input_ext) const;
  /// The pipeline in its canonical JSON form (string steps), as parse_pipeline reads it.
  std::string to_json() const;
};

/// Parse the JSON form. `source` names the text in messages (a file name).
/// Throws: InvalidArgument naming the source, the step number and the option for malformed
/// JSON, an unknown step or option, a missing or out-of-range value, or compress/convert
/// anywhere but last.
Pipeline parse_pipeline(std::string_view json, const std::string& source = "pipeline");
/// Parse steps given one per string in command-line form ("simplify --ratio 0.25").
/// Throws: as parse_pipeline.
Pipeline parse_steps(const std::vector<std::string>& steps, const std::string& source = "--step");
/// Read and parse a pipeline file. Throws: Error when unreadable; as parse_pipeline.
Pipeline load_pipeline(const std::filesystem::path& path);

}  // namespace geom::batch
