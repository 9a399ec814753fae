// Batch processing for Python: the per-file function and the planning, on the pipeline's JSON
// text, so a task is a few strings that pickle cheaply to a process pool or a Dask worker.

#include "bindings.h"

#include <geom/batch/batch.h>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

namespace geom::python {
namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

batch::ExistingOutput existing_from(const std::string& name) {
  if (name == "fail") return batch::ExistingOutput::kFail;
  if (name == "skip") return batch::ExistingOutput::kSkip;
  if (name == "overwrite") return batch::ExistingOutput::kOverwrite;
  throw InvalidArgument("existing must be 'fail', 'skip' or 'overwrite', not '" + name + "'");
}

}  // namespace

void bind_batch(py::module_& m) {
  m.def("_batch_pipeline", [](const std::string& json) {
    return batch::parse_pipeline(json).to_json();
  }, py::arg("pipeline_json"));
  m.def("_batch_find", &batch::find_meshes, py::arg("dir"), py::arg("exclude") = fs::path());
  m.def("_batch_plan", [](const std::string& json, const fs::path& in_root,
                          const std::vector<fs::path>& inputs, const fs::path& out_root) {
    std::vector<std::tuple<std::string, std::string, std::string, std::string>> out;
    for (const auto& t : batch::plan(batch::parse_pipeline(json), in_root, inputs, out_root))
      out.emplace_back(t.input.string(), t.output.string(), t.input_name, t.output_name);
    return out;
  }, py::arg("pipeline_json"), py::arg("in_root"), py::arg("inputs"), py::arg("out_root"));
  m.def("_batch_process", [](const std::string& json, const std::string& existing,
                             const std::tuple<std::string, std::string, std::string, std::string>& t) {
    const batch::Pipeline p = batch::parse_pipeline(json);
    const batch::Task task{std::get<0>(t), std::get<1>(t), std::get<2>(t), std::get<3>(t)};
    const batch::ExistingOutput e = existing_from(existing);
    py::gil_scoped_release release;
    return batch::process(p, task, e).to_json();
  }, py::arg("pipeline_json"), py::arg("existing"), py::arg("task"));
  m.def("_batch_remove_partial_outputs", &batch::remove_partial_outputs, py::arg("out_root"));
}

}  // namespace geom::python
