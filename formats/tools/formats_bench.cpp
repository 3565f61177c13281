// Benchmark driver for scripts/bench-formats.sh (built only on request:
// `cmake --build BUILD --target formats_bench`). Not a user tool.
//   formats_bench generate N OUT [--threads T]  write N level-tagged node fetches
//   formats_bench read FILE [--threads T]       decode every record, print a checksum
// Both print "records=N seconds=S" on standard error.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"

namespace formats = nodetrace::formats;

namespace {

// Root-to-leaf descents of a breadth-first-laid-out binary tree, as a kd-tree
// traversal issues them: level = depth, address = base + slot * 8.
int generate(std::uint64_t count, const std::string& out, unsigned threads) {
  formats::WriterOptions options;
  options.threads = threads;
  auto writer = formats::TraceWriter::create(out, {{"producer", {{"tool", "formats_bench"}}}}, options);
  std::vector<formats::Record> batch;
  batch.reserve(1 << 16);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  std::uint64_t written = 0;
  const auto start = std::chrono::steady_clock::now();
  while (written < count) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const unsigned depth = 8 + static_cast<unsigned>((state >> 59) & 15);  // 8..23
    std::uint64_t bits = state >> 20;
    std::uint64_t slot = 0;
    for (unsigned level = 0; level <= depth && written < count; ++level) {
      batch.push_back({0x10000000ull + slot * 8, 8, formats::AccessType::Read, formats::TraversalUnit{}, static_cast<formats::Tag>(level)});
      ++written;
      slot = 2 * slot + 1 + (bits & 1);
      bits >>= 1;
      if (batch.size() == batch.capacity()) {
        writer->write(batch);
        batch.clear();
      }
    }
  }
  writer->write(batch);
  writer->finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "records=%llu seconds=%.4f\n", static_cast<unsigned long long>(written), seconds);
  return 0;
}

int read(const std::string& path, unsigned threads) {
  formats::ReaderOptions options;
  options.threads = threads;
  const auto start = std::chrono::steady_clock::now();
  auto reader = formats::TraceReader::open(path, options);
  formats::RecordBatch batch;
  std::uint64_t records = 0, checksum = 0;
  while (reader->next(batch)) {
    records += batch.records.size();
    for (const auto& record : batch.records) checksum += record.address ^ record.tag;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("checksum=%llu\n", static_cast<unsigned long long>(checksum));
  std::fprintf(stderr, "records=%llu seconds=%.4f\n", static_cast<unsigned long long>(records), seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return nodetrace::cli::exit_status_of("formats_bench", [&] {
    const std::vector<std::string> args(argv + 1, argv + argc);
    unsigned threads = 0;
    for (std::size_t i = 0; i + 1 < args.size(); ++i) {
      if (args[i] == "--threads") threads = static_cast<unsigned>(std::stoul(args[i + 1]));
    }
    if (args.size() >= 3 && args[0] == "generate") return generate(std::stoull(args[1]), args[2], threads);
    if (args.size() >= 2 && args[0] == "read") return read(args[1], threads);
    throw nodetrace::base::UsageError("usage: formats_bench generate N OUT [--threads T] | read FILE [--threads T]");
  });
}
