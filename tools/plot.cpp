// plot.cpp - gnuplot through posix_spawn: an argument vector, no shell.
#include "plot.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "output.h"

extern char** environ;

namespace {

// PSNR of identical pictures (+inf) is drawn at this height.
constexpr double kIdenticalPsnrDb = 99.0;

double finite_or_identical(double psnr) { return std::isfinite(psnr) ? psnr : kIdenticalPsnrDb; }

// A descriptor that closes itself.
struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  ~Fd() {
    if (fd >= 0) close(fd);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
};

// An anonymous in-memory file (no path anywhere) holding `text`, at offset 0.
int memory_file(const char* name, const std::string& text) {
  int fd = memfd_create(name, MFD_CLOEXEC);
  if (fd < 0) return -1;
  size_t done = 0;
  while (done < text.size()) {
    ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      close(fd);
      return -1;
    }
    done += size_t(n);
  }
  if (lseek(fd, 0, SEEK_SET) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

// The last non-empty line of what gnuplot wrote to its stderr, trimmed.
std::string last_error_line(int fd) {
  std::string text;
  char buf[4096];
  if (lseek(fd, 0, SEEK_SET) != 0) return "";
  for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0 && text.size() < (1u << 20);)
    text.append(buf, size_t(n));
  std::string line;
  size_t end = text.size();
  while (end > 0) {
    size_t start = text.rfind('\n', end - 1);
    start = start == std::string::npos ? 0 : start + 1;
    line = text.substr(start, end - start);
    size_t a = line.find_first_not_of(" \t\r");
    if (a != std::string::npos) {
      size_t b = line.find_last_not_of(" \t\r");
      return line.substr(a, b - a + 1);
    }
    end = start == 0 ? 0 : start - 1;
  }
  return "";
}

// Everything in `fd` from offset 0 (at most 256 MiB: a plot is ~30 KB).
bool read_all(int fd, std::string& text) {
  text.clear();
  if (lseek(fd, 0, SEEK_SET) != 0) return false;
  char buf[65536];
  for (;;) {
    ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) return true;
    text.append(buf, size_t(n));
    if (text.size() > (size_t(256) << 20)) return false;
  }
}

// A complete PNG: the signature first and the IEND chunk last.
bool complete_png(const std::string& png) {
  static const char kSignature[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  static const char kIend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', '\xae', '\x42', '\x60', '\x82'};
  return png.size() >= 8 + 12 && png.compare(0, 8, kSignature, 8) == 0 &&
         png.compare(png.size() - 12, 12, kIend, 12) == 0;
}

} // namespace

bool find_gnuplot(std::string& gnuplot, std::string& error) {
  std::string path;
  if (const char* p = std::getenv("PATH")) {
    path = p;
  } else {
    size_t n = confstr(_CS_PATH, nullptr, 0);
    path.resize(n);
    if (n) confstr(_CS_PATH, &path[0], n);
    path.resize(std::strlen(path.c_str()));
  }
  for (size_t start = 0; start <= path.size();) {
    size_t colon = path.find(':', start);
    std::string dir =
        path.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    start = colon == std::string::npos ? path.size() + 1 : colon + 1;
    if (dir.empty()) continue; // not the current folder by accident
    std::string candidate = dir + "/gnuplot";
    struct stat st;
    if (stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        access(candidate.c_str(), X_OK) == 0) {
      gnuplot = candidate;
      return true;
    }
  }
  error = "--plot needs gnuplot, which is not in PATH (apt-get install gnuplot-nox)";
  return false;
}

bool plot_script(const std::vector<PlotPoint>& points, const PlotTitle& title,
                 std::string& script) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "set terminal pngcairo size 900,600 font 'sans,11'\n"
                "set title 'rt64k: ms per %dx%d frame against error vs every-pixel trace "
                "(%d frames, %d threads)'\n",
                title.width, title.height, title.frames, title.threads);
  script = buf;
  // No `set output`: pngcairo writes to stdout, a memory file.
  script += "set xlabel 'median ms per frame (log scale)'\n"
            "set ylabel 'PSNR against full trace, dB (99 = identical)'\n"
            "set logscale x\nset grid\nset key bottom right\n"
            "set arrow from graph 0, first 40 to graph 1, first 40 nohead dt 2 lc rgb '#c00000'\n"
            "$modes << EOD\n";
  for (size_t i = 0; i < points.size(); ++i) {
    const PlotPoint& p = points[i];
    if (p.label.empty() ||
        p.label.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                  "0123456789-_") != std::string::npos)
      return false;
    // Where the label goes, in dB: one line (kLabelLineDb) above the median
    // point; the second of points drawn at nearly the same place (medians
    // within kSameSpot of each other in ms and kLabelLineDb in PSNR, e.g.
    // adaptive8 and adaptive16 of the same speed and error) one line below
    // its min-PSNR point instead, any further one stacked higher above, so
    // that no two names print over each other.
    constexpr double kLabelLineDb = 2.5, kSameSpot = 1.15;
    double median = finite_or_identical(p.medianPsnr);
    int near = 0;
    for (size_t j = 0; j < i; ++j) {
      const PlotPoint& q = points[j];
      double ratio = p.medianMs > q.medianMs ? p.medianMs / q.medianMs : q.medianMs / p.medianMs;
      double dy = median - finite_or_identical(q.medianPsnr);
      if (ratio < kSameSpot && dy < kLabelLineDb && dy > -kLabelLineDb) ++near;
    }
    double labelDb = near == 1 ? finite_or_identical(p.minPsnr) - kLabelLineDb
                               : median + kLabelLineDb * (near ? near : 1);
    std::snprintf(buf, sizeof buf, "\"%s\" %.4f %.3f %.3f %.4f %.2f\n", p.label.c_str(), p.medianMs,
                  finite_or_identical(p.minPsnr), median, p.p95Ms, labelDb);
    script += buf;
  }
  script += "EOD\n"
            "plot $modes using 2:6:1 with labels notitle, \\\n"
            "     $modes using 2:4 with points pt 7 ps 1.5 title 'median PSNR', \\\n"
            "     $modes using 2:3 with points pt 5 ps 1.2 title 'min PSNR'\n";
  return true;
}

bool draw_plot(const std::string& gnuplot, const std::string& path,
               const std::vector<PlotPoint>& points, const PlotTitle& title, std::string& error) {
  std::string script;
  if (!plot_script(points, title, script)) {
    error = "cannot draw the plot: a mode name is not plain letters and digits";
    return false;
  }
  // Descriptors at 3 and above: stdin/stdout/stderr may be closed, and the
  // dup2s below must not overwrite one another.
  Fd scriptFd(memory_file("rt64k-plot-script", script));
  Fd errFd(memory_file("rt64k-gnuplot-stderr", ""));
  Fd pngFd(memory_file("rt64k-plot-png", ""));
  if (scriptFd.fd < 0 || errFd.fd < 0 || pngFd.fd < 0) {
    error = std::string("cannot draw the plot: memfd_create: ") + std::strerror(errno);
    return false;
  }
  Fd script3(fcntl(scriptFd.fd, F_DUPFD_CLOEXEC, 3)), err3(fcntl(errFd.fd, F_DUPFD_CLOEXEC, 3));
  Fd out3(fcntl(pngFd.fd, F_DUPFD_CLOEXEC, 3));
  if (script3.fd < 0 || err3.fd < 0 || out3.fd < 0) {
    error = std::string("cannot draw the plot: ") + std::strerror(errno);
    return false;
  }

  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, script3.fd, 0);
  posix_spawn_file_actions_adddup2(&actions, out3.fd, 1);
  posix_spawn_file_actions_adddup2(&actions, err3.fd, 2);
  posix_spawnattr_init(&attr);
  // gnuplot starts with default signal actions (SIGXFSZ: ignored here, so
  // that our own writes report EFBIG) and nothing blocked.
  sigset_t defaults, none;
  sigemptyset(&defaults);
  for (int sig : {SIGXFSZ, SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGQUIT})
    sigaddset(&defaults, sig);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  char arg0[] = "gnuplot";
  char* argv[] = {arg0, nullptr};
  pid_t pid;
  int rc = posix_spawn(&pid, gnuplot.c_str(), &actions, &attr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    error = "cannot run '" + gnuplot + "': " + std::strerror(rc);
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      error = std::string("cannot wait for gnuplot: ") + std::strerror(errno);
      return false;
    }
  }
  std::string said = last_error_line(errFd.fd);
  if (WIFSIGNALED(status)) {
    error = "gnuplot was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
            strsignal(WTERMSIG(status)) + "); no plot written";
    return false;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    error = "gnuplot failed (exit code " + std::to_string(WEXITSTATUS(status)) +
            (said.empty() ? std::string(")") : "): " + said) + "; no plot written";
    return false;
  }
  std::string png;
  if (!read_all(pngFd.fd, png) || !complete_png(png)) {
    error = "gnuplot wrote no complete PNG" + (said.empty() ? std::string() : ": " + said) +
            "; no plot written";
    return false;
  }
  // Only a whole PNG reaches the output, through checked writes.
  OutputFile out;
  if (!out.open(path, error)) return false;
  std::fwrite(png.data(), 1, png.size(), out.stream());
  return out.commit(error);
}
