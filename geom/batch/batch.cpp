#include <geom/batch/batch.h>

#include <geom/core/errors.h>
#include <geom/core/soup.h>
#include <geom/core/validate.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <utility>
#include <unistd.h>

namespace geom::batch {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kPartialMarker = ".geom-partial-";

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The temporary sits beside the output so the rename stays within one file system (atomic).
// pid and a counter keep concurrent writers (threads, Dask worker processes) apart.
void write_atomically(const fs::path& path, std::span<const std::byte> bytes) {
  static std::atomic<unsigned> counter{0};
  fs::create_directories(path.parent_path());
  const fs::path temp = path.parent_path() / ("." + path.filename().string() + kPartialMarker +
                                              std::to_string(::getpid()) + "-" +
                                              std::to_string(counter++));
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f) throw Error(path.string() + ": cannot write: " + std::strerror(errno));
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (std::fclose(f) != 0 || !written) {
    fs::remove(temp);
    throw Error(path.string() + ": cannot write (disk full?)");
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp);
    throw Error(path.string() + ": cannot rename into place: " + ec.message());
  }
}

bool up_to_date(const Task& t) {
  std::error_code ec;
  const auto out = fs::last_write_time(t.output, ec);
  if (ec) return false;
  return out >= fs::last_write_time(t.input, ec) && !ec;
}

MeshCounts counts(const SurfaceMesh& m) { return {m.n_vertices(), m.n_faces()}; }

// The mesh flowing through the steps, and what the last step decided about the output.
struct State {
  // The input as read; kept while a first "validate" needs it, and written as it is when
  // every step is a conversion (no half-edge mesh is built: nothing is repaired).
  PolygonSoup soup;
  bool soup_only = false;
  SurfaceMesh mesh;
  // The source vertex of each mesh vertex while the mesh is the one read and reading split
  // non-manifold vertices apart (a compress step records them, as geom compress does);
  // empty once a step changes the mesh.
  std::vector<std::uint32_t> origin;
  // After a simplify of split input, the source vertex of each mesh vertex: the copies of
  // one are joined again when writing (cleared by any later step that changes the mesh).
  std::vector<std::uint32_t> join_origin;
  // The input's material files (OBJ mtllib): a mesh keeps its faces' material names only.
  std::vector<std::string> material_libraries;
  std::vector<std::uint8_t> compressed;  // set by a compress step
  bool is_compressed = false;
  WriteOptions write;
};

void apply(const Step& step, bool first, State& s, Record& r) {
  if (!std::holds_alternative<ValidateStep>(step.options) && !std::holds_alternative<ConvertStep>(step.options))
    s.join_origin.clear();
  std::visit(
      [&](const auto& o) {
        using T = std::decay_t<decltype(o)>;
        if constexpr (std::is_same_v<T, ValidateStep>) {
          const RequirementCheck c = check_requirements(first ? s.soup : to_soup(s.mesh),
                                                        {o.manifold, o.closed, o.oriented});
          if (!c.failures.empty()) {
            std::string why;
            for (const auto& f : c.failures) why += (why.empty() ? "" : "; ") + f;
            throw Error("validate: " + why);
          }
        } else if constexpr (std::is_same_v<T, RepairStep>) {
          if (!first) s.mesh = build(to_soup(s.mesh), o.options).mesh, s.origin.clear();  // first: done on read
        } else if constexpr (std::is_same_v<T, SimplifyStep>) {
          SimplifyOptions options = o.options;
          if (!s.origin.empty()) {  // split non-manifold vertices stay, to be joined again
            const std::vector<Vertex> copies = split_copies(s.origin);
            options.locked.insert(options.locked.end(), copies.begin(), copies.end());
          }
          SimplifyResult result = simplify(s.mesh, options);
          if (!s.origin.empty())
            for (Vertex v : result.vertex_origin) s.join_origin.push_back(s.origin[v.idx()]);
          if (!result.dropped_properties.empty()) {
            std::string names;
            for (const std::string& n : result.dropped_properties) names += (names.empty() ? "" : ", ") + n;
            r.warnings.push_back("simplify: not carried to the output: " + names);
          }
          s.mesh = std::move(result.mesh);
          s.origin.clear();
        } else if constexpr (std::is_same_v<T, SubdivideStep>) {
          if (s.soup_only) {
            SoupSubdivideResult result = subdivide(s.soup, o.options);
            if (result.opened_edges > 0)
              r.warnings.push_back("subdivide: " + std::to_string(result.opened_edges) +
                                   " smooth edges had to be opened to split non-manifold input; "
                                   "next to them the result differs from OpenSubdiv's");
            s.soup = std::move(result.soup);
          } else {
            s.mesh = subdivide(s.mesh, o.options).mesh;
          }
          s.origin.clear();
        } else if constexpr (std::is_same_v<T, CompressStep>) {
          CompressOptions options = o.options;
          options.vertex_origin = s.origin;
          s.compressed = compress(s.mesh, options).bytes;
          s.is_compressed = true;
        } else if constexpr (std::is_same_v<T, ConvertStep>) {
          s.write.format = o.format;
          s.write.binary = !o.ascii;
        }
      },
      step.options);
}

// Reading builds the mesh with the first step's repair options when it is a repair, so that
// step costs no second build; otherwise with build()'s defaults (which drop what cannot be
// a mesh and report it, as every reader of geom does).
void read(const Pipeline& p, const Task& task, State& s, Record& r) {
  s.soup = read_soup(task.input);
  r.before = {s.soup.positions.size(), s.soup.n_faces()};
  r.warnings = s.soup.warnings;
  s.material_libraries = s.soup.material_libraries;
  s.write.format = format_from_path(task.input);  // kept unless a convert step changes it
  // Conversions and subdivision take the soup as given: no half-edge mesh is built (the
  // subdivision splits and joins non-manifold input itself).
  s.soup_only = std::all_of(p.steps.begin(), p.steps.end(), [](const Step& step) {
    return std::holds_alternative<ConvertStep>(step.options) ||
           std::holds_alternative<SubdivideStep>(step.options);
  });
  if (s.soup_only) return;
  const auto* repair = std::get_if<RepairStep>(&p.steps.front().options);
  BuildResult built = build(s.soup, repair ? repair->options : BuildOptions{});
  s.mesh = std::move(built.mesh);
  const BuildReport& b = built.report;
  r.repairs = b.welded_vertices + b.dropped_out_of_range + b.dropped_degenerate +
              b.dropped_duplicate + b.split_nonmanifold_edges + b.split_nonmanifold_vertices +
              b.flipped_faces + b.collapsed_corners + b.cut_edges + b.detached_faces +
              b.dropped_unreferenced;
  // (A pipeline that starts with a repair asked for the split mesh.)
  if (!repair && b.split_apart()) s.origin = b.vertex_origin;
  if (!std::holds_alternative<ValidateStep>(p.steps.front().options)) s.soup = {};
}

void write(const Task& task, State& s, Record& r) {
  r.after = s.soup_only ? MeshCounts{s.soup.positions.size(), s.soup.n_faces()} : counts(s.mesh);
  std::vector<std::byte> file;
  if (!s.is_compressed) {
    PolygonSoup out = s.soup_only ? std::move(s.soup) : to_soup(s.mesh);
    if (!s.join_origin.empty()) {
      std::unordered_map<std::uint32_t, std::uint32_t> first;
      std::vector<std::uint32_t> same(out.positions.size());
      for (std::uint32_t v = 0; v < same.size(); ++v) same[v] = first.try_emplace(s.join_origin[v], v).first->second;
      join_vertices(out, same);
      r.after.vertices = out.positions.size();
    }
    if (!out.face_materials.empty() && out.material_libraries.empty()) out.material_libraries = s.material_libraries;
    file = write_soup(out, *s.write.format, s.write);
    for (std::string& line : unstored(out, *s.write.format, s.write)) r.warnings.push_back(std::move(line));
  }
  const auto bytes = s.is_compressed ? std::as_bytes(std::span(s.compressed)) : std::span(std::as_const(file));
  write_atomically(task.output, bytes);
  r.output_bytes = bytes.size();
}

template <class F>
void timed(Record& r, const std::string& name, F&& f) {
  const auto t0 = Clock::now();
  f();
  r.steps.push_back({name, seconds_since(t0)});
}

}  // namespace

std::string Record::to_json() const {
  nlohmann::json j = {{"input", input}, {"output", output}, {"status", status}};
  if (status == "ok") {
    j["before"] = {{"vertices", before.vertices}, {"faces", before.faces}};
    j["after"] = {{"vertices", after.vertices}, {"faces", after.faces}};
    j["repairs"] = repairs;
    j["bytes"] = output_bytes;
  }
  if (!error.empty()) j["error"] = error;
  if (!warnings.empty()) j["warnings"] = warnings;
  j["steps"] = nlohmann::json::array();
  for (const auto& s : steps) j["steps"].push_back({{"step", s.step}, {"seconds", s.seconds}});
  j["seconds"] = seconds;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

const std::vector<std::string>& mesh_extensions() {
  static const std::vector<std::string> exts = {".obj", ".ply",  ".off", ".stl",
                                                ".drc", ".gltf", ".glb"};
  return exts;
}

std::vector<fs::path> find_meshes(const fs::path& dir, const fs::path& exclude) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(dir.string() + ": not a folder");
  const fs::path skip = exclude.empty() ? fs::path() : fs::weakly_canonical(exclude);
  std::vector<fs::path> found;
  const auto& exts = mesh_extensions();
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    const fs::path& p = it->path();
    const bool hidden = p.filename().string().starts_with(".");
    if (it->is_directory() && (hidden || (!skip.empty() && fs::weakly_canonical(p) == skip))) {
      it.disable_recursion_pending();
      continue;
    }
    if (hidden || !it->is_regular_file()) continue;
    if (std::find(exts.begin(), exts.end(), lower(p.extension().string())) != exts.end())
      found.push_back(p);
  }
  if (ec) throw Error(dir.string() + ": cannot list: " + ec.message());
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<Task> plan(const Pipeline& pipeline, const fs::path& in_root,
                       std::span<const fs::path> inputs, const fs::path& out_root) {
  if (fs::weakly_canonical(in_root) == fs::weakly_canonical(out_root))
    throw InvalidArgument(out_root.string() + ": the output folder is the input folder");
  // Lexical, not canonical: an input that is a symbolic link keeps its place in the tree.
  const fs::path in = fs::absolute(in_root).lexically_normal();
  const fs::path out = fs::absolute(out_root).lexically_normal();
  std::vector<Task> tasks;
  std::map<fs::path, int> uses;
  for (const fs::path& input : inputs) {
    const fs::path rel = fs::absolute(input).lexically_normal().lexically_relative(in);
    if (rel.empty() || *rel.begin() == "..")
      throw InvalidArgument(input.string() + ": not under " + in_root.string());
    fs::path out_rel = rel;
    out_rel.replace_extension(pipeline.output_extension(lower(rel.extension().string())));
    tasks.push_back({input, out / out_rel, rel.generic_string(), out_rel.generic_string()});
    ++uses[out_rel];
  }
  for (Task& t : tasks) {
    if (uses[fs::path(t.output_name)] < 2) continue;
    const fs::path rel(t.input_name);
    fs::path out_rel = rel;
    out_rel += pipeline.output_extension(lower(rel.extension().string()));
    t.output = out / out_rel;
    t.output_name = out_rel.generic_string();
  }
  return tasks;
}

Record process(const Pipeline& pipeline, const Task& task, ExistingOutput existing) {
  Record r;
  r.input = task.input_name;
  r.output = task.output_name;
  const auto t0 = Clock::now();
  try {
    std::error_code ec;
    if (fs::exists(task.output, ec)) {
      if (existing == ExistingOutput::kSkip && up_to_date(task)) {
        r.status = "skipped";
        return r;
      }
      if (existing == ExistingOutput::kFail)
        throw Error(task.output.string() + ": output exists (resume or overwrite to reuse it)");
    }
    if (pipeline.steps.empty()) throw InvalidArgument("the pipeline has no steps");
    State s;
    timed(r, "read", [&] { read(pipeline, task, s, r); });
    for (std::size_t i = 0; i < pipeline.steps.size(); ++i)
      timed(r, pipeline.steps[i].text, [&] { apply(pipeline.steps[i], i == 0, s, r); });
    timed(r, "write", [&] { write(task, s, r); });
    r.status = "ok";
  } catch (const std::bad_alloc&) {
    r.status = "failed";
    r.error = task.input.string() + ": out of memory";
  } catch (const std::exception& e) {
    r.status = "failed";
    r.error = e.what();
  }
  r.seconds = seconds_since(t0);
  return r;
}

std::size_t remove_partial_outputs(const fs::path& out_root) {
  std::error_code ec;
  if (!fs::is_directory(out_root, ec)) return 0;
  std::vector<fs::path> partial;
  for (auto it = fs::recursive_directory_iterator(out_root, ec); !ec && it != fs::end(it);
       it.increment(ec))
    if (it->is_regular_file() && it->path().filename().string().find(kPartialMarker) != std::string::npos)
      partial.push_back(it->path());
  for (const auto& p : partial) fs::remove(p, ec);
  return partial.size();
}

Summary run(const Pipeline& pipeline, std::span<const Task> tasks, const RunOptions& options,
            const std::function<void(const Record&)>& on_record) {
  const auto t0 = Clock::now();
  Summary summary;
  summary.total = tasks.size();
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  auto worker = [&] {
    for (;;) {
      if (options.stop && options.stop->load()) return;
      const std::size_t i = next++;
      if (i >= tasks.size()) return;
      const Record r = process(pipeline, tasks[i], options.existing);
      const std::lock_guard lock(mutex);
      if (r.status == "ok") {
        ++summary.ok;
        summary.faces_in += r.before.faces;
        summary.faces_out += r.after.faces;
      }
      summary.failed += r.status == "failed";
      summary.skipped += r.status == "skipped";
      if (on_record) on_record(r);
    }
  };
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const unsigned jobs = std::min<std::size_t>(options.jobs ? options.jobs : hw,
                                              std::max<std::size_t>(tasks.size(), 1));
  std::vector<std::jthread> threads;
  for (unsigned j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  threads.clear();  // joins
  summary.seconds = seconds_since(t0);
  summary.interrupted = summary.ok + summary.failed + summary.skipped < summary.total;
  return summary;
}

}  // namespace geom::batch
