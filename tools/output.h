// output.h - every file the tool writes appears whole or not at all.
//
// The rule (docs/outputs.md has the reasons and the tests):
// - A regular file (new or existing) is written to a temporary file created
//   exclusively, with a unique name, in the same folder (".NAME.rt64k-XXXXXXXX"),
//   and renamed over the target only after every write, fsync and close
//   succeeded. An existing file is never opened for writing, so a failed or
//   interrupted run leaves it byte for byte as it was. A symbolic link is
//   followed to the file it names, which is then replaced (the link stays).
// - A character device or a FIFO (/dev/null, /dev/stdout on a pipe, a named
//   pipe) is a stream, not a file: it is written in place, every write
//   checked; it cannot be atomic, and it is never created, truncated, renamed
//   or removed. Block devices, sockets and folders are refused.
// - Nothing the tool did not create is ever removed: a temporary is removed
//   by its folder descriptor and name only while it is still the file the
//   tool created (same device and inode).
// - SIGINT, SIGTERM, SIGHUP and SIGQUIT (unless ignored when the tool
//   started) remove the live temporaries, then end the process with the
//   signal. SIGXFSZ is ignored, so a write over `ulimit -f` fails with EFBIG
//   and is reported. SIGKILL cannot be caught: it leaves the old file intact
//   and a temporary behind.
// - Tests: with RT64K_TEST_STOP_IN_WRITE set to an output's path (as given),
//   the tool stops itself (SIGSTOP) once that output's temporary holds data
//   and before it replaces the target, so a test can kill it mid-write.
#pragma once
#include <cstdio>
#include <string>

// `text` on one line, safe for a terminal: control characters, DEL, C1
// controls, backslash and bytes that are not UTF-8 become escapes (\n, \t, \r,
// \\, \xHH); printable UTF-8 is kept.
std::string printable(const std::string& text);

// Prints "rt64k: MESSAGE" (made printable) as one line on stderr.
void report_error(const std::string& message);

// Installs the signal handlers described above. Call once, first thing in main.
void install_output_signal_handlers();

// Checks, before any long work, that `path` can be written under the rule
// above: its folder exists and is writable, it is not a folder, a block
// device, a socket or a dangling link, an existing file is writable. Returns
// false with a one-line `error` naming the cause.
bool check_output_path(const std::string& path, std::string& error);

// One output, written whole or not at all.
class OutputFile {
public:
  OutputFile() = default;
  ~OutputFile() { abort(); }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Creates the temporary (or opens the stream). False with `error` if not.
  bool open(const std::string& path, std::string& error);
  // Every write goes through this stream; the first failing write is kept
  // (its errno) and later ones are dropped.
  std::FILE* stream() const { return stream_; }
  // The descriptor behind stream() (for a child process's stdout).
  int fd() const { return fd_; }
  // A write has failed already.
  bool failed() const { return errno_ != 0; }
  // Flushes, fsyncs, closes and renames over the target. False with `error`
  // (the temporary removed, the target untouched) if any step failed.
  bool commit(std::string& error);
  // Closes and removes the temporary; the target is untouched.
  void abort();

  // Internal: the stream's write and close functions.
  long write_bytes(const char* data, size_t size);
  int close_fd();

private:
  bool fail(const std::string& what, int err, std::string& error);

  std::string path_;     // as given
  std::string base_;     // the target's name in dirFd_
  std::string tempName_; // in dirFd_; empty for a stream
  int dirFd_ = -1, fd_ = -1;
  int slot_ = -1; // entry in the signal handler's list
  std::FILE* stream_ = nullptr;
  int errno_ = 0;            // first failed write
  bool stopPending_ = false; // RT64K_TEST_STOP_IN_WRITE names this path (tests)
};

// Flushes and closes stdout. On failure prints one line naming the cause and
// returns false (the caller exits 2).
bool finish_stdout();
