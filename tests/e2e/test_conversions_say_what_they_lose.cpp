// tracetool's conversions and reads, as a new user meets them: the output's
// record form follows its name as in `tracer -o` (a contradicting --records
// is an error), nothing is dropped without a warning, binary is not written
// to a terminal, a .bin name is read as binary, and info counts animation
// frames as verify does.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

class Conversions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    for (const std::string& options : {"-o " + shell_quoted(kd()), "--accel bvh2 -o " + shell_quoted(bvh()),
                                      "--sample-rows 1/4 -o " + shell_quoted(sampled())}) {
      const auto rendered = run_command(shell_quoted(program("tracer")) +
                                        " render mountain --width 64 --height 48 -q --high-size 1k " + options);
      ASSERT_EQ(rendered.exit_code, 0) << options << ": " << rendered.err;
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path kd() { return *dir_ / "t.din.zst"; }
  static fs::path bvh() { return *dir_ / "b.xdin.zst"; }
  static fs::path sampled() { return *dir_ / "s.din.zst"; }
  static fs::path out(const std::string& name) { return *dir_ / name; }
  static CommandResult tracetool(const std::string& arguments) {
    return run_command(shell_quoted(program("tracetool")) + " " + arguments);
  }
  static std::string form_of(const fs::path& path) {
    return std::string(formats::form_name(formats::TraceReader::open(path.string())->form()));
  }

 private:
  static TempDir* dir_;
};

TempDir* Conversions::dir_ = nullptr;

TEST_F(Conversions, OutputFormFollowsTheNameAsInTracer) {
  ASSERT_EQ(tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("a.xdin.zst"))).exit_code, 0);
  EXPECT_EQ(form_of(out("a.xdin.zst")), "xdin");
  ASSERT_EQ(tracetool("convert " + shell_quoted(bvh()) + " " + shell_quoted(out("b2.din.zst"))).exit_code, 0);
  EXPECT_EQ(form_of(out("b2.din.zst")), "din");
  ASSERT_EQ(tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("a.bin"))).exit_code, 0);
  const auto records = formats::TraceReader::open(kd().string())->trailer()->totals.at("records").get<std::uint64_t>();
  EXPECT_EQ(fs::file_size(out("a.bin")), 8 * records);  // Dinero binary, not din text
  // A name without a form keeps the input's.
  ASSERT_EQ(tracetool("convert " + shell_quoted(bvh()) + " " + shell_quoted(out("b3.zst"))).exit_code, 0);
  EXPECT_EQ(form_of(out("b3.zst")), "xdin");
}

TEST_F(Conversions, RecordsOptionThatContradictsTheNameIsAUsageError) {
  const auto converted =
      tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("c.xdin.zst")) + " --records din");
  EXPECT_EQ(converted.exit_code, 2);
  EXPECT_NE(converted.err.find("the name says xdin records, --records says din"), std::string::npos) << converted.err;
  EXPECT_FALSE(fs::exists(out("c.xdin.zst")));
  const auto rendered = run_command(shell_quoted(program("tracer")) + " render mountain --width 8 --height 6 -q -o " +
                                    shell_quoted(out("r.xdin.zst")) + " --records din");
  EXPECT_EQ(rendered.exit_code, 2);
  EXPECT_NE(rendered.err.find("the name says xdin records, --records says din"), std::string::npos) << rendered.err;
}

TEST_F(Conversions, BvhNodeSizesLostToDinAreWarnedOf) {
  const auto result = tracetool("convert " + shell_quoted(bvh()) + " " + shell_quoted(out("d.din.zst")));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("had sizes other than 4 bytes, which din records cannot carry"), std::string::npos)
      << result.err;
  const auto kept = tracetool("convert " + shell_quoted(bvh()) + " " + shell_quoted(out("d.xdin.zst")));
  EXPECT_EQ(kept.err, "");
}

TEST_F(Conversions, TagsLostToBinaryAreWarnedOfAndCachesimSaysWhySplitCannotRun) {
  const auto result = tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("e.bin.zst")));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("lost their tags (node levels, p, t): Dinero binary records carry none"),
            std::string::npos)
      << result.err;
  const auto split = run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(out("e.bin.zst")) +
                                 " --scheme split");
  EXPECT_EQ(split.exit_code, 2);
  EXPECT_NE(split.err.find("Dinero binary records carry no tag"), std::string::npos) << split.err;
  EXPECT_EQ(split.err.find("--tags-are-levels"), std::string::npos) << split.err;
  const auto cat = tracetool("cat --records binary " + shell_quoted(kd()) + " > /dev/null");
  EXPECT_EQ(cat.exit_code, 0) << cat.err;
  EXPECT_NE(cat.err.find("lost their tags"), std::string::npos) << cat.err;
}

TEST_F(Conversions, RowSamplingLostToPlainRecordsIsWarnedOf) {
  const auto result = tracetool("convert " + shell_quoted(sampled()) + " " + shell_quoted(out("f.din")));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("plain records keep no header: lost its row sampling"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("animation-frame marker"), std::string::npos) << result.err;
  const auto container = tracetool("convert " + shell_quoted(sampled()) + " " + shell_quoted(out("f.din.zst")));
  EXPECT_EQ(container.err, "");
}

// Runs `command` with its standard output on a terminal (util-linux script).
CommandResult on_a_terminal(const std::string& command) {
  return run_command("script -qec " + shell_quoted(command) + " /dev/null");
}

TEST_F(Conversions, BinaryIsNotWrittenToATerminal) {
  if (run_command("command -v script").exit_code != 0) GTEST_SKIP() << "no script(1) to make a terminal";
  const std::string tool = program("tracetool").string() + " ";
  for (const std::string& arguments : {"convert " + kd().string() + " -", "cat --records binary " + kd().string()}) {
    const auto result = on_a_terminal(tool + arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments << ": " << result.out;
    EXPECT_NE(result.out.find("to a terminal; redirect standard output"), std::string::npos) << result.out;
  }
  const auto text = on_a_terminal(tool + "cat " + kd().string() + " | head -1");
  EXPECT_EQ(text.exit_code, 0) << text.out;
}

// tracetool convert --archive ran for seconds on a terminal without a word.
TEST_F(Conversions, ConvertShowsProgressOnATerminal) {
  if (run_command("command -v script").exit_code != 0) GTEST_SKIP() << "no script(1) to make a terminal";
  const auto result = on_a_terminal(program("tracetool").string() + " convert " + kd().string() + " " +
                                    out("p.din.zst").string());
  EXPECT_EQ(result.exit_code, 0) << result.out;
  EXPECT_NE(result.out.find("converting " + kd().string() + ": "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find(" records ("), std::string::npos) << result.out;  // of the trailer's total
}

TEST_F(Conversions, BinByNameIsReadAsBinary) {
  ASSERT_EQ(tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("g.bin"))).exit_code, 0);
  const auto info = tracetool("info " + shell_quoted(out("g.bin")) + " --format json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out).at("records_form"), "binary");
  const auto run = run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(out("g.bin")));
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

// Issue 52 item 10: binary records read as text (no .bin name, a pipe) are
// told apart by their NUL bytes, and each program names its own option for
// them; cachesim dinero no longer suggests -informat d (din text) for them.
TEST_F(Conversions, BinaryReadAsTextIsToldToNameItsForm) {
  ASSERT_EQ(tracetool("convert " + shell_quoted(kd()) + " " + shell_quoted(out("sf.bin"))).exit_code, 0);
  const std::string bin = shell_quoted(out("sf.bin"));
  const std::string cachesim = shell_quoted(program("cachesim"));
  const std::string hint = "(the record holds a NUL byte, so the input is not text: for Dinero binary records give ";
  for (const std::string& command :
       {"cat " + bin + " | " + cachesim + " run - --size 1k", "cat " + bin + " | zstd -qc | " + cachesim + " run -",
        "cat " + bin + " | " + shell_quoted(program("tracetool")) + " verify -"}) {
    const auto result = run_command(command);
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_NE(result.err.find("<stdin>: record 1: non hex digit (code 0x0) in label " + hint + "--informat binary)"),
              std::string::npos)
        << command << ": " << result.err;
  }
  // Dinero's default -informat D reads a .bin name as extended din too.
  for (const std::string& command : {cachesim + " dinero -l1-usize 1k -l1-ubsize 8 " + bin,
                                     "cat " + bin + " | " + cachesim + " dinero -l1-usize 1k -l1-ubsize 8 -informat d"}) {
    const auto result = run_command(command);
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_NE(result.err.find(hint + "-informat b)"), std::string::npos) << command << ": " << result.err;
    EXPECT_EQ(result.err.find("-informat d"), std::string::npos) << command << ": " << result.err;
  }
  // Text that is only wrong gets no such hint.
  const auto text = run_command(cachesim + " run - --size 1k", "0 10g\n");
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_EQ(text.err, "cachesim run: <stdin>: record 1: non hex digit (code 0x67) in address\n");
}

TEST_F(Conversions, InfoCountsAnimationFramesAsVerifyDoes) {
  ASSERT_EQ(tracetool("cat " + shell_quoted(kd()) + " > " + shell_quoted(out("h.din"))).exit_code, 0);
  const auto verify = tracetool("verify " + shell_quoted(out("h.din")));
  EXPECT_NE(verify.out.find(", 1 animation frame "), std::string::npos) << verify.out;
  const auto info = tracetool("info " + shell_quoted(out("h.din")) + " --format json");
  EXPECT_EQ(nlohmann::json::parse(info.out).at("animation_frames"), 1) << info.out;
  const auto table = tracetool("info " + shell_quoted(out("h.din")));
  EXPECT_NE(table.out.find("animation frames     1\n"), std::string::npos) << table.out;
}

}  // namespace
}  // namespace nodetrace::testing
