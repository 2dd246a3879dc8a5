// text.cpp - command line parsing and number printing without the C runtime.
#include "text.h"

namespace {

typedef unsigned long long u64;

// Significant digits kept in the mantissa (10^17 < 2^63). A mantissa below
// 2^53 (every one of 15 digits) converts to double exactly; a longer one is
// rounded once more, a few ulps at most.
constexpr int kMaxMantissaDigits = 17;
// 10^k is exact in a double for k <= 22 (5^22 < 2^53), so mantissa / 10^k is
// one correctly rounded division.
constexpr int kMaxExactPow10 = 22;
// append_fixed prints |v| < 1e15 and at most 9 decimals: v * 10^9 < 1e24
// would not fit u64, so the integer and fraction parts are printed apart.
constexpr double kMaxFixed = 1e15;
constexpr int kMaxDecimals = 9;

bool is_space(char c) { return c == ' ' || c == '\t'; }
char lower(char c) { return c >= 'A' && c <= 'Z' ? (char)(c - 'A' + 'a') : c; }

// True when [begin, end) equals the lower-case word `w` ignoring case.
bool word_is(const char* begin, const char* end, const char* w) {
  for (; begin < end; ++begin, ++w)
    if (*w == '\0' || lower(*begin) != *w) return false;
  return *w == '\0';
}

// True when [begin, end) starts with the lower-case `prefix` ignoring case.
bool starts_with(const char* begin, const char* end, const char* prefix) {
  for (; *prefix; ++begin, ++prefix)
    if (begin == end || lower(*begin) != *prefix) return false;
  return true;
}

double pow10(int k) {
  double p = 1.0;
  for (int i = 0; i < k; ++i)
    p *= 10.0;
  return p;
}

} // namespace

bool parse_seconds(const char* begin, const char* end, double* out) {
  if (!begin || !end || begin >= end) return false;
  const char* p = begin;
  bool negative = false;
  if (*p == '+' || *p == '-') negative = *p++ == '-';
  u64 mantissa = 0;
  int significant = 0, fractionDigits = 0, digits = 0;
  bool seenPoint = false;
  for (; p < end; ++p) {
    char c = *p;
    if (c == '.' && !seenPoint) {
      seenPoint = true;
      continue;
    }
    if (c < '0' || c > '9') return false;
    ++digits;
    if (significant == 0 && c == '0') {
      if (seenPoint) ++fractionDigits; // leading zeros of the fraction still scale
      continue;
    }
    if (significant < kMaxMantissaDigits) {
      mantissa = mantissa * 10 + (u64)(c - '0');
      ++significant;
      if (seenPoint) ++fractionDigits;
    } else if (!seenPoint) {
      return false; // more than 17 integer digits: far above kMaxStartSeconds
    }
    // Further fraction digits beyond 17 significant ones are dropped (truncation).
  }
  if (digits == 0) return false;
  // A fraction with more than 22 digits (leading zeros included) is scaled in
  // steps of 10^22; the value is then below 1e-5 or has dropped digits anyway.
  double value = (double)(long long)mantissa; // < 10^17 < 2^63: signed, one instruction
  for (int k; fractionDigits > 0; fractionDigits -= k) {
    k = fractionDigits < kMaxExactPow10 ? fractionDigits : kMaxExactPow10;
    value /= pow10(k);
  }
  if (value > kMaxStartSeconds) return false;
  *out = negative ? -value : value;
  return true;
}

IntroOptions parse_command_line(const char* line) {
  IntroOptions o{0.0, false, false, false, false, false, false, false};
  if (!line) return o;
  const char* p = line;
  while (is_space(*p))
    ++p;
  // The program name: quoted (may hold spaces) or up to the first blank.
  if (*p == '"') {
    ++p;
    while (*p && *p != '"')
      ++p;
    if (*p) ++p;
  }
  while (*p && !is_space(*p))
    ++p;
  for (;;) {
    while (is_space(*p))
      ++p;
    if (!*p) return o;
    const char* begin = p;
    while (*p && !is_space(*p))
      ++p;
    if (*begin != '/' && *begin != '-') continue;
    const char* name = begin + 1;
    if (word_is(name, p, "hold")) {
      o.hold = true;
    } else if (RT64K_BENCH && word_is(name, p, "bench")) {
      o.bench = true;
    } else if (RT64K_FULLSCREEN && word_is(name, p, "f")) {
      o.fullscreen = true;
    } else if (RT64K_FULLSCREEN && word_is(name, p, "scaled")) {
      o.scaled = true;
    } else if (RT64K_ONCE && word_is(name, p, "once")) {
      o.once = true;
    } else if (RT64K_MUTE && word_is(name, p, "mute")) {
      o.mute = true;
    } else if (RT64K_LOG && word_is(name, p, "log")) {
      o.log = true;
    } else if (starts_with(name, p, "t:")) {
      double t;
      if (parse_seconds(name + 2, p, &t)) o.startSeconds = t;
    }
  }
}

double once_end_seconds(double startSeconds) {
  double loops = startSeconds / kOnceLoopSeconds; // exact: a power of two
  long long n = (long long)loops;                 // |loops| < 2^63 for |start| <= 1e9
  if ((double)n > loops) --n;                     // floor for negatives
  return ((double)n + 1.0) * kOnceLoopSeconds;
}

TextBuffer text_buffer(char* storage, int size) {
  TextBuffer b{storage, storage + size, storage};
  *storage = '\0';
  return b;
}

void append(TextBuffer& b, const char* s) {
  while (*s && b.at + 1 < b.end)
    *b.at++ = *s++;
  *b.at = '\0';
}

namespace {

// One character (what append of a one-character string does).
void append_char(TextBuffer& b, char c) {
  if (b.at + 1 < b.end) *b.at++ = c;
  *b.at = '\0';
}

} // namespace

void append_uint(TextBuffer& b, unsigned long long v) {
  char digits[24]; // 2^64 has 20 decimal digits
  int n = 0;
  do {
    digits[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v);
  while (n)
    append_char(b, digits[--n]);
}

void append_fixed(TextBuffer& b, double v, int decimals) {
  if (!(v > -kMaxFixed && v < kMaxFixed)) { // NaN fails both comparisons
    append(b, "?");
    return;
  }
  if (decimals < 0) decimals = 0;
  if (decimals > kMaxDecimals) decimals = kMaxDecimals;
  // Signed 64-bit integers: |v| < 1e15 and scale <= 1e9 fit, and their
  // conversions to and from double are single instructions (unsigned ones
  // are not), with the same values.
  long long scale = 1;
  for (int i = 0; i < decimals; ++i)
    scale *= 10;
  if (v < 0) {
    v = -v;
    // Only print the sign when something non-zero follows it.
    if (v * (double)scale >= 0.5) append_char(b, '-');
  }
  long long whole = (long long)v;
  long long frac = (long long)((v - (double)whole) * (double)scale + 0.5);
  if (frac >= scale) { // rounding carried into the integer part
    frac -= scale;
    ++whole;
  }
  append_uint(b, whole);
  if (decimals == 0) return;
  append_char(b, '.');
  for (long long s = scale / 10; s > 0; s /= 10)
    append_char(b, (char)('0' + frac / s % 10));
}

int text_length(const TextBuffer& b) { return (int)(b.at - b.begin); }
