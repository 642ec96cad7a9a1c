#include "app/import/heightfield.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>

#include <simreel/error.hpp>

namespace simreel {

TriangleMesh heightfield_mesh(int nrow, int ncol, const std::vector<double>& elevation, double rx, double ry,
                              double z_top, double z_base) {
  if (nrow < 2 || ncol < 2) throw InputError("a heightfield needs at least 2 rows and 2 columns");
  if ((size_t)nrow * (size_t)ncol != elevation.size())
    throw InputError("a heightfield of " + std::to_string(nrow) + " x " + std::to_string(ncol) + " needs " +
                     std::to_string((size_t)nrow * ncol) + " elevations, got " +
                     std::to_string(elevation.size()));
  if (!(rx > 0) || !(ry > 0) || !(z_top >= 0) || !(z_base > 0) || !std::isfinite(rx + ry + z_top + z_base))
    throw InputError("a heightfield's size must be positive (x and y half-sizes, top, base)");
  double lo = elevation[0], hi = elevation[0];
  for (double e : elevation) {
    if (!std::isfinite(e)) throw InputError("a heightfield's elevation is not finite");
    lo = std::min(lo, e), hi = std::max(hi, e);
  }
  const double range = hi - lo;
  TriangleMesh m;
  const int n = nrow * ncol;
  m.vertices.reserve(2 * (size_t)n);
  for (int base = 0; base < 2; ++base)
    for (int r = 0; r < nrow; ++r)
      for (int c = 0; c < ncol; ++c) {
        const double x = rx * (2.0 * c / (ncol - 1) - 1), y = ry * (2.0 * r / (nrow - 1) - 1);
        const double e = range > 0 ? (elevation[(size_t)r * ncol + c] - lo) / range : 0.0;
        m.vertices.emplace_back(x, y, base ? -z_base : z_top * e);
      }
  auto top = [&](int r, int c) { return r * ncol + c; };
  auto bot = [&](int r, int c) { return n + r * ncol + c; };
  for (int r = 0; r + 1 < nrow; ++r)
    for (int c = 0; c + 1 < ncol; ++c) {
      // Counter-clockwise from above on top, from below at the bottom.
      m.triangles.push_back({top(r, c), top(r, c + 1), top(r + 1, c + 1)});
      m.triangles.push_back({top(r, c), top(r + 1, c + 1), top(r + 1, c)});
      m.triangles.push_back({bot(r, c), bot(r + 1, c + 1), bot(r, c + 1)});
      m.triangles.push_back({bot(r, c), bot(r + 1, c), bot(r + 1, c + 1)});
    }
  // The sides, outward: each boundary edge of the top with the one below it.
  auto wall = [&](int a, int b) {  // a -> b runs counter-clockwise seen from above: the quad faces out
    m.triangles.push_back({a, a + n, b + n});
    m.triangles.push_back({a, b + n, b});
  };
  for (int c = 0; c + 1 < ncol; ++c) {
    wall(top(0, c), top(0, c + 1));                // -y side, x increasing
    wall(top(nrow - 1, c + 1), top(nrow - 1, c));  // +y side, x decreasing
  }
  for (int r = 0; r + 1 < nrow; ++r) {
    wall(top(r, ncol - 1), top(r + 1, ncol - 1));  // +x side, y increasing
    wall(top(r + 1, 0), top(r, 0));                // -x side, y decreasing
  }
  return m;
}

std::vector<double> read_heightfield_png(const std::string& file, int& nrow, int& ncol) {
  png_image im{};
  im.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&im, file.c_str()))
    throw InputError(file + ": not a PNG simreel reads (" + im.message + ")");
  im.format = PNG_FORMAT_RGB;
  if (im.width < 2 || im.height < 2 || im.width > 16384 || im.height > 16384) {
    png_image_free(&im);
    throw InputError(file + ": a heightfield image must be 2 to 16384 pixels a side");
  }
  std::vector<png_byte> px(PNG_IMAGE_SIZE(im));
  if (!png_image_finish_read(&im, nullptr, px.data(), 0, nullptr))
    throw InputError(file + ": broken PNG data (" + im.message + ")");
  nrow = (int)im.height;
  ncol = (int)im.width;
  std::vector<double> out((size_t)nrow * ncol);
  for (int r = 0; r < nrow; ++r)
    for (int c = 0; c < ncol; ++c) {
      const png_byte* p = &px[3 * ((size_t)(nrow - 1 - r) * ncol + c)];  // row 0: the image's bottom
      out[(size_t)r * ncol + c] = (p[0] + p[1] + p[2]) / 3.0;
    }
  return out;
}

std::vector<double> read_heightfield_bin(const std::string& file, int& nrow, int& ncol) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open the heightfield file");
  in.seekg(0, std::ios::end);
  const auto bytes = (long long)in.tellg();
  in.seekg(0);
  std::int32_t head[2] = {0, 0};
  if (bytes < 8 || !in.read(reinterpret_cast<char*>(head), sizeof head))
    throw InputError(file + ": a binary heightfield starts with two int32 (nrow, ncol); the file has " +
                     std::to_string(bytes) + " bytes");
  if (head[0] < 2 || head[1] < 2 || head[0] > 16384 || head[1] > 16384)
    throw InputError(file + ": nrow " + std::to_string(head[0]) + ", ncol " + std::to_string(head[1]) +
                     ": each must be 2 to 16384");
  const long long want = 8 + 4LL * head[0] * head[1];
  if (bytes != want)
    throw InputError(file + ": " + std::to_string(head[0]) + " x " + std::to_string(head[1]) +
                     " float32 elevations need " + std::to_string(want) + " bytes; the file has " +
                     std::to_string(bytes));
  nrow = head[0];
  ncol = head[1];
  std::vector<float> f((size_t)nrow * ncol);
  in.read(reinterpret_cast<char*>(f.data()), (std::streamsize)(4 * f.size()));
  if (!in) throw InputError(file + ": could not read its elevations");
  return std::vector<double>(f.begin(), f.end());  // row 0 at -y, as stored (MuJoCo keeps the order)
}

}  // namespace simreel
