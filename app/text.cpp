#include "app/text.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace simreel {

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (unsigned char ch : s) {
    switch (ch) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\n':
        o += "\\n";
        break;
      case '\t':
        o += "\\t";
        break;
      case '\r':
        o += "\\r";
        break;
      default:
        if (ch < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", ch);
          o += b;
        } else {
          o += (char)ch;
        }
    }
  }
  return o + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string json_vec(const Vec3& v) {
  return "[" + json_number(v.x()) + ", " + json_number(v.y()) + ", " + json_number(v.z()) + "]";
}

std::string json_mat(const Mat3& m) {
  return "[" + json_vec(m.row(0)) + ", " + json_vec(m.row(1)) + ", " + json_vec(m.row(2)) + "]";
}

std::string json_strings(const std::vector<std::string>& v) {
  std::string o = "[";
  for (size_t i = 0; i < v.size(); ++i) o += (i ? ", " : "") + json_string(v[i]);
  return o + "]";
}

Progress::Progress(const char* what, long total, bool quiet)
    : what_(what), total_(total), on_(!quiet && isatty(STDERR_FILENO)) {
  t0_ = last_ = std::chrono::steady_clock::now();
}

void Progress::update(long done) {
  if (!on_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  const double el = std::chrono::duration<double>(now - t0_).count();
  const double rate = el > 0 ? done / el : 0;
  const double left = rate > 0 ? (total_ - done) / rate : 0;
  const int width = 30, fill = total_ > 0 ? (int)(width * done / total_) : width;
  std::fprintf(stderr, "\r[%.*s%*s] %ld/%ld %s  %.1f/s  %.1f s left ", fill, "##############################",
               width - fill, "", done, total_, what_, rate, left);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!on_) return;
  update(total_);
  std::fprintf(stderr, "\n");
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  tmp_ = path_ + ".partial-" + std::to_string(getpid());
  f_ = std::fopen(tmp_.c_str(), "wb");
  if (!f_) throw std::runtime_error("cannot write '" + path_ + "'");
}

AtomicFile::~AtomicFile() {
  if (f_) std::fclose(f_);
  if (!done_) std::remove(tmp_.c_str());
}

void AtomicFile::commit() {
  const bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
  std::fclose(f_);
  f_ = nullptr;
  if (!ok || std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error("cannot write '" + path_ + "'");
  done_ = true;
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
