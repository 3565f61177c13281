// The ordered pipeline: results come out in submission order whatever order
// the jobs finish in and whatever the thread count; a job's exception comes
// out at its place; the destructor waits for jobs in flight.
#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <stdexcept>
#include <string>
#include <vector>

#include "nodetrace/base/ordered_pipeline.hpp"

namespace nodetrace::base {
namespace {

TEST(OrderedPipeline, ResultsComeOutInSubmissionOrderWhenLaterJobsFinishFirst) {
  OrderedPipeline<int> pipeline(2);
  std::promise<void> second_done;
  std::shared_future<void> second = second_done.get_future().share();
  pipeline.submit([second] {
    second.wait();  // finishes only after the job submitted after it
    return 1;
  });
  pipeline.submit([&second_done] {
    second_done.set_value();
    return 2;
  });
  pipeline.push_ready(3);
  ASSERT_EQ(pipeline.size(), 3u);
  EXPECT_EQ(pipeline.pop(), 1);
  EXPECT_EQ(pipeline.pop(), 2);
  EXPECT_TRUE(pipeline.front_ready());
  EXPECT_EQ(pipeline.pop(), 3);
  EXPECT_TRUE(pipeline.empty());
}

TEST(OrderedPipeline, SameResultsWhateverTheThreadCount) {
  std::vector<std::vector<std::string>> runs;
  for (const unsigned threads : {1u, 2u, 7u}) {
    OrderedPipeline<std::string> pipeline(threads);
    EXPECT_EQ(pipeline.threads(), threads);
    std::vector<std::string> out;
    for (int i = 0; i < 200; ++i) {
      if (i % 10 == 0) {
        pipeline.push_ready("marker " + std::to_string(i));
      } else {
        pipeline.submit([i] {
          std::string text;
          for (int k = 0; k < (i * 37) % 500; ++k) text += static_cast<char>('a' + k % 26);
          return std::to_string(i) + ":" + text;
        });
      }
      while (pipeline.size() > threads + 1) out.push_back(pipeline.pop());
    }
    while (!pipeline.empty()) out.push_back(pipeline.pop());
    runs.push_back(out);
  }
  ASSERT_EQ(runs[0].size(), 200u);
  EXPECT_EQ(runs[0][10], "marker 10");
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(runs[0], runs[2]);
}

TEST(OrderedPipeline, AJobsExceptionComesOutAtItsPlace) {
  OrderedPipeline<int> pipeline(2);
  pipeline.submit([] { return 1; });
  pipeline.submit([]() -> int { throw std::runtime_error("job 2 failed"); });
  pipeline.submit([] { return 3; });
  EXPECT_EQ(pipeline.pop(), 1);
  try {
    pipeline.pop();
    FAIL() << "the job's exception did not reach the caller";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "job 2 failed");
  }
  EXPECT_EQ(pipeline.pop(), 3);
}

TEST(OrderedPipeline, VoidJobsAndDestructionWithJobsInFlight) {
  std::atomic<int> done{0};
  {
    OrderedPipeline<void> pipeline(2);
    for (int i = 0; i < 50; ++i) pipeline.submit([&done] { ++done; });
    pipeline.pop();  // the first is done
    EXPECT_GE(done.load(), 1);
  }  // the destructor waits for the other 49 and joins the threads
  EXPECT_EQ(done.load(), 50);
}

TEST(OrderedPipeline, ZeroThreadsMeansOnePerCore) {
  OrderedPipeline<int> pipeline(0);
  EXPECT_EQ(pipeline.threads(), threads_or_cores(0));
  EXPECT_GE(pipeline.threads(), 1u);
}

}  // namespace
}  // namespace nodetrace::base
