// test_text.cpp - intro.exe's command line parser and number printing
// (src/win32/text.cpp), compiled natively: the same freestanding source as
// in the exe. Random inputs come from a seeded generator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include "text.h"

namespace {

IntroOptions parse(const std::string& line) { return parse_command_line(line.c_str()); }

bool parse_number(const std::string& s, double* out) {
  return parse_seconds(s.data(), s.data() + s.size(), out);
}

std::string fixed(double v, int decimals) {
  char storage[64];
  TextBuffer b = text_buffer(storage, sizeof storage);
  append_fixed(b, v, decimals);
  return storage;
}

TEST(CommandLine, NullAndEmptyGiveDefaults) {
  for (const char* line :
       {(const char*)nullptr, "", "   ", "intro.exe", "\"C:\\a b\\intro.exe\""}) {
    IntroOptions o = parse_command_line(line);
    EXPECT_EQ(o.startSeconds, 0.0);
    EXPECT_FALSE(o.hold);
    EXPECT_FALSE(o.bench);
    EXPECT_FALSE(o.fullscreen);
    EXPECT_FALSE(o.once);
    EXPECT_FALSE(o.mute);
    EXPECT_FALSE(o.log);
  }
}

TEST(CommandLine, Options) {
  IntroOptions o = parse("intro.exe /t:12 /hold");
  EXPECT_EQ(o.startSeconds, 12.0);
  EXPECT_TRUE(o.hold);
  EXPECT_FALSE(o.bench);
  o = parse("intro.exe\t-BENCH  /T:44.5");
  EXPECT_EQ(o.startSeconds, 44.5);
  EXPECT_FALSE(o.hold);
  EXPECT_TRUE(o.bench);
  o = parse("intro.exe /t:-3.25");
  EXPECT_EQ(o.startSeconds, -3.25);
}

TEST(CommandLine, DemopartySwitches) {
  IntroOptions o = parse("intro.exe /f /once /mute /log");
  EXPECT_TRUE(o.fullscreen);
  EXPECT_TRUE(o.once);
  EXPECT_TRUE(o.mute);
  EXPECT_TRUE(o.log);
  EXPECT_FALSE(o.hold);
  EXPECT_FALSE(o.bench);
  EXPECT_EQ(o.startSeconds, 0.0);
  o = parse("intro.exe -F\t/ONCE /t:60");
  EXPECT_TRUE(o.fullscreen);
  EXPECT_TRUE(o.once);
  EXPECT_FALSE(o.mute);
  EXPECT_FALSE(o.log);
  EXPECT_EQ(o.startSeconds, 60.0);
  EXPECT_FALSE(o.scaled);
  o = parse("intro.exe /f -SCALED");
  EXPECT_TRUE(o.fullscreen);
  EXPECT_TRUE(o.scaled);
  // Near misses are unknown options, ignored.
  for (const char* j : {"/fs", "/full", "/f:", "f", "/oncex", "/on", "/muted", "/mut", "/logx",
                        "/lo", "/f/once", "/once/mute", "/scale", "/scaledx", "/f/scaled"}) {
    o = parse(std::string("intro.exe ") + j);
    EXPECT_FALSE(o.fullscreen) << j;
    EXPECT_FALSE(o.once) << j;
    EXPECT_FALSE(o.mute) << j;
    EXPECT_FALSE(o.log) << j;
    EXPECT_FALSE(o.scaled) << j;
  }
}

// /once ends at the end of the start's own 64-s loop: issue 12's
// /t:63.999999 played a whole extra loop (the start's float wrap rounds to
// 64 s, taken as 0 s of the next loop).
TEST(OnceEnd, StartsNearALoopsEndDoNotGainALoop) {
  const double justBelow64 = std::nextafter(64.0, 0.0);
  struct Case {
    double start, end;
  } cases[] = {
      {0.0, 64.0},         {60.0, 64.0},          {63.99, 64.0},      {63.9999, 64.0},
      {63.99999, 64.0},    {63.999999, 64.0},     {63.9999999, 64.0}, {justBelow64, 64.0},
      {64.0, 128.0},       {127.999999, 128.0},   {-3.0, 0.0},        {-1e-9, 0.0},
      {-64.0, 0.0},        {-64.000001, -64.0},   {1e9, 1e9 + 64.0}, // 1e9 = 64 x 15,625,000
      {-1e9, -1e9 + 64.0}, {999999999.99999, 1e9}};
  for (const Case& c : cases)
    EXPECT_EQ(once_end_seconds(c.start), c.end) << c.start;
  EXPECT_EQ(once_end_seconds(parse("intro.exe /t:63.999999 /once").startSeconds), 64.0);
}

// For any start: the end is a multiple of 64 s, after the start and at most
// a loop later (seeded; near-multiples of 64 and the whole allowed range).
TEST(OnceEnd, EndIsTheStartsLoopEnd) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> any(-kMaxStartSeconds, kMaxStartSeconds);
  std::uniform_int_distribution<int> loop(-1000, 1000), ulps(-4, 4);
  for (int i = 0; i < 100000; ++i) {
    double start = any(rng);
    if (i % 2) { // a few ulps around a loop boundary
      start = 64.0 * loop(rng);
      for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1)
        start = std::nextafter(start, k > 0 ? 1e300 : -1e300);
    }
    double end = once_end_seconds(start);
    ASSERT_GT(end, start) << start;
    ASSERT_LE(end - start, 64.0) << start;
    ASSERT_EQ(std::fmod(end, 64.0), 0.0) << start;
  }
}

TEST(CommandLine, ProgramNameIsSkipped) {
  // A quoted path may hold spaces and things that look like options.
  IntroOptions o = parse("\"C:\\demo /hold /t:5\\intro.exe\" /t:7");
  EXPECT_EQ(o.startSeconds, 7.0);
  EXPECT_FALSE(o.hold);
  o = parse("Z:\\x\\intro.exe/hold /bench"); // no blank: still the program name
  EXPECT_FALSE(o.hold);
  EXPECT_TRUE(o.bench);
  o = parse("\"unterminated /hold"); // a quote never closed: all program name
  EXPECT_FALSE(o.hold);
}

TEST(CommandLine, MalformedAndUnknownOptionsAreIgnored) {
  const char* junk[] = {"/t:",        "/t:abc", "/t:1e5",        "/t:1.2.3",
                        "/t:--5",     "/t:nan", "/t:inf",        "/t:+",
                        "/t:.",       "/t:12x", "/t: 5",         "/holdx",
                        "/benchmark", "hold",   "t:5",           "/",
                        "-",          "//",     "/t:1000000001", "/t:99999999999999999999999999",
                        "\"/t:5\""};
  for (const char* j : junk) {
    IntroOptions o = parse(std::string("intro.exe /t:12 ") + j);
    EXPECT_EQ(o.startSeconds, 12.0) << j;
    EXPECT_FALSE(o.bench) << j;
    // "/t: 5": the 5 is a separate unknown token.
    EXPECT_FALSE(o.hold) << j;
  }
}

TEST(CommandLine, LaterStartTimeWins) {
  EXPECT_EQ(parse("intro.exe /t:1 /t:2").startSeconds, 2.0);
  EXPECT_EQ(parse("intro.exe /t:1 /t:x").startSeconds, 1.0);
}

TEST(ParseSeconds, MatchesStrtodForShortDecimals) {
  std::mt19937_64 rng(20240601);
  // At most 15 significant digits: the range where the contract promises
  // the correctly rounded value. Up to 9 integer digits: up to and past 1e9.
  std::uniform_int_distribution<int> intDigits(0, 9), fracDigits(0, 6), digit(0, 9), coin(0, 1);
  for (int i = 0; i < 200000; ++i) {
    std::string s = coin(rng) ? "-" : "";
    int ni = intDigits(rng), nf = fracDigits(rng);
    if (ni + nf == 0) ni = 1;
    for (int k = 0; k < ni; ++k)
      s += char('0' + digit(rng));
    if (nf || coin(rng)) s += '.';
    for (int k = 0; k < nf; ++k)
      s += char('0' + digit(rng));
    double expected = std::strtod(s.c_str(), nullptr), got = -12345.0;
    bool ok = parse_number(s, &got);
    if (std::fabs(expected) > kMaxStartSeconds) {
      EXPECT_FALSE(ok) << s;
    } else {
      ASSERT_TRUE(ok) << s;
      ASSERT_EQ(got, expected) << s; // bit-exact: correctly rounded
    }
  }
}

TEST(ParseSeconds, LongDecimalsAreClose) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> digit(0, 9);
  for (int i = 0; i < 100000; ++i) {
    std::string s = std::to_string(1 + digit(rng)) + "."; // [1, 10]: relative = absolute scale
    for (int k = 0; k < 25; ++k)
      s += char('0' + digit(rng));
    double expected = std::strtod(s.c_str(), nullptr), got;
    ASSERT_TRUE(parse_number(s, &got)) << s;
    ASSERT_LE(std::fabs(got - expected), 4 * std::ldexp(1.0, -52) * 10) << s; // 4 ulps of 10
  }
}

TEST(ParseSeconds, EdgeCases) {
  double v = -1;
  EXPECT_TRUE(parse_number("1000000000", &v));
  EXPECT_EQ(v, 1e9);
  EXPECT_FALSE(parse_number("1000000000.5", &v));
  EXPECT_TRUE(parse_number("0000000000000000000000000000012", &v)); // leading zeros
  EXPECT_EQ(v, 12.0);
  EXPECT_TRUE(parse_number("0.0000000000000000000000000000001", &v)); // > 22 fraction digits
  EXPECT_NEAR(v, 1e-31, 1e-45);
  EXPECT_TRUE(parse_number("3.14159265358979323846264338327950288", &v)); // digits dropped
  EXPECT_NEAR(v, 3.141592653589793, 1e-15);
  EXPECT_TRUE(parse_number(".5", &v));
  EXPECT_EQ(v, 0.5);
  EXPECT_TRUE(parse_number("7.", &v));
  EXPECT_EQ(v, 7.0);
  EXPECT_TRUE(parse_number("-0", &v));
  EXPECT_EQ(v, 0.0);
  v = 99;
  EXPECT_FALSE(parse_seconds(nullptr, nullptr, &v));
  const char* s = "12";
  EXPECT_FALSE(parse_seconds(s + 2, s, &v)); // end before begin
  EXPECT_EQ(v, 99);
}

// Random bytes (NUL-terminated, any other value allowed): the parser returns,
// and whatever it returns is a valid option set.
TEST(CommandLine, RandomBytesAreSafe) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> len(0, 300), byte(1, 255), pick(0, 13);
  const char* pieces[] = {"/t:", "/hold", "/bench", " ",  "\t",    "\"",    "-",
                          ".",   "9",     "/T:1",   "/f", "/once", "/mute", "/log"};
  for (int i = 0; i < 100000; ++i) {
    std::string s;
    int n = len(rng);
    for (int k = 0; k < n; ++k) {
      if (pick(rng) < 3)
        s += pieces[pick(rng)];
      else
        s += char(byte(rng));
    }
    IntroOptions o = parse(s);
    ASSERT_TRUE(std::isfinite(o.startSeconds)) << s;
    ASSERT_LE(std::fabs(o.startSeconds), kMaxStartSeconds) << s;
  }
}

TEST(TextBuffer, FixedPoint) {
  EXPECT_EQ(fixed(0.0, 2), "0.00");
  EXPECT_EQ(fixed(4.6, 2), "4.60");
  EXPECT_EQ(fixed(6.125, 2), "6.13");  // exact half: rounds up
  EXPECT_EQ(fixed(9.999, 2), "10.00"); // rounding carries into the integer part
  EXPECT_EQ(fixed(123.0, 0), "123");
  EXPECT_EQ(fixed(-2.5, 1), "-2.5");
  EXPECT_EQ(fixed(-0.001, 2), "0.00"); // no "-0.00"
  EXPECT_EQ(fixed(1e14 + 0.25, 2), "100000000000000.25");
  EXPECT_EQ(fixed(1e15, 2), "?");
  EXPECT_EQ(fixed(NAN, 2), "?");
  EXPECT_EQ(fixed(INFINITY, 2), "?");
  EXPECT_EQ(fixed(0.5, 99), "0.500000000"); // decimals clamped to 9
}

TEST(TextBuffer, NeverOverflows) {
  char storage[8];
  for (char& c : storage)
    c = 'X';
  TextBuffer b = text_buffer(storage, 5);
  append(b, "abcdefgh");
  append_uint(b, 18446744073709551615ull);
  EXPECT_STREQ(storage, "abcd");
  EXPECT_EQ(text_length(b), 4);
  EXPECT_EQ(storage[5], 'X');
  char big[32];
  TextBuffer u = text_buffer(big, sizeof big);
  append_uint(u, 18446744073709551615ull);
  EXPECT_STREQ(big, "18446744073709551615");
}

} // namespace
