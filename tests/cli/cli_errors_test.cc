// The command line's contract for bad input (SPEC section 4): exit code 2 and exactly one line on
// stderr naming the file, line or field and the problem.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::runSlamcmp;
using test::TempDir;
using test::writeText;

int lineCount(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

void expectBadInput(const std::string& args, const std::string& must_mention) {
  const auto r = runSlamcmp(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << args << "\nstderr: " << r.err;
  EXPECT_NE(r.err.find(must_mention), std::string::npos)
      << args << "\nstderr should mention '" << must_mention << "': " << r.err;
}

TEST(Cli, HelpListsSubcommands) {
  const auto r = runSlamcmp("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("synth"), std::string::npos);
  EXPECT_NE(r.out.find("run"), std::string::npos);
}

TEST(Cli, NoSubcommandIsUsageError) { expectBadInput("", "subcommand"); }

// Found by the reliability probe: a misspelt subcommand got "A subcommand is required", not naming it.
TEST(Cli, UnknownSubcommandIsNamedWithTheKnownOnes) {
  expectBadInput("frobnicate --out x",
                 "unknown subcommand 'frobnicate' (known: synth, run, compare, reproduce, eval, calibrate)");
}

TEST(Cli, UnknownOptionIsUsageError) { expectBadInput("run --backend cslam --sequence x --frobnicate 3", "frobnicate"); }

TEST(Cli, RunOnMissingSequence) {
  TempDir tmp;
  expectBadInput("run --backend cslam --sequence " + tmp.file("nope") + " --out " + tmp.file("o"),
                 tmp.file("nope"));
}

TEST(Cli, RunOnEmptyRgbList) {
  TempDir tmp;
  writeText(tmp.file("rgb.txt"), "# nothing here\n");
  expectBadInput("run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                 "rgb.txt");
}

TEST(Cli, RunOnRgbListNamingMissingImage) {
  TempDir tmp;
  writeText(tmp.file("rgb.txt"), "0.0 missing.png\n");
  expectBadInput("run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                 "rgb.txt:1");
}

TEST(Cli, EmptyFolderIsRefused) {
  TempDir tmp;
  expectBadInput("run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                 "no rgb.txt and no image files");
}

}  // namespace
}  // namespace slamcmp
