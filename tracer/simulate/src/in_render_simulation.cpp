#include "nodetrace/tracer/simulate/in_render_simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <utility>

#include "nodetrace/cachesim/simulation/run_arguments.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/split_words.hpp"
#include "nodetrace/formats/read/record_pipe.hpp"

namespace nodetrace::tracer::simulate {

// One layout's simulation: the pipe its sink fills, and either the sweep
// the pipe feeds on the render's thread that hands over the records, or
// the thread that runs cachesim over the pipe's reader (the modes that
// read a trace their own way).
struct InRenderSimulation::Layout {
  std::unique_ptr<formats::RecordPipe> pipe;
  std::unique_ptr<formats::TraceReader> reader;
  std::unique_ptr<cachesim::Simulation> fed;
  std::thread thread;
  cachesim::TraceOutcome outcome;
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  bool finished = false;

  // The simulation's error, once its thread has ended.
  void rethrow_failure() {
    if (thread.joinable()) thread.join();
    if (error) std::rethrow_exception(error);
  }
  ~Layout() {
    if (!thread.joinable()) return;
    pipe->fail("the render stopped before the end of its records");
    thread.join();
  }
};

namespace {

class SimulationSink final : public RecordSink {
 public:
  explicit SimulationSink(std::shared_ptr<InRenderSimulation::Layout> layout) : layout_(std::move(layout)) {}
  // A render that stopped early (an error) ends its simulation too.
  ~SimulationSink() override {
    if (layout_->finished || !layout_->thread.joinable()) return;
    layout_->pipe->fail("the render stopped before the end of its records");
    layout_->thread.join();
  }
  void begin_animation_frame(const formats::AnimationFrameMarker& marker) override {
    check();
    layout_->pipe->begin_animation_frame(marker);
  }
  void begin_window(const formats::WindowMarker& marker) override {
    check();
    layout_->pipe->begin_window(marker);
  }
  void write(std::span<const formats::Record> records) override {
    check();
    layout_->pipe->write(records);
  }
  void finish(const nlohmann::json& totals) override {
    check();
    layout_->pipe->finish(totals);
    if (layout_->fed) layout_->outcome = layout_->fed->finish();
    layout_->rethrow_failure();
    layout_->finished = true;
  }

 private:
  // A simulation that failed (a cache its high levels do not fit, ...) ends
  // the render now, with its error.
  void check() {
    if (layout_->failed.load(std::memory_order_acquire)) layout_->rethrow_failure();
  }
  std::shared_ptr<InRenderSimulation::Layout> layout_;
};

}  // namespace

namespace {

// How --simulate's options are named in usage and errors.
constexpr const char* kSimulateName = "tracer render --simulate";

}  // namespace

InRenderSimulation::~InRenderSimulation() = default;

std::optional<int> InRenderSimulation::parse(const std::string& text, const std::vector<std::string>& layout_names) {
  std::string options = text;
  const std::size_t first_space = text.find(' ');
  const std::size_t equals = text.find('=');
  // "LAYOUT=OPTIONS": cachesim's options begin with '-', a layout's name never does.
  if (!text.empty() && text[0] != '-' && equals != std::string::npos && equals < first_space) {
    const std::string layout = text.substr(0, equals);
    const auto found = std::find(layout_names.begin(), layout_names.end(), layout);
    if (found == layout_names.end()) {
      std::string names;
      for (const auto& name : layout_names) names += (names.empty() ? "" : ", ") + name;
      cli::report_error(kSimulateName,
                        fmt::format("'{}': this render has no layout of that name (its layouts: {})", layout, names)
                            .c_str());
      return 2;
    }
    only_layout_ = static_cast<std::size_t>(found - layout_names.begin());
    options = text.substr(equals + 1);
  }
  std::vector<std::string> words;
  const int status = cli::exit_status_of(kSimulateName, [&] {
    words = cli::split_words(options, "--simulate");
    return 0;
  });
  if (status != 0) return status;
  cachesim::SimulationOptions parsed;
  if (auto parse_status = parse_words(words, parsed)) return parse_status;
  const int plan_status = cli::exit_status_of(kSimulateName, [&] {
    plan(std::move(parsed));
    return 0;
  });
  if (plan_status != 0) return plan_status;
  return std::nullopt;
}

std::optional<int> InRenderSimulation::parse_words(const std::vector<std::string>& words,
                                                   cachesim::SimulationOptions& options) {
  const cachesim::RunArgumentsSyntax syntax{
      kSimulateName, "Simulate node caches on the render's records (cachesim run's options, no traces)",
      /*traces=*/false};
  return cachesim::parse_run_arguments(words, syntax, options);
}

void InRenderSimulation::plan(cachesim::SimulationOptions options) { plan_.emplace(std::move(options)); }

std::vector<std::string> InRenderSimulation::trace_names(const TraceJobOptions& options,
                                                         const std::vector<std::string>& layout_names) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < layout_names.size(); ++i) {
    const std::string& file = i == 0 ? options.output : options.other_layouts[i - 1].output;
    names.push_back(file.empty() ? layout_names[i] : file);
  }
  return names;
}

RecordSinkMaker InRenderSimulation::sink_maker(std::vector<std::string> trace_names) {
  return [this, names = std::move(trace_names)](const TraceStart& start) -> std::unique_ptr<RecordSink> {
    if (only_layout_ && *only_layout_ != start.layout_index) return nullptr;
    auto layout = std::make_shared<Layout>();
    const std::string& name = names.at(start.layout_index);
    Layout* simulated = layout.get();
    layout->pipe = std::make_unique<formats::RecordPipe>(name, start.header, start.writer);
    layout->reader = layout->pipe->reader();
    const cachesim::SimulationMode mode = plan_->mode_for({layout->reader.get()});
    if (!mode_) mode_ = mode;
    // Fed as the records are handed over, on that thread, where the mode
    // allows: a thread of its own cost more CPU in hand-overs, wake-ups and
    // records moved between cores than the simulation itself.
    layout->fed = plan_->start(mode, *layout->reader, name);
    if (layout->fed) {
      layout->pipe->feed_to([simulated](const formats::RecordBatch& batch) { simulated->fed->feed(batch); });
      layouts_.push_back(layout);
      return std::make_unique<SimulationSink>(std::move(layout));
    }
    // The other modes read the pipe on a thread of their own.
    layout->thread = std::thread([this, simulated, mode, name] {
      try {
        simulated->outcome = plan_->simulate(mode, *simulated->reader, name);
      } catch (...) {
        simulated->error = std::current_exception();
        simulated->pipe->stop_reading();
        simulated->failed.store(true, std::memory_order_release);
      }
    });
    layouts_.push_back(layout);
    return std::make_unique<SimulationSink>(std::move(layout));
  };
}

std::vector<cli::NamedOutput> InRenderSimulation::table_files() const {
  const cachesim::SimulationOptions& line = plan_->options();
  std::vector<cli::NamedOutput> files;
  for (const auto& [option, path] : {std::pair{"--per-level", &line.per_level},
                                     std::pair{"--per-frame", &line.per_frame},
                                     std::pair{"--per-unit", &line.per_unit}}) {
    if (!path->empty() && *path != "-") files.push_back({fmt::format("--simulate's {}", option), *path});
  }
  return files;
}

cachesim::SimulationReport InRenderSimulation::report() const {
  std::vector<cachesim::TraceOutcome> outcomes;
  for (const auto& layout : layouts_) outcomes.push_back(layout->outcome);
  return plan_->report(mode_.value_or(cachesim::SimulationMode::Sweep), outcomes);
}

}  // namespace nodetrace::tracer::simulate
