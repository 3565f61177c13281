// decide_trace_output: container or plain records and the record form, from the
// output path and the options (the one place that reads suffixes).
#include <gtest/gtest.h>

#include "nodetrace/formats/write/trace_output.hpp"

namespace nodetrace::formats {
namespace {

TEST(TraceOutput, TheNameSaysContainerOrPlainAndTheForm) {
  const auto plan = [](const char* path) { return decide_trace_output(path); };
  EXPECT_TRUE(plan("t.din.zst").container);
  EXPECT_TRUE(plan("-").container);
  EXPECT_FALSE(plan("t.din").container);
  EXPECT_FALSE(plan("t.zst.din").container);
  EXPECT_EQ(plan("t.din.zst").form, RecordForm::Din);
  EXPECT_EQ(plan("t.xdin.zst").form, RecordForm::ExtendedDin);
  EXPECT_EQ(plan("t.xdin").form, RecordForm::ExtendedDin);
  EXPECT_EQ(plan("t.bin.zst").form, RecordForm::Binary);
  EXPECT_EQ(plan("t.bin").form, RecordForm::Binary);
  EXPECT_EQ(plan("t.txt").form, RecordForm::Din);
  EXPECT_EQ(plan("-").form, RecordForm::Din);
  EXPECT_EQ(plan("").form, RecordForm::Din);
}

TEST(TraceOutput, OptionsOverrideTheName) {
  EXPECT_TRUE(decide_trace_output("t.din", OutputKind::Container).container);
  EXPECT_FALSE(decide_trace_output("t.din.zst", OutputKind::Plain).container);
  EXPECT_FALSE(decide_trace_output("-", OutputKind::Plain).container);
  EXPECT_EQ(decide_trace_output("t.bin.zst", OutputKind::Auto, RecordForm::ExtendedDin).form, RecordForm::ExtendedDin);
  EXPECT_EQ(decide_trace_output("-", OutputKind::Auto, RecordForm::Binary).form, RecordForm::Binary);
}

}  // namespace
}  // namespace nodetrace::formats
