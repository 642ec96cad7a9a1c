// MJCF heightfields (<hfield>): an elevation grid made into the closed solid MuJoCo collides with,
// for a static body's triangle-mesh collider.
#pragma once
#include <string>
#include <vector>

#include <simreel/mesh.hpp>

namespace simreel {

// A grid of nrow x ncol elevations, row-major, row 0 at -y and column 0 at -x (MuJoCo's order),
// spanning [-rx, rx] x [-ry, ry]. The elevations are normalised to [0, 1] (minus the least,
// over the range; all equal: 0), as MuJoCo does, and scaled to z_top; the solid's base is z_base
// below z = 0. Each top cell is two triangles (counter-clockwise from above, split along the
// diagonal from its (-x, -y) corner); the four sides and a flat bottom close it. Throws InputError for a
// grid under 2 x 2, a size that is not positive, or an elevation that is not finite.
TriangleMesh heightfield_mesh(int nrow, int ncol, const std::vector<double>& elevation, double rx, double ry,
                              double z_top, double z_base);

// The grey levels of a PNG (RGB averaged, as MuJoCo does), row-major with row 0 the image's bottom
// row (MuJoCo puts the image's top at +y). Throws InputError naming the file when it cannot be read.
std::vector<double> read_heightfield_png(const std::string& file, int& nrow, int& ncol);

// MuJoCo's binary heightfield: int32 nrow, int32 ncol, then nrow x ncol float32, all
// little-endian, row-major with row 0 at -y (measured with MuJoCo 2.2.2's mj_ray: the file's order
// is kept, and its elevations are normalised as a PNG's are). Throws InputError naming the file
// when the header or the size is wrong.
std::vector<double> read_heightfield_bin(const std::string& file, int& nrow, int& ncol);

}  // namespace simreel
