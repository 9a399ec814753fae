// Pipeline parsing. Both JSON step forms become a list of command-line tokens first, so there
// is one place that knows each step's options, and its messages use the CLI's option names.

#include <geom/batch/pipeline.h>

#include <geom/core/errors.h>

#include <nlohmann/json.hpp>

#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

namespace geom::batch {
namespace {

using Json = nlohmann::json;

std::vector<std::string> split_words(std::string_view text) {
  std::vector<std::string> words;
  std::istringstream in{std::string(text)};
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// A step's options as "--name [value]" tokens, read once each; finish() rejects leftovers.
class OptionReader {
 public:
  OptionReader(const std::vector<std::string>& tokens, std::string where)
      : where_(std::move(where)) {
    for (std::size_t i = 0; i < tokens.size(); ++i) {
      const std::string& t = tokens[i];
      if (!t.starts_with("--") || t.size() == 2) fail("expected an option, found '" + t + "'");
      const bool has_value = i + 1 < tokens.size() && !tokens[i + 1].starts_with("--");
      if (!options_.emplace(t, has_value ? std::optional(tokens[++i]) : std::nullopt).second)
        fail("option " + t + " given twice");
    }
  }

  bool flag(const std::string& name) {
    known_.push_back(name);
    auto it = options_.find(name);
    if (it == options_.end()) return false;
    if (it->second) fail(name + " takes no value (found '" + *it->second + "')");
    options_.erase(it);
    return true;
  }

  std::optional<double> number(const std::string& name, double lo, double hi) {
    const auto text = value(name);
    if (!text) return std::nullopt;
    double v = 0;
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), v);
    if (ec != std::errc() || end != text->data() + text->size())
      fail(name + " needs a number, found '" + *text + "'");
    if (!(v >= lo && v <= hi))
      fail(name + " " + *text + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]");
    return v;
  }

  std::optional<long long> integer(const std::string& name, long long lo, long long hi) {
    const auto v = number(name, static_cast<double>(lo), static_cast<double>(hi));
    if (v && *v != static_cast<double>(static_cast<long long>(*v)))
      fail(name + " needs a whole number, found " + fmt(*v));
    return v ? std::optional(static_cast<long long>(*v)) : std::nullopt;
  }

  std::optional<std::string> word(const std::string& name, const std::vector<std::string>& allowed) {
    const auto text = value(name);
    if (!text) return std::nullopt;
    for (const auto& a : allowed)
      if (*text == a) return text;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(name + " '" + *text + "' is not one of: " + list);
  }

  void finish() const {
    if (options_.empty()) return;
    std::string known;
    for (const auto& k : known_) known += (known.empty() ? "" : " ") + k;
    fail("unknown option " + options_.begin()->first +
         (known.empty() ? " (this step takes none)" : " (known: " + known + ")"));
  }

  [[noreturn]] void fail(const std::string& what) const { throw InvalidArgument(where_ + ": " + what); }

 private:
  std::optional<std::string> value(const std::string& name) {
    known_.push_back(name);
    auto it = options_.find(name);
    if (it == options_.end()) return std::nullopt;
    if (!it->second) fail(name + " needs a value");
    std::string v = *it->second;
    options_.erase(it);
    return v;
  }
  static std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

  std::string where_;
  std::map<std::string, std::optional<std::string>> options_;
  std::vector<std::string> known_;
};

StepOptions read_validate(OptionReader& r) {
  ValidateStep s;
  const bool all = r.flag("--all");
  s.manifold = r.flag("--manifold") || all;
  s.closed = r.flag("--closed") || all;
  s.oriented = r.flag("--oriented") || all;
  return s;
}

StepOptions read_repair(OptionReader& r) {
  RepairStep s;
  s.options.weld_tolerance = r.number("--weld", -1.0, 1.0).value_or(0.0);
  s.options.drop_unreferenced = !r.flag("--keep-unreferenced");
  s.options.orient = !r.flag("--no-orient");
  return s;
}

StepOptions read_simplify(OptionReader& r) {
  SimplifyStep s;
  const auto ratio = r.number("--ratio", 0.0, 1.0);
  const auto faces = r.integer("--faces", 0, 1LL << 40);
  const auto max_error = r.number("--max-error", 0.0, 1e300);
  s.options.lock_boundary = r.flag("--keep-boundary");
  if (auto w = r.number("--boundary-weight", 0.0, 1e12)) s.options.boundary_weight = *w;
  if (auto q = r.number("--min-quality", 0.0, 1.0)) s.options.min_triangle_quality = *q;
  r.finish();  // a misspelt option is named before the checks below
  if (!ratio && !faces && !max_error) r.fail("give --ratio R, --faces N or --max-error E");
  if (ratio && faces) r.fail("give --ratio or --faces, not both");
  s.options.ratio = ratio.value_or(faces || max_error ? 0.0 : 0.5);
  s.options.target_faces = static_cast<std::size_t>(faces.value_or(0));
  if (max_error) s.options.max_error = *max_error;
  return s;
}

StepOptions read_subdivide(OptionReader& r) {
  SubdivideStep s;
  if (r.word("--scheme", {"catmull-clark", "loop"}).value_or("catmull-clark") == "loop")
    s.options.scheme = SubdivisionScheme::kLoop;
  s.options.levels = static_cast<int>(r.integer("--levels", 0, 10).value_or(1));
  const auto boundary = r.word("--boundary", {"none", "edges", "corners"}).value_or("edges");
  s.options.boundary = boundary == "none"    ? BoundaryInterpolation::kNone
                       : boundary == "edges" ? BoundaryInterpolation::kEdges
                                             : BoundaryInterpolation::kEdgesAndCorners;
  if (r.word("--crease-method", {"uniform", "chaikin"}).value_or("uniform") == "chaikin")
    s.options.crease_method = CreaseMethod::kChaikin;
  s.options.limit = r.flag("--limit");
  s.options.crease_angle = r.number("--crease-angle", 0.0, 180.0);
  s.options.parallel = false;  // batch parallelism is across files, one mesh per worker
  return s;
}

StepOptions read_compress(OptionReader& r) {
  CompressStep s;
  if (auto b = r.integer("--bits", 1, 30)) s.options.bits = static_cast<unsigned>(*b);
  if (auto p = r.number("--precision", 0.0, 1e300)) {
    if (!(*p > 0)) r.fail("--precision must be > 0");
    s.options.precision = *p;
  }
  if (auto l = r.integer("--level", 0, 9)) s.options.level = static_cast<int>(*l);
  s.options.preserve_order = r.flag("--preserve-order");
  return s;
}

StepOptions read_convert(OptionReader& r) {
  ConvertStep s;
  const auto name = r.word("--format", {"obj", "ply", "off", "stl", "drc", "gltf", "glb"});
  s.ascii = r.flag("--ascii");
  r.finish();
  if (!name) r.fail("needs --format");
  s.format = format_from_path("x." + *name);
  return s;
}

using Reader = StepOptions (*)(OptionReader&);
const std::vector<std::pair<std::string, Reader>>& readers() {
  static const std::vector<std::pair<std::string, Reader>> table = {
      {"validate", read_validate}, {"repair", read_repair},     {"simplify", read_simplify},
      {"subdivide", read_subdivide}, {"compress", read_compress}, {"convert", read_convert}};
  return table;
}

Step make_step(const std::vector<std::string>& words, const std::string& where) {
  if (words.empty()) throw InvalidArgument(where + ": empty step");
  const std::string& name = words.front();
  for (const auto& [known, read] : readers()) {
    if (name != known) continue;
    OptionReader r({words.begin() + 1, words.end()}, where + " (" + name + ")");
    Step step{name, {}, read(r)};
    r.finish();
    for (const auto& w : words) step.text += (step.text.empty() ? "" : " ") + w;
    return step;
  }
  std::string list;
  for (const auto& [known, read] : readers()) list += (list.empty() ? "" : ", ") + known;
  throw InvalidArgument(where + ": unknown step '" + name + "' (known: " + list + ")");
}

// {"simplify": {"ratio": 0.25, "keep-boundary": true}} -> simplify --ratio 0.25 --keep-boundary
std::vector<std::string> words_of_object(const Json& step, const std::string& where) {
  if (step.size() != 1 || !step.begin().value().is_object())
    throw InvalidArgument(where + ": an object step is {\"name\": {options}}");
  std::vector<std::string> words{step.begin().key()};
  for (const auto& [key, value] : step.begin().value().items()) {
    if (value.is_boolean()) {
      if (value.get<bool>()) words.push_back("--" + key);
    } else if (value.is_number() || value.is_string()) {
      words.push_back("--" + key);
      words.push_back(value.is_string() ? value.get<std::string>() : value.dump());
    } else {
      throw InvalidArgument(where + ": option '" + key + "' needs a number, string or boolean");
    }
  }
  return words;
}

Pipeline finish_pipeline(std::vector<Step> steps, const std::string& source) {
  if (steps.empty()) throw InvalidArgument(source + ": the pipeline has no steps");
  for (std::size_t i = 0; i + 1 < steps.size(); ++i) {
    const auto& o = steps[i].options;
    if (std::holds_alternative<CompressStep>(o) || std::holds_alternative<ConvertStep>(o))
      throw InvalidArgument(source + ": step " + std::to_string(i + 1) + " (" + steps[i].name +
                            ") writes the output, so it must be the last step");
  }
  return Pipeline{std::move(steps)};
}

}  // namespace

std::string Pipeline::output_extension(const std::string& input_ext) const {
  if (steps.empty()) return input_ext;
  if (std::holds_alternative<CompressStep>(steps.back().options)) return ".gmc";
  if (const auto* c = std::get_if<ConvertStep>(&steps.back().options))
    return std::string(".") + format_name(c->format);
  return input_ext;
}

std::string Pipeline::to_json() const {
  Json j = {{"steps", Json::array()}};
  for (const auto& s : steps) j["steps"].push_back(s.text);
  return j.dump();
}

Pipeline parse_steps(const std::vector<std::string>& texts, const std::string& source) {
  std::vector<Step> steps;
  for (std::size_t i = 0; i < texts.size(); ++i)
    steps.push_back(make_step(split_words(texts[i]), source + ": step " + std::to_string(i + 1)));
  return finish_pipeline(std::move(steps), source);
}

Pipeline parse_pipeline(std::string_view text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {  // a syntax error, or a number beyond a double's range
    throw InvalidArgument(source + ": not JSON: " + e.what());
  }
  if (!j.is_object() || !j.contains("steps") || !j["steps"].is_array())
    throw InvalidArgument(source + ": expected {\"steps\": [...]}");
  for (const auto& [key, value] : j.items())
    if (key != "steps") throw InvalidArgument(source + ": unknown key '" + key + "'");
  std::vector<Step> steps;
  for (std::size_t i = 0; i < j["steps"].size(); ++i) {
    const Json& s = j["steps"][i];
    const std::string where = source + ": step " + std::to_string(i + 1);
    if (s.is_string())
      steps.push_back(make_step(split_words(s.get<std::string>()), where));
    else if (s.is_object())
      steps.push_back(make_step(words_of_object(s, where), where));
    else
      throw InvalidArgument(where + ": a step is a string or an object");
  }
  return finish_pipeline(std::move(steps), source);
}

Pipeline load_pipeline(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open pipeline file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_pipeline(text.str(), path.string());
}

}  // namespace geom::batch
