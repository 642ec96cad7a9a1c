// libFuzzer harness: mass properties of arbitrary triangle meshes (sim/mesh_mass.cpp), every mode.
//
// Input: byte 0 picks the mode (solid, shell, hull) and how coordinates are coded, byte 1 a
// binary exponent for the coordinates (-128 .. 127, times 8: sizes from 1e-308 to 1e308), byte 2
// the vertex count; then the vertices (3 int16 each, times 2^exponent, or 3 raw doubles), then
// triangles as byte triples (indices modulo the vertex count) to the end.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "sim/error.hpp"
#include "tests/fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace simreel;
  if (size < 3) return 0;
  const int mode = data[0] % 3;
  const bool raw = (data[0] / 3) % 4 == 0;
  const int exponent = 8 * (int)(int8_t)data[1];
  const int nv = data[2];
  size_t at = 3;
  TriangleMesh m;
  for (int i = 0; i < nv; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      if (raw) {
        if (at + 8 > size) return 0;
        std::memcpy(&p[k], data + at, 8);
        at += 8;
      } else {
        if (at + 2 > size) return 0;
        int16_t q;
        std::memcpy(&q, data + at, 2);
        at += 2;
        p[k] = std::ldexp((double)q, exponent);
      }
    }
    m.vertices.push_back(p);
  }
  for (; at + 3 <= size; at += 3)
    if (nv > 0) m.triangles.push_back({data[at] % nv, data[at + 1] % nv, data[at + 2] % nv});
  MeshMassOptions opt;
  opt.mode = mode == 0 ? MassMode::solid : mode == 1 ? MassMode::shell : MassMode::hull;
  try {
    fuzz::check_report(analyze_mesh(m, opt));
  } catch (const InputError&) {
  }
  return 0;
}
