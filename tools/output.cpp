// output.cpp - whole-or-nothing outputs, printable messages, checked stdout.
#include "output.h"

#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace {

// ---- the temporaries the signal handler removes --------------------------
//
// A slot is filled (folder descriptor, name, device, inode) before `live` is
// set, and `live` is cleared before the slot is reused; the handler reads only
// live slots. A temporary is removed only while its name still holds the file
// the tool created (same device and inode), so nothing else is ever removed.
constexpr int kMaxTemporaries = 8;
struct TempSlot {
  std::atomic<int> live;
  int dirFd;
  dev_t dev;
  ino_t ino;
  char name[NAME_MAX + 1];
};
TempSlot g_slots[kMaxTemporaries];
std::atomic<int> g_creating{0}; // temporaries being created and not yet in a slot

constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

void remove_slot(TempSlot& s) {
  struct stat st;
  if (fstatat(s.dirFd, s.name, &st, AT_SYMLINK_NOFOLLOW) == 0 && st.st_dev == s.dev &&
      st.st_ino == s.ino)
    unlinkat(s.dirFd, s.name, 0);
}

extern "C" void on_cleanup_signal(int sig) {
  int savedErrno = errno;
  // A temporary being created in another thread (whose signals are blocked
  // meanwhile) is in its slot within microseconds: wait for it, at most 1 s.
  for (int i = 0; i < 1000 && g_creating.load() != 0; ++i) {
    struct timespec ms = {0, 1000000};
    nanosleep(&ms, nullptr);
  }
  for (TempSlot& s : g_slots)
    if (s.live.load(std::memory_order_acquire)) remove_slot(s);
  // SA_RESETHAND restored the default action; the signal, raised again, is
  // delivered when this handler returns and ends the process with it.
  raise(sig);
  errno = savedErrno;
}

// Blocks the cleanup signals in the calling thread for its lifetime.
class BlockCleanupSignals {
public:
  BlockCleanupSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : kCleanupSignals)
      sigaddset(&set, sig);
    pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~BlockCleanupSignals() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }

private:
  sigset_t old_;
};

// ---- paths ----------------------------------------------------------------

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// Where an output goes, decided from what is at its path now.
struct Target {
  bool stream = false;   // a character device or FIFO, written in place
  std::string dir, base; // a file: its folder and name in it
  bool exists = false;   // a file: an existing regular file is replaced
  struct stat st = {};   // of the existing file
};

void split_path(const std::string& path, std::string& dir, std::string& base) {
  size_t slash = path.rfind('/');
  if (slash == std::string::npos) {
    dir.assign(1, '.');
    base = path;
  } else {
    dir = slash == 0 ? "/" : path.substr(0, slash);
    base = path.substr(slash + 1);
  }
}

bool check_folder(const std::string& path, const std::string& dir, std::string& error) {
  struct stat ds;
  if (stat(dir.c_str(), &ds) != 0) {
    error =
        "cannot write " + quoted(path) + ": folder " + quoted(dir) + ": " + std::strerror(errno);
    return false;
  }
  if (!S_ISDIR(ds.st_mode)) {
    error = "cannot write " + quoted(path) + ": " + quoted(dir) + " is not a folder";
    return false;
  }
  if (access(dir.c_str(), W_OK | X_OK) != 0) {
    error = "cannot write " + quoted(path) + ": folder " + quoted(dir) + " is not writable (" +
            std::strerror(errno) + ")";
    return false;
  }
  return true;
}

bool resolve(const std::string& path, Target& t, std::string& error) {
  t = Target{};
  if (path.empty()) {
    error = "the output path is empty";
    return false;
  }
  if (path.back() == '/') {
    error = "cannot write " + quoted(path) + ": it names a folder, not a file";
    return false;
  }
  struct stat st;
  if (stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) {
      error = "cannot write " + quoted(path) + ": it is a folder";
      return false;
    }
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      t.stream = true;
      return true;
    }
    if (S_ISBLK(st.st_mode)) {
      error = "cannot write " + quoted(path) + ": it is a block device (rt64k writes files)";
      return false;
    }
    if (!S_ISREG(st.st_mode)) {
      error = "cannot write " + quoted(path) + ": it is not a regular file";
      return false;
    }
    if (access(path.c_str(), W_OK) != 0) {
      error = "cannot write " + quoted(path) + ": " + std::strerror(errno);
      return false;
    }
    std::string real = path;
    struct stat lst;
    if (lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
      // Replace the file the link names; the link stays a link.
      char* r = realpath(path.c_str(), nullptr);
      if (!r) {
        error = "cannot write " + quoted(path) + ": " + std::strerror(errno);
        return false;
      }
      real = r;
      std::free(r);
    }
    split_path(real, t.dir, t.base);
    t.exists = true;
    t.st = st;
    return check_folder(path, t.dir, error);
  }
  int err = errno;
  struct stat lst;
  if (err == ENOENT && lstat(path.c_str(), &lst) == 0) {
    error = "cannot write " + quoted(path) + ": it is a symbolic link to nothing";
    return false;
  }
  if (err != ENOENT) {
    error = "cannot write " + quoted(path) + ": " + std::strerror(err);
    return false;
  }
  split_path(path, t.dir, t.base);
  return check_folder(path, t.dir, error);
}

// ".NAME.rt64k-XXXXXXXX": hidden, next to the target, unique. NAME is cut
// so that the whole stays within NAME_MAX.
std::string temp_name(const std::string& base) {
  static const char kDigits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
  unsigned char random[8];
  if (getrandom(random, sizeof random, GRND_NONBLOCK) != (ssize_t)sizeof random) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    unsigned long long x = (unsigned long long)ts.tv_nsec * 6364136223846793005ull ^
                           (unsigned long long)getpid() << 32 ^ (unsigned long long)ts.tv_sec;
    for (unsigned char& r : random) {
      r = (unsigned char)(x >> 56);
      x = x * 6364136223846793005ull + 1442695040888963407ull;
    }
  }
  std::string name(1, '.');
  name.append(base, 0, 200);
  name.append(".rt64k-");
  for (unsigned char r : random)
    name += kDigits[r % 36];
  return name;
}

// The stdio stream's functions: every byte goes through OutputFile.
ssize_t cookie_write(void* cookie, const char* data, size_t size) {
  return static_cast<OutputFile*>(cookie)->write_bytes(data, size);
}
int cookie_close(void* cookie) { return static_cast<OutputFile*>(cookie)->close_fd(); }

bool utf8_char(const unsigned char* s, size_t n, size_t& len) {
  unsigned c = s[0];
  unsigned cp;
  if (c >= 0xc2 && c <= 0xdf)
    len = 2, cp = c & 0x1f;
  else if (c >= 0xe0 && c <= 0xef)
    len = 3, cp = c & 0x0f;
  else if (c >= 0xf0 && c <= 0xf4)
    len = 4, cp = c & 0x07;
  else
    return false;
  if (len > n) return false;
  for (size_t i = 1; i < len; ++i) {
    if ((s[i] & 0xc0) != 0x80) return false;
    cp = cp << 6 | (s[i] & 0x3f);
  }
  // No overlong forms, surrogates or code points past U+10FFFF; no C1 controls.
  static const unsigned kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
  return cp >= kMin[len] && !(cp >= 0xd800 && cp <= 0xdfff) && cp <= 0x10ffff && cp >= 0xa0;
}

} // namespace

std::string printable(const std::string& text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  const unsigned char* s = reinterpret_cast<const unsigned char*>(text.data());
  size_t n = text.size();
  for (size_t i = 0; i < n;) {
    unsigned c = s[i];
    size_t len = 1;
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else if (c == '\t')
      out += "\\t";
    else if (c == '\r')
      out += "\\r";
    else if (c >= 0x20 && c < 0x7f)
      out += char(c);
    else if (c >= 0x80 && utf8_char(s + i, n - i, len))
      out.append(text, i, len);
    else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
      len = 1;
    }
    i += len;
  }
  return out;
}

void report_error(const std::string& message) {
  std::string line = "rt64k: " + printable(message) + "\n";
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

void install_output_signal_handlers() {
  for (int sig : kCleanupSignals) {
    struct sigaction old;
    if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue; // nohup, &
    struct sigaction sa = {};
    sa.sa_handler = on_cleanup_signal;
    sigemptyset(&sa.sa_mask);
    for (int other : kCleanupSignals)
      sigaddset(&sa.sa_mask, other);
    sa.sa_flags = SA_RESETHAND;
    sigaction(sig, &sa, nullptr);
  }
  // Over `ulimit -f` a write fails with EFBIG and is reported, instead of the
  // process being killed with a temporary left behind.
  signal(SIGXFSZ, SIG_IGN);
}

bool check_output_path(const std::string& path, std::string& error) {
  Target t;
  return resolve(path, t, error);
}

bool OutputFile::open(const std::string& path, std::string& error) {
  abort();
  path_ = path;
  errno_ = 0;
  const char* stop = std::getenv("RT64K_TEST_STOP_IN_WRITE");
  stopPending_ = stop && path == stop;
  Target t;
  if (!resolve(path, t, error)) return false;
  if (t.stream) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd_ < 0) return fail("", errno, error);
    struct stat st;
    if (fstat(fd_, &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) {
      error = "cannot write " + quoted(path) + ": it changed while rt64k ran";
      abort();
      return false;
    }
  } else {
    dirFd_ = ::open(t.dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd_ < 0) dirFd_ = ::open(t.dir.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
    if (dirFd_ < 0) return fail("folder " + quoted(t.dir), errno, error);
    base_ = t.base;
    int slot = -1;
    for (int i = 0; i < kMaxTemporaries && slot < 0; ++i)
      if (!g_slots[i].live.load()) slot = i;
    if (slot < 0) return fail("too many outputs open", EMFILE, error);
    {
      BlockCleanupSignals blocked;
      g_creating.fetch_add(1);
      int err = 0;
      for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = temp_name(t.base);
        fd_ =
            openat(dirFd_, name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd_ >= 0) {
          tempName_ = name;
          break;
        }
        err = errno;
        if (err != EEXIST) break;
      }
      struct stat st;
      if (fd_ >= 0 && fstat(fd_, &st) == 0) {
        TempSlot& s = g_slots[slot];
        s.dirFd = dirFd_;
        s.dev = st.st_dev;
        s.ino = st.st_ino;
        std::strncpy(s.name, tempName_.c_str(), sizeof s.name - 1);
        s.name[sizeof s.name - 1] = '\0';
        s.live.store(1, std::memory_order_release);
        slot_ = slot;
      } else if (fd_ >= 0) {
        err = errno;
        ::close(fd_);
        fd_ = -1;
        unlinkat(dirFd_, tempName_.c_str(), 0); // created just now by this call
        tempName_.clear();
      }
      g_creating.fetch_sub(1);
      if (fd_ < 0) return fail("cannot create a temporary file in " + quoted(t.dir), err, error);
    }
    if (t.exists) {
      // The replacement keeps the old file's owner (where allowed) and mode.
      if (fchown(fd_, t.st.st_uid, t.st.st_gid) != 0) {
        // Only root may give a file away: the replacement is then ours.
      }
      fchmod(fd_, t.st.st_mode & 0777);
    }
  }
  cookie_io_functions_t io = {nullptr, cookie_write, nullptr, cookie_close};
  stream_ = fopencookie(this, "w", io);
  if (!stream_) return fail("", errno, error);
  setvbuf(stream_, nullptr, _IOFBF, 1 << 16);
  return true;
}

long OutputFile::write_bytes(const char* data, size_t size) {
  if (errno_ != 0) return 0;
  size_t done = 0;
  while (done < size) {
    ssize_t n = ::write(fd_, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      errno_ = n < 0 ? errno : EIO;
      return 0;
    }
    done += size_t(n);
  }
  if (stopPending_) { // tests: stop with the output partly written
    stopPending_ = false;
    raise(SIGSTOP);
  }
  return long(size);
}

int OutputFile::close_fd() {
  int r = fd_ >= 0 ? ::close(fd_) : 0;
  if (r != 0 && errno_ == 0 && errno != EINTR) errno_ = errno;
  fd_ = -1;
  return r == 0 ? 0 : EOF;
}

bool OutputFile::fail(const std::string& what, int err, std::string& error) {
  error = "cannot write " + quoted(path_) + ": " + (what.empty() ? "" : what + ": ") +
          std::strerror(err);
  abort();
  return false;
}

bool OutputFile::commit(std::string& error) {
  if (!stream_) return fail("not open", EBADF, error);
  if (std::fflush(stream_) != 0 && errno_ == 0) errno_ = errno ? errno : EIO;
  if (errno_ == 0 && std::ferror(stream_)) errno_ = EIO;
  if (errno_ != 0) return fail("", errno_, error);
  if (stopPending_) { // tests: stop with the output written, not yet in place
    stopPending_ = false;
    raise(SIGSTOP);
  }
  bool file = !tempName_.empty();
  if (file && fsync(fd_) != 0) return fail("fsync", errno, error);
  std::FILE* s = stream_;
  stream_ = nullptr;
  if (std::fclose(s) != 0 && errno_ == 0) errno_ = errno ? errno : EIO;
  fd_ = -1;
  if (errno_ != 0) return fail("close", errno_, error);
  if (file) {
    if (renameat(dirFd_, tempName_.c_str(), dirFd_, base_.c_str()) != 0)
      return fail("cannot replace it", errno, error);
    g_slots[slot_].live.store(0, std::memory_order_release);
    slot_ = -1;
    tempName_.clear();
    fsync(dirFd_); // the new name on disk; the data already is (errors: only durability)
  }
  abort(); // closes the folder
  return true;
}

void OutputFile::abort() {
  if (stream_) {
    std::fclose(stream_); // closes fd_
    stream_ = nullptr;
  } else if (fd_ >= 0) {
    ::close(fd_);
  }
  fd_ = -1;
  if (slot_ >= 0) {
    remove_slot(g_slots[slot_]);
    g_slots[slot_].live.store(0, std::memory_order_release);
    slot_ = -1;
  }
  tempName_.clear();
  if (dirFd_ >= 0) ::close(dirFd_);
  dirFd_ = -1;
}

bool finish_stdout() {
  errno = 0;
  bool ok = std::fflush(stdout) == 0 && !std::ferror(stdout);
  int err = errno;
  errno = 0;
  if (std::fclose(stdout) != 0 && ok) {
    ok = false;
    err = errno;
  }
  if (!ok)
    report_error(std::string("cannot write to standard output: ") +
                 (err ? std::strerror(err) : "write error"));
  return ok;
}
