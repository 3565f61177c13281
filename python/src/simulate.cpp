// nodetrace.simulate(): cachesim's simulation API on a trace or on arrays
// of records; the options parsed by cachesim run's own parser.
#include <pybind11/numpy.h>
#include <pybind11/eval.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "array_trace_reader.hpp"
#include "captured_stderr.hpp"
#include "interruptible.hpp"
#include "json_value.hpp"
#include "option_arguments.hpp"
#include "simulate.hpp"
#include "trace_file.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/simulation/run_arguments.hpp"
#include "nodetrace/cachesim/simulation/simulation.hpp"
#include "nodetrace/cli/split_words.hpp"

namespace py = pybind11;

namespace nodetrace::python {

std::vector<std::string> simulation_words(const py::object& options, const std::string& name) {
  std::vector<std::string> words;
  if (py::isinstance<py::str>(options)) {
    words = cli::split_words(options.cast<std::string>(), name.c_str());
  } else if (py::isinstance<py::list>(options) || py::isinstance<py::tuple>(options)) {
    words = options.cast<std::vector<std::string>>();  // words as a command line gives them
  } else if (py::isinstance<py::dict>(options)) {
    words = option_words(options.cast<py::dict>());
  } else if (!options.is_none()) {
    throw base::UsageError(name + ": expected cachesim run's options as a text, a list of words or a dict");
  }
  return words;
}

cachesim::SimulationOptions parse_simulation_options(
    const std::string& name, const std::function<std::optional<int>(cachesim::SimulationOptions&)>& parse) {
  cachesim::SimulationOptions options;
  std::string printed;
  const std::optional<int> status = capture_stderr(printed, [&] { return parse(options); });
  if (status) {
    // "NAME: MESSAGE\nRun with --help ...": the message alone.
    std::string message = printed.substr(0, printed.find('\n'));
    const std::string prefix = name + ": ";
    if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
    throw base::UsageError(*status == 0 ? "--help: the options are cachesim run's (cachesim run --help)" : message);
  }
  if (options.format != "table") {
    throw base::UsageError("--format: simulate() returns the rows themselves (as cachesim run --format csv prints "
                           "them); it takes no format");
  }
  options.format = "json";
  return options;
}

// The rows of the report's JSON ({"columns": [...], "rows": [{column:
// value, ...}, ...]}: the CSV's cells typed, null for an empty one), with
// the notes, in a SimulationRows.
py::object report_rows(const cachesim::SimulationReport& report) {
  const py::object json = py::module_::import("json").attr("loads")(report.out);
  const py::object columns = json["columns"];
  const py::object rows = json["rows"];
  py::list notes;
  std::size_t start = 0;
  while (start < report.err.size()) {
    const std::size_t end = report.err.find('\n', start);
    notes.append(report.err.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return py::module_::import("nodetrace").attr("SimulationRows")(rows, columns, notes);
}

namespace {

constexpr const char* kName = "nodetrace.simulate";

// Parsed by cachesim run's parser; its parse error, which it prints, raised.
cachesim::SimulationOptions parse_options(const std::vector<std::string>& words) {
  const cachesim::RunArgumentsSyntax syntax(kName, "cachesim run's options, for simulate()", /*traces=*/false);
  return parse_simulation_options(
      kName, [&](cachesim::SimulationOptions& options) { return cachesim::parse_run_arguments(words, syntax, options); });
}

}  // namespace

void bind_simulate(py::module_& module) {
  // The rows as a list, with the report's columns and notes, and a pandas
  // DataFrame when pandas is there.
  py::exec(R"(
class SimulationRows(list):
    """The rows cachesim run --format csv prints, one dict per row (ints, floats, None for an empty cell);
    .columns in the CSV's order, .notes what cachesim run says on standard error."""
    def __init__(self, rows, columns, notes):
        super().__init__(rows)
        self.columns = list(columns)
        self.notes = list(notes)

    def to_pandas(self):
        """The rows as a pandas DataFrame, columns in the CSV's order (needs pandas)."""
        import pandas
        return pandas.DataFrame(list(self), columns=self.columns)
)",
           module.attr("__dict__"));
  module.attr("SimulationRows").attr("__module__") = "nodetrace";

  module.def(
      "simulate",
      [](const py::object& input, const py::object& options, std::optional<std::string> name,
         const py::kwargs& keywords) {
        std::vector<std::string> words = simulation_words(options, "options");
        const std::vector<std::string> more = option_words(keywords);
        words.insert(words.end(), more.begin(), more.end());
        cachesim::SimulationOptions parsed = parse_options(words);
        std::unique_ptr<formats::TraceReader> reader;
        std::string column;
        std::optional<py::array_t<ArrayRecord>> held;  // the arrays a reader reads in place
        if (py::isinstance<py::array>(input)) {
          held = py::array_t<ArrayRecord>::ensure(input);
          if (!held || held->ndim() != 1) {
            throw base::UsageError("records: expected a one-dimensional array of nodetrace.RECORD_DTYPE");
          }
          column = name.value_or("records");
        } else {
          const std::string path = py::isinstance<TraceFile>(input) ? input.cast<const TraceFile&>().path()
                                                                    : input.cast<std::filesystem::path>().string();
          column = name.value_or(path);
        }
        parsed.traces = {column};
        const cachesim::SimulationPlan plan(parsed);
        if (held) {
          reader = std::make_unique<ArrayTraceReader>(*held, column);
        } else {
          const std::string path = py::isinstance<TraceFile>(input) ? input.cast<const TraceFile&>().path()
                                                                    : input.cast<std::filesystem::path>().string();
          reader = formats::TraceReader::open(path, plan.reader_options());
        }
        const cachesim::SimulationMode mode = plan.mode_for({reader.get()});
        const cachesim::SimulationReport report = run_interruptibly([&](const SignalCheck& check) {
          const cachesim::TraceOutcome outcome =
              plan.simulate(mode, *reader, column, [&](std::uint64_t) { check(); });
          return plan.report(mode, {outcome});
        });
        return report_rows(report);
      },
      py::arg("trace"), py::arg("options") = py::none(), py::kw_only(), py::arg("name") = py::none(),
      "Simulates caches on TRACE (a trace file's path, a TraceFile, or an array of nodetrace.RECORD_DTYPE "
      "records) with cachesim run's options: a text as cachesim run takes them (\"--size 4k,8k --scheme "
      "single,split\"), a list of words, a dict, or keywords (size=\"4k,8k\", scheme=[\"single\", \"split\"]), parsed by "
      "cachesim run's parser. Returns the rows cachesim run --format csv prints (SimulationRows: a list of "
      "dicts; .to_pandas()). name= is the trace column (default: the path as given, or 'records'). Runs in "
      "C++ without the GIL; Ctrl-C stops it. A wrong option name or value raises ValueError with cachesim "
      "run's message.");
}

}  // namespace nodetrace::python
