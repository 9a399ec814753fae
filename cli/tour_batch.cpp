// Tour step "batch": the toured mesh in five formats plus one broken file, through one
// pipeline, as `geom batch` runs it — every good file done, the bad one reported.

#include "tour.h"

#include <geom/batch/batch.h>

#include <fstream>

namespace geom::cli {

void tour_batch(TourContext& tour) {
  tour.heading("Batch processing");
  const std::vector<std::string> steps = {"repair", "simplify --ratio 0.5", "compress --bits 12"};
  tour.text("`geom batch IN_DIR OUT_DIR --step repair --step \"simplify --ratio 0.5\" --step "
            "\"compress --bits 12\"`: the sample in five formats and one broken file, processed "
            "in parallel. Outputs are written whole or not at all, and the report has one JSON "
            "line per input.");
  const auto in = tour.path("batch_in"), out = tour.path("batch_out");
  std::filesystem::remove_all(in);
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(in / "formats");
  for (const char* ext : {".obj", ".ply", ".off", ".stl", ".glb"})
    save_mesh(tour.mesh, in / "formats" / (tour.stem + ext));
  std::ofstream(in / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 3\n";

  const batch::Pipeline pipeline = batch::parse_steps(steps);
  const auto tasks = batch::plan(pipeline, in, batch::find_meshes(in), out);
  std::ofstream report(tour.path("batch_report.jsonl"));
  std::vector<std::vector<std::string>> rows;
  const batch::Summary s = batch::run(pipeline, tasks, {}, [&](const batch::Record& r) {
    report << r.to_json() << '\n';
    rows.push_back({r.input, r.status, r.status == "ok" ? std::to_string(r.before.faces) : "",
                    r.status == "ok" ? std::to_string(r.after.faces) : "",
                    r.status == "ok" ? std::to_string(r.output_bytes) : r.error});
  });
  std::sort(rows.begin(), rows.end());
  tour.grid({"input", "status", "faces before", "faces after", "bytes / error"}, rows);
  tour.add_file(tour.path("batch_report.jsonl"), "the batch run's JSON-lines report");
  tour.table({{"files", std::to_string(s.total)},
              {"ok", std::to_string(s.ok)},
              {"failed", std::to_string(s.failed)},
              {"seconds", TourContext::number(s.seconds)}});
  tour.record({{"files", s.total}, {"ok", s.ok}, {"failed", s.failed}, {"seconds", s.seconds}});
  if (s.ok + 1 != s.total) throw Error("batch: expected every file but the broken one to succeed");
}

}  // namespace geom::cli
