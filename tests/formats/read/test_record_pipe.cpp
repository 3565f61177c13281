// RecordPipe hands a producer's records to a reader on another thread (or
// to a function on the producer's) as a container reader of the same trace
// would deliver them: the records as their form reads back, the markers
// where they begin, and batches no larger than a container's decoded
// pieces, however large the producer's writes.
#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>
#include <vector>

#include "nodetrace/formats/read/record_pipe.hpp"

namespace nodetrace::formats {
namespace {

constexpr std::size_t kContainerPieceRecords = 16384;

std::vector<Record> numbered_records(std::size_t count, std::uint64_t first) {
  std::vector<Record> records(count);
  for (std::size_t i = 0; i < count; ++i) {
    records[i].address = (first + i) * 8;
    records[i].size = 8;
    records[i].tag = static_cast<Tag>((first + i) % 20);
  }
  return records;
}

struct Delivered {
  std::vector<Record> records;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> frames;   // (first record, frame)
  std::vector<std::pair<std::uint64_t, std::uint64_t>> windows;  // (first record, window)
  std::size_t largest_batch = 0;
  bool first_records_consistent = true;
  bool kinds_stated = true;
};

void take(Delivered& delivered, const RecordBatch& batch) {
  delivered.first_records_consistent &= batch.first_record == delivered.records.size();
  if (batch.marker) delivered.frames.emplace_back(batch.first_record, batch.marker->frame);
  if (batch.window) delivered.windows.emplace_back(batch.first_record, batch.window->window);
  if (!batch.records.empty()) delivered.kinds_stated &= batch.kinds.demand_fetches && batch.kinds.levels;
  delivered.largest_batch = std::max(delivered.largest_batch, batch.records.size());
  delivered.records.insert(delivered.records.end(), batch.records.begin(), batch.records.end());
}

Delivered read_everything(TraceReader& reader) {
  Delivered delivered;
  RecordBatch batch;
  while (reader.next(batch)) take(delivered, batch);
  return delivered;
}

// Three full pieces and a part, then a window, then an animation frame with no records.
const std::vector<Record> kFirst = numbered_records(3 * kContainerPieceRecords + 123, 0);
const std::vector<Record> kSecond = numbered_records(5, kFirst.size());

void produce(RecordPipe& pipe) {
  AnimationFrameMarker frame0;
  frame0.frame = 0;
  pipe.begin_animation_frame(frame0);
  pipe.write(kFirst);
  WindowMarker window;
  window.window = 7;
  pipe.begin_window(window);
  pipe.write(kSecond);
  AnimationFrameMarker frame1;
  frame1.frame = 1;
  pipe.begin_animation_frame(frame1);
  pipe.finish(nlohmann::json::object());
}

void expect_container_batches(const Delivered& delivered) {
  const std::vector<Record>& first = kFirst;
  const std::vector<Record>& second = kSecond;
  std::vector<Record> expected;
  for (const auto* part : {&first, &second}) {
    for (const Record& record : *part) expected.push_back(as_read_back(record, RecordForm::Din));
  }
  ASSERT_EQ(delivered.records.size(), expected.size());
  EXPECT_TRUE(delivered.records == expected);  // din reads back size 4
  EXPECT_EQ(delivered.records.front().size, 4u);
  EXPECT_EQ(delivered.largest_batch, kContainerPieceRecords);
  EXPECT_TRUE(delivered.first_records_consistent);
  EXPECT_TRUE(delivered.kinds_stated);
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> frames{{0, 0}, {expected.size(), 1}};
  EXPECT_EQ(delivered.frames, frames);
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> windows{{first.size(), 7}};
  EXPECT_EQ(delivered.windows, windows);
}

TEST(RecordPipe, LargeWritesArriveInContainerSizedBatchesWithMarkersWhereTheyBegin) {
  WriterOptions options;
  options.form = RecordForm::Din;
  RecordPipe pipe("pipe", nlohmann::json::object(), options);
  auto reader = pipe.reader();
  std::thread producer([&] { produce(pipe); });
  const Delivered delivered = read_everything(*reader);
  producer.join();
  expect_container_batches(delivered);
  ASSERT_TRUE(reader->trailer().has_value());
  EXPECT_EQ(reader->trailer()->totals.at("records"), kFirst.size() + kSecond.size());
}

TEST(RecordPipe, AConsumerGetsTheReadersBatchesOnTheProducersThreadAsTheyAreMade) {
  WriterOptions options;
  options.form = RecordForm::Din;
  Delivered delivered;
  bool on_producers_thread = true;
  const std::thread::id producer = std::this_thread::get_id();
  RecordPipe pipe("pipe", nlohmann::json::object(), options);
  pipe.feed_to([&](const RecordBatch& batch) {
    on_producers_thread &= std::this_thread::get_id() == producer;
    take(delivered, batch);
  });
  produce(pipe);
  EXPECT_TRUE(on_producers_thread);
  expect_container_batches(delivered);

  Delivered early;
  RecordPipe second("second", nlohmann::json::object(), options);
  second.feed_to([&](const RecordBatch& batch) { take(early, batch); });
  second.write(numbered_records(10, 0));
  EXPECT_EQ(early.records.size(), 10u);  // before write returns, not at the end
  // Batches already made went nowhere else: a consumer comes before them.
  EXPECT_THROW(second.feed_to([](const RecordBatch&) {}), std::logic_error);
}

TEST(RecordPipe, EachFormReadsBackAsItsContainerGivesIt) {
  std::vector<Record> records = numbered_records(100, 0);
  records[3].unit = traversal_unit(5);
  records[4].type = AccessType::Write;
  for (RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin, RecordForm::Binary}) {
    WriterOptions options;
    options.form = form;
    Delivered delivered;
    RecordPipe pipe("pipe", nlohmann::json::object(), options);
    pipe.feed_to([&](const RecordBatch& batch) { take(delivered, batch); });
    pipe.write(records);
    pipe.finish(nlohmann::json::object());
    std::vector<Record> expected;
    for (const Record& record : records) expected.push_back(as_read_back(record, form));
    EXPECT_TRUE(delivered.records == expected) << form_name(form);
    // Binary records carry no tag, so no level; a write is a demand fetch.
    EXPECT_EQ(delivered.kinds_stated, form != RecordForm::Binary) << form_name(form);
  }
  EXPECT_EQ(as_read_back(records[3], RecordForm::Binary).unit, TraversalUnit{});
  EXPECT_EQ(as_read_back(records[3], RecordForm::Binary).tag, kTagNone);
  EXPECT_EQ(as_read_back(records[3], RecordForm::Din).size, 4u);
  EXPECT_EQ(as_read_back(records[3], RecordForm::ExtendedDin), records[3]);
}

}  // namespace
}  // namespace nodetrace::formats
