// Helpers for the formats tests: reading a whole trace, writing one, and
// catching the error a reader gives.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"

namespace nodetrace::formats::testing_util {

struct ReadResult {
  std::vector<Record> records;
  std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> markers;  // record position, marker
  RecordForm form = RecordForm::Din;
  bool tags_are_levels = false;
};

inline ReadResult read_all(const std::string& path, const ReaderOptions& options = {}) {
  auto reader = TraceReader::open(path, options);
  ReadResult result;
  result.form = reader->form();
  result.tags_are_levels = reader->tags_are_levels();
  RecordBatch batch;
  while (reader->next(batch)) {
    EXPECT_EQ(batch.first_record, result.records.size());
    if (batch.marker) result.markers.emplace_back(result.records.size(), *batch.marker);
    result.records.insert(result.records.end(), batch.records.begin(), batch.records.end());
  }
  return result;
}

// The base::FormatError message reading `path` gives, or "" when it reads cleanly.
inline std::string read_error(const std::string& path, const ReaderOptions& options = {}) {
  try {
    read_all(path, options);
  } catch (const base::FormatError& error) {
    return error.what();
  }
  return {};
}

// Runs `body` with standard input reading `bytes` through a pipe (fed in
// 4 KiB pieces by another thread), then restores standard input. Returns the
// message of an exception `body` threw, or "".
template <typename Body>
std::string with_stdin_from(const std::string& bytes, Body&& body) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return "cannot make a pipe";
  const int saved_stdin = ::dup(0);
  ::dup2(pipe_fds[0], 0);
  ::close(pipe_fds[0]);
  std::thread feeder([&] {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const auto wrote = ::write(pipe_fds[1], bytes.data() + done, std::min<std::size_t>(4096, bytes.size() - done));
      if (wrote <= 0) break;
      done += static_cast<std::size_t>(wrote);
    }
    ::close(pipe_fds[1]);
  });
  std::string error;
  try {
    body();
  } catch (const std::exception& caught) {
    error = caught.what();
  }
  feeder.join();
  ::dup2(saved_stdin, 0);
  ::close(saved_stdin);
  return error;
}

inline void write_trace(const std::string& path, const std::vector<Record>& records, const WriterOptions& options,
                        const nlohmann::json& header = nlohmann::json::object(),
                        const std::vector<std::pair<std::uint64_t, AnimationFrameMarker>>& markers = {}) {
  auto writer = TraceWriter::create(path, header, options);
  std::size_t next_marker = 0;
  for (std::size_t i = 0; i <= records.size(); ++i) {
    while (next_marker < markers.size() && markers[next_marker].first == i) {
      writer->begin_animation_frame(markers[next_marker++].second);
    }
    if (i < records.size()) writer->write(records[i]);
  }
  writer->finish();
}

// Deterministic level-tagged node fetches (8-byte nodes, levels 0..29).
inline std::vector<Record> sample_records(std::size_t count, std::uint32_t seed = 1) {
  std::vector<Record> records;
  records.reserve(count);
  std::uint64_t state = seed;
  for (std::size_t i = 0; i < count; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const auto level = static_cast<Tag>((state >> 33) % 30);
    const std::uint64_t address = 0x10000000u + ((state >> 20) & 0xFFFFF) * 8;
    records.push_back(Record{address, 8, AccessType::Read, TraversalUnit{}, level});
  }
  return records;
}

}  // namespace nodetrace::formats::testing_util
