#include "nodetrace/cachesim/simulation/run_arguments.hpp"

#include <CLI/CLI.hpp>

#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/format_option.hpp"

namespace nodetrace::cachesim {

namespace {

// --policy's description. `cachesim_run`: the policies Dinero IV does not have too.
std::string policy_help(bool cachesim_run) {
  if (!cachesim_run) {
    return "Replacement: lru, fifo, random (list); random draws Dinero IV's sequence. The other policies "
           "of cachesim run (plru, srrip, brrip, drrip, opt) are not Dinero IV's: not here";
  }
  return "Replacement (list): lru, fifo, random (Dinero IV's: random draws its sequence, glibc's random() "
         "after srandom(1), one generator per cache); plru (tree pseudo-LRU, power-of-two ways); srrip "
         "(2-bit RRIP: insert at 2, 0 on a hit, victim the first way at 3 after ageing the set); brrip (insert "
         "at 3 but every 32nd insertion of the cache at 2: the 32nd, 64th, ...); drrip (set dueling, 10-bit "
         "PSEL from 511: of S sets, min(32, S/2) runs of consecutive sets, each run's first set an srrip "
         "leader and its last a brrip leader; other sets brrip while PSEL >= 512); opt (Belady's MIN: on a "
         "miss in a full set the block whose next use is farthest, never used again counting as farthest, "
         "is kept out, the incoming one included: it is then not placed; MIN within each set; the trace is "
         "read once and its fetches kept, 8 bytes each). A miss fills the lowest invalid way first";
}

// The options cachesim run and dinero-wrap run share. `side_tables`:
// --per-level and --per-frame (cachesim run only: Dinero IV reports totals).
void add_shared_options(CLI::App& app, SimulationOptions& line, bool side_tables, bool traces_positional) {
  if (traces_positional) {
    app.add_option("traces", line.traces, "Trace files (container, plain din / xdin, zstd); - is stdin")
        ->required();
  }
  app.add_option("--size", line.sizes, "Total cache sizes, bytes with optional k/m, at most 256m (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--block", line.blocks, "Block sizes in bytes (list)")->delimiter(',')->capture_default_str();
  app.add_option("--assoc", line.assocs, "Associativities: ways or 'full' (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--policy", line.policies, policy_help(side_tables))->delimiter(',')->capture_default_str();
  app.add_option("--scheme", line.schemes, "single, split (list)")->delimiter(',')->capture_default_str();
  app.add_option("--split-level", line.split_levels,
                 "K: levels < K go to the high-level cache; 'auto' sizes K to the high cache "
                 "from the animation-frame markers (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--high-policy", line.high_policies,
                 "High-level cache: retain (loaded once per animation frame) or cache (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--high-size", line.high_size, "High-level cache size (default: half the total)");
  app.add_option("--low-size", line.low_size, "Low-level cache size (default: the rest)");
  app.add_option("--high-assoc", line.high_assoc, "High-level cache associativity under 'cache' (default: --assoc)");
  app.add_flag("--count-loads", line.count_loads, "retain: count the high-level loads as misses");
  app.add_option("--fetch", line.fetch,
                 "Fetch policy, Dinero IV's: demand, always, miss, tagged, load-forward, subblock. "
                 "Other than demand: --scheme single only, each configuration simulated by itself "
                 "(the stack groups that answer many configurations in one pass are demand-only); "
                 "misses are demand misses, as Dinero IV counts them")
      ->check(CLI::IsMember({"demand", "always", "miss", "tagged", "load-forward", "subblock"}))
      ->capture_default_str();
  app.add_option("--prefetch-distance", line.prefetch_distance,
                 "Blocks ahead that a prefetch goes (Dinero IV's -pfdist; load-forward and subblock: 1)")
      ->capture_default_str();
  app.add_flag("--tags-are-levels", line.tags_are_levels, "Read the tag field of a plain trace as the node level");
  if (side_tables) {
    app.add_option("--per-level", line.per_level,
                   "Write the table of references and misses per node level to FILE (its own table: "
                   "every configuration column, then level, refs, misses; - for standard output, "
                   "which then carries it alone)")
        ->type_name("FILE");
    app.add_option("--per-frame", line.per_frame,
                   "Write the table of the counts of each animation frame (each with its own K) to "
                   "FILE (the main columns with frame after trace; - for standard output, which then "
                   "carries it alone)")
        ->type_name("FILE");
  }
  cli::add_format_option(app, line.format, "csv: one table, json: {\"columns\": [...], \"rows\": [...]}");
  app.add_option("--informat", line.informat, "Record form of plain traces: din, xdin or binary (default: detected)")
      ->check(CLI::IsMember({"din", "xdin", "binary"}));
  app.add_option("--threads", line.threads, "Trace decoding threads (0: one per core; at most 16 per core)")
      ->capture_default_str();
}

// The values of the options whose default is "not given" (SimulationOptions' optionals).
struct UnsetDefaults {
  std::string units = "shared";
  std::uint32_t l2_block = 64;
  std::string l2_assoc = "8";
  std::string l2_policy = "lru";
};

// cachesim run's own options (dinero-wrap has none of these).
void add_cachesim_options(CLI::App& app, SimulationOptions& line, UnsetDefaults& unset) {
  // A curve has no Dinero IV run to check it.
  app.add_flag("--curve", line.curve,
               "Instead: miss ratio of every power-of-two size up to 64 MB (in --format), per --block and "
               "--assoc, single caches and the split scheme's low cache (K from --split-level, "
               "or auto for --high-size)");
  app.add_option("--sample-windows", line.sample_windows,
                 "Simulate one window of records in every K (1/K), chosen by --sample-seed; the "
                 "report gains each miss ratio's standard error and 95% interval");
  app.add_option("--window-records", line.window_records,
                 "Records per window of --sample-windows (default: one container data frame)")
      ->capture_default_str();
  app.add_option("--sample-sets", line.sample_sets,
                 "Simulate the blocks of one cache set in every K (1/K, K a power of two); needs one --block and "
                 "power-of-two set counts of at least K");
  app.add_option("--sample-seed", line.sample_seed, "Seed of the sampled windows and sets")->capture_default_str();
  app.add_option("--units", unset.units,
                 "Traversal units of a trace whose records carry them (header \"units\"): shared (one copy of "
                 "each cache sees every record) or private (each unit its own copy; the report sums them)")
      ->check(CLI::IsMember({"shared", "private"}))
      ->capture_default_str();
  app.add_option("--l2-size", line.l2_size,
                 "Add a second-level cache of this size, shared by all units, seeing each configuration's "
                 "first-level misses (and retained high-cache loads) in trace order; its own report columns");
  app.add_option("--l2-block", unset.l2_block, "Second-level block size in bytes")->capture_default_str();
  app.add_option("--l2-assoc", unset.l2_assoc, "Second-level ways, or full")->capture_default_str();
  app.add_option("--l2-policy", unset.l2_policy, "Second-level replacement: lru or fifo")
      ->check(CLI::IsMember({"lru", "fifo"}))
      ->capture_default_str();
  app.add_option("--prefetch", line.prefetch,
                 "Treelet prefetcher (list): none, treelet[:BYTES] (on a demand miss, the rest of the missed "
                 "block's treelet, at most BYTES from the block on, a power of two, into the cache that missed) or "
                 "treelet-low[:BYTES] (into the split scheme's low-level cache only); needs a trace with a treelet "
                 "map (tracer render --layout treelet); adds the prefetch columns; timing not modelled")
      ->delimiter(',');
  app.add_option("--per-unit", line.per_unit,
                 "--units private: also write each unit's rows (the main columns, unit after trace) to FILE "
                 "(- for standard output instead of the main table)");
}

template <typename T>
void set_if_given(const CLI::App& app, const char* option, const T& value, std::optional<T>& to) {
  if (app.count(option) > 0) to = value;
}

}  // namespace

std::optional<int> parse_run_arguments(const std::vector<std::string>& arguments, const RunArgumentsSyntax& syntax,
                                       SimulationOptions& options) {
  CLI::App app{syntax.description, syntax.name};
  add_shared_options(app, options, syntax.cachesim_only_options, syntax.traces);
  UnsetDefaults unset;
  if (syntax.cachesim_only_options) add_cachesim_options(app, options, unset);
  for (const ExtraOption& extra : syntax.extra) {
    std::visit([&](auto* value) { app.add_option(extra.name, *value, extra.help); }, extra.value);
  }
  std::vector<std::string> args = arguments;
  args.insert(args.begin(), syntax.name);
  std::vector<char*> argv;
  for (auto& arg : args) argv.push_back(arg.data());
  if (const std::optional<int> status = cli::parse_command_line(app, static_cast<int>(argv.size()), argv.data())) {
    return status;
  }
  options.sizes_given = options.sizes_given || app.count("--size") > 0;
  options.high_policies_given = options.high_policies_given || app.count("--high-policy") > 0;
  if (syntax.cachesim_only_options) {
    set_if_given(app, "--units", unset.units, options.units);
    set_if_given(app, "--l2-block", unset.l2_block, options.l2_block);
    set_if_given(app, "--l2-assoc", unset.l2_assoc, options.l2_assoc);
    set_if_given(app, "--l2-policy", unset.l2_policy, options.l2_policy);
  }
  return std::nullopt;
}

}  // namespace nodetrace::cachesim
