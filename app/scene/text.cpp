#include "app/scene/text.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace simreel {

Progress::Progress(const char* what, long total, bool quiet)
    : what_(what), total_(total), on_(!quiet), tty_(isatty(STDERR_FILENO)) {
  t0_ = last_ = std::chrono::steady_clock::now();
}

void Progress::update(long done) {
  if (!on_) return;
  const auto now = std::chrono::steady_clock::now();
  const double el = std::chrono::duration<double>(now - t0_).count();
  if (!tty_) {
    // A plain line at each tenth, or after 10 s without one.
    const bool share = total_ > 0 && done * 10 >= next_share_ * total_;
    if (!share && now - last_ < std::chrono::seconds(10)) return;
    while (total_ > 0 && done * 10 >= next_share_ * total_) ++next_share_;
    last_ = now;
    std::fprintf(stderr, "%ld/%ld %s (%.0f%%), %.1f s\n", done, total_, what_,
                 total_ > 0 ? 100.0 * done / total_ : 100.0, el);
    return;
  }
  if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  const double rate = el > 0 ? done / el : 0;
  const double left = rate > 0 ? (total_ - done) / rate : 0;
  const int width = 30, fill = total_ > 0 ? (int)(width * done / total_) : width;
  std::fprintf(stderr, "\r[%.*s%*s] %ld/%ld %s  %.1f/s  %.1f s left ", fill, "##############################",
               width - fill, "", done, total_, what_, rate, left);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!on_ || !tty_) return;
  update(total_);
  std::fprintf(stderr, "\n");
}

void remove_stale_partials(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  // AtomicFile's "<name>.partial-<pid>" and the video writer's "<stem>.partial-<pid>.<ext>".
  const std::string prefixes[2] = {p.filename().string() + ".partial-", p.stem().string() + ".partial-"};
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    for (const std::string& pre : prefixes) {
      if (n.rfind(pre, 0) != 0) continue;
      const std::string rest = n.substr(pre.size());
      const size_t digits = rest.find_first_not_of("0123456789");
      if (digits == 0 || rest.empty()) continue;
      const long pid = std::strtol(rest.substr(0, digits).c_str(), nullptr, 10);
      if (pid <= 0 || pid == (long)getpid()) continue;
      if (kill((pid_t)pid, 0) == -1 && errno == ESRCH) fs::remove(e.path(), ec);
      break;
    }
  }
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // Follow a symlink (and a chain of them) to the file it names, so the link survives the rename.
  for (int hops = 0; hops < 40 && fs::is_symlink(path_, ec); ++hops) {
    const fs::path target = fs::read_symlink(path_, ec);
    if (ec) break;
    path_ = (target.is_absolute() ? target : fs::path(path_).parent_path() / target).string();
  }
  const fs::file_status st = fs::status(path_, ec);
  if (fs::is_directory(st)) throw std::runtime_error("cannot write '" + path_ + "': it is a folder");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    // A device or a FIFO: written through, never replaced by a regular file.
    f_ = std::fopen(path_.c_str(), "wb");
    if (!f_) throw std::runtime_error("cannot write '" + path_ + "'");
    through_ = true;
    return;
  }
  remove_stale_partials(path_);
  tmp_ = path_ + ".partial-" + std::to_string(getpid());
  f_ = std::fopen(tmp_.c_str(), "wb");
  if (!f_) throw std::runtime_error("cannot write '" + path_ + "'");
}

AtomicFile::~AtomicFile() {
  if (f_) std::fclose(f_);
  if (!done_ && !through_) std::remove(tmp_.c_str());
}

void AtomicFile::commit() {
  const bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
  std::fclose(f_);
  f_ = nullptr;
  if (!ok || (!through_ && std::rename(tmp_.c_str(), path_.c_str()) != 0))
    throw std::runtime_error("cannot write '" + path_ + "'");
  done_ = true;
}

namespace {
std::atomic<int> g_stop{0};
extern "C" void on_stop_signal(int sig) {
  int none = 0;
  g_stop.compare_exchange_strong(none, sig);  // the first signal wins; later ones change nothing
}
constexpr int kStopSignals[4] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
}  // namespace

StopSignals::StopSignals() {
  g_stop = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : kStopSignals) sigaction(sig, &sa, nullptr);
}

// The handlers stay to the end of the process: a signal that comes after the outputs are finished
// (a second Ctrl-C while the process exits) must not kill it with the files half closed.
StopSignals::~StopSignals() = default;

const std::atomic<int>& StopSignals::flag() const {
  return g_stop;
}

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = (char)std::tolower((unsigned char)c);
  return e;
}

bool ensure_parent_dir(const std::string& path, std::string* err) {
  const std::filesystem::path p = std::filesystem::path(path).parent_path();
  if (p.empty()) return true;
  std::error_code ec;
  std::filesystem::create_directories(p, ec);
  if (ec) {
    *err = "cannot create folder '" + p.string() + "': " + ec.message();
    return false;
  }
  return true;
}

}  // namespace simreel
