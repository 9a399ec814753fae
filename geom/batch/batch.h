#pragma once
/// \file
/// Batch processing: one pipeline applied to many mesh files, each file independently, so the
/// same per-file function serves `geom batch` (threads on one machine) and geom.batch in
/// Python (a process pool, or a Dask cluster whose workers call it with a path).
///
/// Guarantees, per file: the output appears whole or not at all (written to a hidden
/// ".<name>.geom-partial-*" file beside it, then renamed); an existing output is skipped
/// (resume) or replaced (overwrite) only when asked, otherwise the file fails; any error is
/// caught and becomes the record's message. One mesh is in memory per worker; records are
/// handed out as they finish and never collected here.
///
/// This library composes the capabilities (io, lod, subdivision, compress), as the CLI does;
/// no capability depends on it.

#include <geom/batch/pipeline.h>

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace geom::batch {

/// One input file and where its output goes; names are relative to the roots, for reports.
struct Task {
  std::filesystem::path input, output;
  std::string input_name, output_name;
};

enum class ExistingOutput {
  kFail,       ///< the file fails: "output exists"
  kSkip,       ///< --resume: an output at least as new as its input means done
  kOverwrite,  ///< --force
};

struct MeshCounts {
  std::size_t vertices = 0, faces = 0;
};

struct StepTime {
  std::string step;  ///< the step's text: "simplify --ratio 0.25"
  double seconds = 0;
};

/// What happened to one input: one line of the JSON-lines report.
struct Record {
  std::string input, output;      ///< relative names (Task::input_name, output_name)
  std::string status;             ///< "ok", "failed" or "skipped"
  MeshCounts before, after;       ///< after: of the mesh written (or compressed)
  std::size_t repairs = 0;        ///< changes build() made when reading the input
  std::size_t output_bytes = 0;
  std::vector<StepTime> steps;    ///< "read" first, "write" last
  double seconds = 0;
  std::string error;              ///< for "failed": the message, naming file/line/element
  /// What reading skipped (PolygonSoup::warnings), a step did not carry or the output
  /// format cannot hold.
  std::vector<std::string> warnings;

  /// One JSON object on one line (no newline); timings under "seconds" and "steps".
  std::string to_json() const;
};

/// Extensions geom reads (".obj", ".ply", ".off", ".stl", ".drc", ".gltf", ".glb").
const std::vector<std::string>& mesh_extensions();

/// Mesh files under `dir`, recursively, by extension (case-insensitive), sorted by path;
/// anything under `exclude` (the output folder, when it lies inside) is left out, and so are
/// hidden files (names starting with '.').
/// Throws: Error when `dir` is not a readable folder.
std::vector<std::filesystem::path> find_meshes(const std::filesystem::path& dir,
                                               const std::filesystem::path& exclude = {});

/// Tasks for `inputs` (files under `in_root`): each output keeps the input's path relative to
/// in_root, under out_root, with the pipeline's output extension. When two inputs would
/// write one output ("a.obj" and "a.ply" converted to ply), both keep their input extension
/// in the name ("a.obj.ply", "a.ply.ply").
/// Throws: InvalidArgument when an input is not under in_root, or out_root equals in_root.
std::vector<Task> plan(const Pipeline& pipeline, const std::filesystem::path& in_root,
                       std::span<const std::filesystem::path> inputs,
                       const std::filesystem::path& out_root);

/// Run the pipeline on one file. Never throws for a bad input: the record says "failed".
Record process(const Pipeline& pipeline, const Task& task,
               ExistingOutput existing = ExistingOutput::kFail);

/// Delete "*.geom-partial-*" files under `out_root` that an interrupted (killed) run left.
/// Returns how many were removed.
std::size_t remove_partial_outputs(const std::filesystem::path& out_root);

struct RunOptions {
  unsigned jobs = 0;  ///< worker threads; 0: all cores
  ExistingOutput existing = ExistingOutput::kFail;
  /// Set from another thread (a signal handler) to stop starting new files; the files in
  /// flight finish, so nothing is left half-written.
  const std::atomic<bool>* stop = nullptr;
};

struct Summary {
  std::size_t total = 0, ok = 0, failed = 0, skipped = 0;
  std::size_t faces_in = 0, faces_out = 0;  ///< over processed ("ok") files
  double seconds = 0;                       ///< wall time of the run
  bool interrupted = false;                 ///< stopped before every task ran
};

/// Process `tasks` on `jobs` threads, one file per thread at a time, calling `on_record`
/// (serialised, in completion order) for each.
Summary run(const Pipeline& pipeline, std::span<const Task> tasks, const RunOptions& options,
            const std::function<void(const Record&)>& on_record);

}  // namespace geom::batch
