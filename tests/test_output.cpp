// test_output.cpp - the tool's output rule (tools/output.h) and its error
// lines, in-process: temporaries, commit and abort, modes, identity checks,
// path checks, printable(); the gnuplot script (tools/plot.h).
#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "output.h"
#include "plot.h"

namespace {

// A fresh folder, removed with its files at the end.
struct TempDir {
  std::string path;
  TempDir() {
    char tmpl[] = "/tmp/rt64k-output-test-XXXXXX";
    path = mkdtemp(tmpl);
  }
  ~TempDir() {
    for (const std::string& n : names())
      unlink((path + "/" + n).c_str());
    rmdir(path.c_str());
  }
  std::set<std::string> names() const {
    std::set<std::string> out;
    if (DIR* d = opendir(path.c_str())) {
      while (dirent* e = readdir(d))
        if (std::string(e->d_name) != "." && std::string(e->d_name) != "..") out.insert(e->d_name);
      closedir(d);
    }
    return out;
  }
  std::string operator/(const std::string& name) const { return path + "/" + name; }
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}
std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
// The one name in `dir` that is not `except`.
std::string other_name(const TempDir& dir, const std::string& except) {
  std::string found;
  for (const std::string& n : dir.names())
    if (n != except) found = n;
  return found;
}

TEST(Printable, EscapesControlsAndBadBytesKeepsUtf8) {
  EXPECT_EQ(printable("plain text.png"), "plain text.png");
  EXPECT_EQ(printable("a\nb"), "a\\nb");
  EXPECT_EQ(printable("a\r\tb"), "a\\r\\tb");
  EXPECT_EQ(printable("back\\slash"), "back\\\\slash");
  EXPECT_EQ(printable("\x1b[31mred"), "\\x1b[31mred");
  EXPECT_EQ(printable(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(printable("del\x7f"), "del\\x7f");
  EXPECT_EQ(printable("caf\xc3\xa9"), "caf\xc3\xa9");           // U+00E9 kept
  EXPECT_EQ(printable("\xe2\x82\xac"), "\xe2\x82\xac");         // U+20AC kept
  EXPECT_EQ(printable("\xf0\x9f\x8e\xb5"), "\xf0\x9f\x8e\xb5"); // U+1F3B5 kept
  EXPECT_EQ(printable("\xc2\x9b"
                      "2J"),
            "\\xc2\\x9b"
            "2J");                                                  // C1 CSI escaped
  EXPECT_EQ(printable("\xc2\xa0"), "\xc2\xa0");                     // U+00A0, first after C1
  EXPECT_EQ(printable("\xff"), "\\xff");                            // never UTF-8
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");                   // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");          // surrogate
  EXPECT_EQ(printable("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80"); // past U+10FFFF
  EXPECT_EQ(printable("\xe2\x82"), "\\xe2\\x82");                   // cut short
  EXPECT_EQ(printable(""), "");
}

TEST(OutputFile, CommitReplacesWholeAndLeavesOnlyTheTarget) {
  TempDir dir;
  write_text(dir / "out.txt", "old contents");
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open(dir / "out.txt", error)) << error;
  // While open: the old file untouched, one hidden temporary beside it.
  EXPECT_EQ(read_text(dir / "out.txt"), "old contents");
  ASSERT_EQ(dir.names().size(), 2u);
  std::string temp = other_name(dir, "out.txt");
  EXPECT_EQ(temp.rfind(".out.txt.rt64k-", 0), 0u) << temp;
  EXPECT_EQ(temp.size(), std::string(".out.txt.rt64k-").size() + 8);
  std::fputs("new contents, longer than the old", out.stream());
  ASSERT_TRUE(out.commit(error)) << error;
  EXPECT_EQ(read_text(dir / "out.txt"), "new contents, longer than the old");
  EXPECT_EQ(dir.names(), std::set<std::string>{"out.txt"});
}

TEST(OutputFile, AbortLeavesTheOldFileAndNoTemporary) {
  TempDir dir;
  write_text(dir / "keep.png", "old");
  {
    OutputFile out;
    std::string error;
    ASSERT_TRUE(out.open(dir / "keep.png", error)) << error;
    std::fputs("half a file", out.stream());
    std::fflush(out.stream());
  } // destroyed without commit
  EXPECT_EQ(read_text(dir / "keep.png"), "old");
  EXPECT_EQ(dir.names(), std::set<std::string>{"keep.png"});
}

TEST(OutputFile, NewFileAppearsOnlyAtCommit) {
  TempDir dir;
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open(dir / "new.csv", error)) << error;
  std::fputs("a,b\n", out.stream());
  EXPECT_EQ(dir.names().count("new.csv"), 0u);
  ASSERT_TRUE(out.commit(error)) << error;
  EXPECT_EQ(read_text(dir / "new.csv"), "a,b\n");
}

TEST(OutputFile, ReplacementKeepsTheOldMode) {
  TempDir dir;
  write_text(dir / "m.png", "old");
  ASSERT_EQ(chmod((dir / "m.png").c_str(), 0640), 0);
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open(dir / "m.png", error)) << error;
  std::fputs("new", out.stream());
  ASSERT_TRUE(out.commit(error)) << error;
  struct stat st;
  ASSERT_EQ(stat((dir / "m.png").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
}

TEST(OutputFile, NeverRemovesAFileItDidNotCreate) {
  // Someone swaps another file in under the temporary's name: abort must
  // leave that file alone (it checks device and inode before unlinking).
  TempDir dir;
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open(dir / "t.png", error)) << error;
  std::string temp = other_name(dir, "");
  ASSERT_FALSE(temp.empty());
  write_text(dir / "theirs", "not rt64k's");
  ASSERT_EQ(rename((dir / "theirs").c_str(), (dir / temp).c_str()), 0);
  out.abort();
  EXPECT_EQ(read_text(dir / temp), "not rt64k's");
  EXPECT_EQ(dir.names(), std::set<std::string>{temp});
}

TEST(OutputFile, LongestNameStillGetsATemporary) {
  TempDir dir;
  std::string name(255, 'n'); // NAME_MAX
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open(dir / name, error)) << error;
  EXPECT_LE(other_name(dir, name).size(), 255u);
  std::fputs("x", out.stream());
  ASSERT_TRUE(out.commit(error)) << error;
  EXPECT_EQ(read_text(dir / name), "x");
  EXPECT_EQ(dir.names().size(), 1u);
}

TEST(OutputFile, DeviceIsWrittenInPlaceAndFailuresReported) {
  struct stat before;
  if (stat("/dev/full", &before) != 0 || !S_ISCHR(before.st_mode)) GTEST_SKIP() << "no /dev/full";
  OutputFile out;
  std::string error;
  ASSERT_TRUE(out.open("/dev/full", error)) << error;
  std::fputs("anything", out.stream());
  EXPECT_FALSE(out.commit(error));
  EXPECT_EQ(error, "cannot write '/dev/full': No space left on device");
  struct stat after;
  ASSERT_EQ(stat("/dev/full", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode));
  EXPECT_EQ(after.st_rdev, before.st_rdev);
  ASSERT_TRUE(out.open("/dev/null", error)) << error;
  std::fputs("anything", out.stream());
  EXPECT_TRUE(out.commit(error)) << error;
}

TEST(CheckOutputPath, NamesTheCause) {
  TempDir dir;
  std::string error;
  EXPECT_TRUE(check_output_path(dir / "fine.png", error)) << error;
  EXPECT_FALSE(check_output_path("", error));
  EXPECT_EQ(error, "the output path is empty");
  EXPECT_FALSE(check_output_path(dir.path, error));
  EXPECT_EQ(error, "cannot write '" + dir.path + "': it is a folder");
  EXPECT_FALSE(check_output_path(dir.path + "/", error));
  EXPECT_NE(error.find("names a folder"), std::string::npos) << error;
  EXPECT_FALSE(check_output_path(dir / "missing/x.png", error));
  EXPECT_EQ(error, "cannot write '" + (dir / "missing/x.png") + "': folder '" + (dir / "missing") +
                       "': No such file or directory");
  ASSERT_EQ(symlink((dir / "nowhere").c_str(), (dir / "dangling").c_str()), 0);
  EXPECT_FALSE(check_output_path(dir / "dangling", error));
  EXPECT_NE(error.find("symbolic link to nothing"), std::string::npos) << error;
  write_text(dir / "file", "");
  EXPECT_FALSE(check_output_path(dir / "file/x.png", error));
  EXPECT_NE(error.find("Not a directory"), std::string::npos) << error;
  EXPECT_TRUE(check_output_path("/dev/null", error)) << error;
  // Checking creates nothing.
  EXPECT_EQ(dir.names(), (std::set<std::string>{"dangling", "file"}));
}

TEST(PlotScript, HoldsNoPathAndOnlyPlainLabels) {
  std::vector<PlotPoint> points = {{"full", 59.79, INFINITY, INFINITY, 142.9},
                                   {"adaptive8", 12.51, 41.19, 45.40, 36.80}};
  std::string script;
  ASSERT_TRUE(plot_script(points, PlotTitle{800, 600, 256, 2}, script));
  EXPECT_EQ(script.find("set output"), std::string::npos);
  EXPECT_NE(script.find("\"full\" 59.7900 99.000 99.000 142.9000 101.50\n"), std::string::npos)
      << script;
  EXPECT_NE(script.find("\"adaptive8\" 12.5100 41.190 45.400 36.8000 47.90\n"), std::string::npos);
  EXPECT_NE(script.find("800x600 frame"), std::string::npos);
  // Every quote in the script is ours: a fixed count.
  EXPECT_EQ(std::count(script.begin(), script.end(), '\''), 14);
  // Two modes at nearly the same spot: the second's label under its min-PSNR point.
  std::vector<PlotPoint> same = {{"adaptive8", 5.17, 42.22, 45.56, 10.48},
                                 {"adaptive16", 5.16, 42.22, 45.56, 10.32},
                                 {"adaptive4", 7.76, 46.10, 47.92, 14.38},
                                 {"slow", 5.17, 30.0, 35.0, 9.0}};
  ASSERT_TRUE(plot_script(same, PlotTitle{800, 600, 256, 2}, script));
  EXPECT_NE(script.find("\"adaptive8\" 5.1700 42.220 45.560 10.4800 48.06\n"), std::string::npos)
      << script;
  EXPECT_NE(script.find("\"adaptive16\" 5.1600 42.220 45.560 10.3200 39.72\n"), std::string::npos);
  EXPECT_NE(script.find("\"adaptive4\" 7.7600 46.100 47.920 14.3800 50.42\n"), std::string::npos);
  EXPECT_NE(script.find("\"slow\" 5.1700 30.000 35.000 9.0000 37.50\n"), std::string::npos);
  points[0].label = "a'b";
  EXPECT_FALSE(plot_script(points, PlotTitle{800, 600, 256, 2}, script));
  points[0].label = "x\ny";
  EXPECT_FALSE(plot_script(points, PlotTitle{800, 600, 256, 2}, script));
}

} // namespace
