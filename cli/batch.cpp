// geom batch IN_DIR OUT_DIR --pipeline P.json: one pipeline over a folder of meshes.

#include "commands.h"
#include "common.h"

#include <geom/batch/batch.h>

#include <atomic>
#include <csignal>
#include <fstream>
#include <memory>

namespace geom::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void request_stop(int) { g_stop = true; }

// Ctrl-C or `kill` lets the files in flight finish (their outputs appear whole), starts no
// new one, and still writes the summary.
class StopOnSignal {
 public:
  StopOnSignal() : int_(std::signal(SIGINT, request_stop)), term_(std::signal(SIGTERM, request_stop)) {}
  ~StopOnSignal() {
    std::signal(SIGINT, int_);
    std::signal(SIGTERM, term_);
  }

 private:
  void (*int_)(int);
  void (*term_)(int);
};

nlohmann::json summary_json(const batch::Summary& s, std::size_t removed_partials) {
  const double per_s = s.seconds > 0 ? 1.0 / s.seconds : 0.0;
  return {{"files", s.total},
          {"ok", s.ok},
          {"failed", s.failed},
          {"skipped", s.skipped},
          {"interrupted", s.interrupted},
          {"seconds", s.seconds},
          {"meshes_per_second", static_cast<double>(s.ok) * per_s},
          {"faces_in", s.faces_in},
          {"faces_out", s.faces_out},
          {"faces_per_second", static_cast<double>(s.faces_in) * per_s},
          {"removed_partial_outputs", removed_partials}};
}

}  // namespace

void add_batch_command(CLI::App& app) {
  struct Args {
    std::string in_dir, out_dir, pipeline, report;
    std::vector<std::string> steps;
    unsigned jobs = 0;
    bool resume = false;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "batch",
      "Apply a pipeline of steps (validate, repair, simplify, subdivide, compress, convert) to "
      "every mesh under a folder, in parallel, with a JSON-lines report",
      [args] {
        if (args->pipeline.empty() == args->steps.empty())
          throw UsageError("give --pipeline P.json or one or more --step, not both");
        if (args->resume && args->common.force) throw UsageError("give --resume or --force, not both");
        if (!args->report.empty()) require_extension(args->report, {".jsonl"}, "--report");
        const batch::Pipeline pipeline = args->pipeline.empty()
                                             ? batch::parse_steps(args->steps)
                                             : batch::load_pipeline(args->pipeline);
        const auto inputs = batch::find_meshes(args->in_dir, args->out_dir);
        const auto tasks = batch::plan(pipeline, args->in_dir, inputs, args->out_dir);
        std::filesystem::create_directories(args->out_dir);
        const std::size_t removed = batch::remove_partial_outputs(args->out_dir);
        const std::string report_path = args->report.empty()
            ? (std::filesystem::path(args->out_dir) / "batch-report.jsonl").string() : args->report;
        std::ofstream report_file(report_path);
        if (!report_file) throw Error(report_path + ": cannot write the report");

        batch::RunOptions options;
        options.jobs = args->jobs;
        options.existing = args->resume ? batch::ExistingOutput::kSkip
                           : args->common.force ? batch::ExistingOutput::kOverwrite
                                                : batch::ExistingOutput::kFail;
        options.stop = &g_stop;
        g_stop = false;
        Progress progress("batch", !args->common.quiet && !args->common.json);
        std::size_t done = 0;
        const StopOnSignal on_signal;
        const batch::Summary s = batch::run(pipeline, tasks, options, [&](const batch::Record& r) {
          report_file << r.to_json() << '\n' << std::flush;
          if (r.status == "failed" && !args->common.quiet && !args->common.json)
            std::cerr << "geom batch: " << r.input << ": " << r.error << '\n';
          progress.update(static_cast<double>(++done) / static_cast<double>(tasks.size()), r.input);
        });
        progress.finish();
        nlohmann::json j = summary_json(s, removed);
        report_file << nlohmann::json{{"summary", j}}.dump() << '\n';
        j["report"] = report_path;
        j["pipeline"] = nlohmann::json::parse(pipeline.to_json())["steps"];
        report(args->common, j,
               std::to_string(s.total) + " files: " + std::to_string(s.ok) + " ok, " +
                   std::to_string(s.failed) + " failed, " + std::to_string(s.skipped) +
                   " skipped in " + std::to_string(s.seconds) + " s" +
                   (s.interrupted ? " (interrupted)" : "") + "\nreport: " + report_path + "\n");
        return s.interrupted ? 130 : s.failed ? 1 : 0;
      });
  cmd->add_option("in_dir", args->in_dir, "Folder of meshes (searched recursively by extension)")
      ->required();
  cmd->add_option("out_dir", args->out_dir, "Folder for the outputs (same relative paths)")
      ->required();
  cmd->add_option("--pipeline", args->pipeline,
                  "JSON file: {\"steps\": [\"repair\", \"simplify --ratio 0.25\", ...]} "
                  "(geom/batch/PIPELINE.md)");
  cmd->add_option("--step", args->steps,
                  "A step as on the command line, e.g. --step \"simplify --ratio 0.25\" "
                  "(repeat, in order; instead of --pipeline)");
  cmd->add_option("--jobs,-j", args->jobs, "Files processed at once (default: all cores)");
  cmd->add_flag("--resume", args->resume, "Skip files whose output exists and is newer than the input");
  cmd->add_option("--report", args->report,
                  "JSON-lines report, a .jsonl file (default OUT_DIR/batch-report.jsonl)");
  cmd->add_flag("--force", args->common.force, "Replace outputs that already exist");
  add_common_options(cmd, args->common, kJson | kQuiet);
}

}  // namespace geom::cli
