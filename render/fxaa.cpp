#include "render/fxaa.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <immintrin.h>

namespace simreel {
namespace {

// Tuning from FXAA 3.11's quality defaults: an edge needs a local luma range of at least 0.166 of
// the brightest neighbour and at least 0.0833 of full scale (8-bit luma: 21); sub-pixel blending
// at 3/4 strength; the edge search walks out in growing steps to 22 px each way. On the 100-box
// benchmark frame the "high quality" thresholds (0.125, 0.0312) flagged 12.7% of the pixels and
// cost 6.8 ms; these flag 4.4% and cost 3.5 ms, with the same look on body edges. The passes skip
// flags eight at a time, use integer luma arithmetic up to the blend weights, and run an AVX2
// clone picked at load time (same output: no FMA, the integer passes vectorise), with the edge
// search by gathers and the luma pass and blend in AVX2 intrinsics (Avx2Ops).
constexpr int kThresholdMin = 21;
constexpr int kThresholdRel = 43;  // 0.166 in 1/256
constexpr float kSubpix = 0.75f;
constexpr int kSteps[] = {1, 1, 2, 2, 2, 2, 4, 8};  // FXAA 3.11 preset 12's spacing, whole pixels

// Step 5's edge search, from r0 (the pixel's luma) and r1 (its neighbour's across the edge) in
// steps of `along`: on each side the first position, of the steps' running sums 1, 2, 4, ... 22
// (each at most the reach to the image border), where the pair's luma differs from the edge's
// average by the limit, or the border, or the last. e: 2 (pair sum - pair0) there.
struct Walk {
  int d_neg, d_pos, e_neg, e_pos;
};

// The per-pixel operations of fxaa_with() in portable code; the edge search one step at a time,
// stopping each side at its end (the reference version).
struct PortableOps {
  static size_t luma(const uint8_t*, uint8_t*, size_t) { return 0; }  // all by fxaa_with's loop
  // Step 7's blend of pixel p towards q by t, rounded.
  static void blend(const uint8_t* p, const uint8_t* q, float t, uint8_t* rgb) {
    for (int c = 0; c < 3; ++c) rgb[c] = (uint8_t)(p[c] + t * ((float)q[c] - p[c]) + 0.5f);  // in [0, 255.5]
  }
  static Walk walk(const uint8_t* r0, const uint8_t* r1, std::ptrdiff_t along, int pair0, int limit,
                   int reach_neg, int reach_pos) {
    auto end_at = [&](int t) { return 2 * (r0[t * along] + r1[t * along] - pair0); };
    Walk o{0, 0, 0, 0};
    bool done_neg = false, done_pos = false;
    for (int s : kSteps) {
      if (!done_neg) {
        o.d_neg = std::min(o.d_neg + s, reach_neg);
        o.e_neg = end_at(-o.d_neg);
        done_neg = std::abs(o.e_neg) >= limit || o.d_neg == reach_neg;
      }
      if (!done_pos) {
        o.d_pos = std::min(o.d_pos + s, reach_pos);
        o.e_pos = end_at(o.d_pos);
        done_pos = std::abs(o.e_pos) >= limit || o.d_pos == reach_pos;
      }
      if (done_neg && done_pos) break;
    }
    return o;
  }
};

// The same with AVX2, the same bytes. The edge search reads all eight positions of a side at once
// (gathers) and picks the first that ends it from a bit mask: PortableOps' positions and values
// without its unpredictable branches (the search was a third of FXAA's time). The gathers read 4
// bytes at each position: the luma buffer has 4 bytes to spare at its end.
#pragma GCC push_options
#pragma GCC target("avx2")
struct Avx2Ops {
  // Luma of 32 pixels a step (widened to 16 bits, vpmaddwd, vphaddd; integer: the same bytes as
  // the scalar loop), the rest one at a time. Returns the first pixel left.
  static size_t luma(const uint8_t* in, uint8_t* L, size_t n) {
    const __m256i c = _mm256_setr_epi16(77, 150, 29, 0, 77, 150, 29, 0, 77, 150, 29, 0, 77, 150, 29, 0);
    const __m256i zero = _mm256_setzero_si256(), half = _mm256_set1_epi32(128);
    auto eight = [&](const uint8_t* p) {  // pixels 0-3 | 4-7
      const __m256i px = _mm256_loadu_si256((const __m256i*)p);
      const __m256i s = _mm256_hadd_epi32(_mm256_madd_epi16(_mm256_unpacklo_epi8(px, zero), c),
                                          _mm256_madd_epi16(_mm256_unpackhi_epi8(px, zero), c));
      return _mm256_srli_epi32(_mm256_add_epi32(s, half), 8);
    };
    size_t i = 0;
    for (; i + 32 <= n; i += 32) {
      const __m256i ab = _mm256_packs_epi32(eight(in + 4 * i), eight(in + 4 * i + 32));
      const __m256i cd = _mm256_packs_epi32(eight(in + 4 * i + 64), eight(in + 4 * i + 96));
      const __m256i bytes =
          _mm256_permutevar8x32_epi32(_mm256_packus_epi16(ab, cd), _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7));
      _mm256_storeu_si256((__m256i*)(L + i), bytes);
    }
    return i;
  }
  // The same four channels at once: the same single-precision operations in the same order
  // (no fused multiply-add), truncated the same way.
  static void blend(const uint8_t* p, const uint8_t* q, float t, uint8_t* rgb) {
    int pi, qi;
    std::memcpy(&pi, p, 4);
    std::memcpy(&qi, q, 4);
    const __m128 P = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(pi)));
    const __m128 Q = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(qi)));
    const __m128 r =
        _mm_add_ps(_mm_add_ps(P, _mm_mul_ps(_mm_set1_ps(t), _mm_sub_ps(Q, P))), _mm_set1_ps(0.5f));
    const __m128i b = _mm_cvttps_epi32(r);
    const int out = _mm_cvtsi128_si32(_mm_packus_epi16(_mm_packus_epi32(b, b), _mm_setzero_si128()));
    std::memcpy(rgb, &out, 3);
  }
  static inline void side(const uint8_t* r0, const uint8_t* r1, int step, int pair0, int limit, int reach,
                          int& d, int& e) {
    const __m256i pos =
        _mm256_min_epi32(_mm256_setr_epi32(1, 2, 4, 6, 8, 10, 14, 22), _mm256_set1_epi32(reach));
    const __m256i off = _mm256_mullo_epi32(pos, _mm256_set1_epi32(step));
    const __m256i byte = _mm256_set1_epi32(0xff);
    const __m256i sum =
        _mm256_add_epi32(_mm256_and_si256(_mm256_i32gather_epi32((const int*)r0, off, 1), byte),
                         _mm256_and_si256(_mm256_i32gather_epi32((const int*)r1, off, 1), byte));
    const __m256i ends = _mm256_slli_epi32(_mm256_sub_epi32(sum, _mm256_set1_epi32(pair0)), 1);
    const __m256i stop =
        _mm256_or_si256(_mm256_cmpgt_epi32(_mm256_abs_epi32(ends), _mm256_set1_epi32(limit - 1)),
                        _mm256_cmpeq_epi32(pos, _mm256_set1_epi32(reach)));
    const int k = __builtin_ctz((unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(stop)) | 0x80u);
    alignas(32) int p[8], v[8];
    _mm256_store_si256((__m256i*)p, pos);
    _mm256_store_si256((__m256i*)v, ends);
    d = p[k], e = v[k];
  }
  static Walk walk(const uint8_t* r0, const uint8_t* r1, std::ptrdiff_t along, int pair0, int limit,
                   int reach_neg, int reach_pos) {
    Walk o;
    side(r0, r1, (int)-along, pair0, limit, reach_neg, o.d_neg, o.e_neg);
    side(r0, r1, (int)along, pair0, limit, reach_pos, o.d_pos, o.e_pos);
    return o;
  }
};
#pragma GCC pop_options

template <class Ops>
__attribute__((always_inline)) inline void fxaa_with(uint8_t* img, int w, int h, FxaaBuffers& buf) {
  const uint8_t* in = img;
  const size_t n = (size_t)w * h;
  buf.luma.resize(n + 4);  // + 4: Avx2Ops reads 4 bytes at a position
  uint8_t* L = buf.luma.data();
  // Luma of the gamma-encoded colour (Rec. 601 weights, as FXAA uses), in 8 bits.
  for (size_t i = Ops::luma(in, L, n); i < n; ++i)
    L[i] = (uint8_t)((77 * in[4 * i] + 150 * in[4 * i + 1] + 29 * in[4 * i + 2] + 128) >> 8);
  buf.changes.clear();
  if (w < 3 || h < 3) return;
  buf.edge.assign((size_t)w + 8, 0);  // + 8: read eight flags at a time past the row's end
  uint8_t* edge = buf.edge.data();
  for (int y = 1; y < h - 1; ++y) {
    const uint8_t *up = L + (size_t)(y - 1) * w, *row = L + (size_t)y * w, *dn = L + (size_t)(y + 1) * w;
    // 1. Local contrast of each pixel and its four neighbours, in a branch-free pass the compiler
    // can vectorise; most pixels stop here.
    for (int x = 1; x < w - 1; ++x) {
      const uint8_t hi = std::max(std::max(std::max(row[x], up[x]), std::max(dn[x], row[x - 1])), row[x + 1]);
      const uint8_t lo = std::min(std::min(std::min(row[x], up[x]), std::min(dn[x], row[x - 1])), row[x + 1]);
      const int need = std::max(kThresholdMin, (hi * kThresholdRel) >> 8);
      edge[x] = (uint8_t)(hi - lo >= need);
    }
    for (int x = 1; x < w - 1; ++x) {
      // Eight flags at a time: on a typical frame 95% of the pixels are not on an edge.
      uint64_t flags8;
      std::memcpy(&flags8, edge + x, 8);
      if (flags8 == 0) {
        x += 7;
        continue;
      }
      if (!edge[x]) continue;
      // Luma in 8-bit units; the FXAA formulas' ratios are scale-free.
      const int m = row[x], nN = up[x], nS = dn[x], nW = row[x - 1], nE = row[x + 1];
      const int nNW = up[x - 1], nNE = up[x + 1], nSW = dn[x - 1], nSE = dn[x + 1];
      const int hi = std::max(std::max(std::max(m, nN), std::max(nS, nW)), nE);
      const int lo = std::min(std::min(std::min(m, nN), std::min(nS, nW)), nE);
      // 2. Sub-pixel aliasing: how far the pixel stands out from its 3x3 low-pass (weights 2 for
      // the sides, 1 for the corners, over 12), relative to the local range.
      const int low12 = 2 * (nN + nS + nW + nE) + (nNW + nNE + nSW + nSE);
      const float a = std::min(1.0f, (float)std::abs(low12 - 12 * m) / (float)(12 * (hi - lo)));
      const float b = (-2.0f * a + 3.0f) * a * a;
      const float subpix = b * b * kSubpix;
      // 3. Edge orientation from second differences across rows and across columns.
      const int horz =
          std::abs(nNW - 2 * nW + nSW) + 2 * std::abs(nN - 2 * m + nS) + std::abs(nNE - 2 * nE + nSE);
      const int vert =
          std::abs(nNW - 2 * nN + nNE) + 2 * std::abs(nW - 2 * m + nE) + std::abs(nSW - 2 * nS + nSE);
      const bool horizontal = horz >= vert;  // the edge runs along x; its neighbours are N and S
      // 4. The side of the edge with the steeper gradient.
      const int n1 = horizontal ? nN : nW, n2 = horizontal ? nS : nE;
      const int g1 = std::abs(n1 - m), g2 = std::abs(n2 - m);
      const bool side1 = g1 >= g2;
      const int across = side1 ? -1 : 1;  // step towards the chosen neighbour (up/left is -1)
      // 5. Walk along the edge, halfway between the pixel's row (column) and the neighbour's, until
      // the luma there differs from the edge's average by a quarter of the gradient. In units of
      // 1/2 luma step: pair sum - (side + centre) against (steeper gradient) / 2.
      const int pair0 = (side1 ? n1 : n2) + m;
      const int limit = std::max(g1, g2);  // 4 * gradient/4 in the same units as 2 * (pair sum - pair0)
      const uint8_t* r0 = L + (size_t)y * w + x;
      const uint8_t* r1 = horizontal ? r0 + (std::ptrdiff_t)across * w : r0 + across;
      const std::ptrdiff_t along = horizontal ? 1 : w;
      const int reach_neg = horizontal ? x : y, reach_pos = (horizontal ? w - 1 - x : h - 1 - y);
      const Walk wk = Ops::walk(r0, r1, along, pair0, limit, reach_neg, reach_pos);
      const int d_neg = wk.d_neg, d_pos = wk.d_pos, e_neg = wk.e_neg, e_pos = wk.e_pos;
      // 6. Where along the span the pixel sits: next to the nearer end the edge crosses the pixel
      // at up to half a pixel; in the middle of a long span, not at all. Only blend if the luma
      // at the nearer end moves away from the pixel's (the edge really ends there).
      const bool neg_closer = d_neg < d_pos;
      const float d = (float)std::min(d_neg, d_pos), span = (float)(d_neg + d_pos);
      const int e_closer = neg_closer ? e_neg : e_pos;
      const bool centre_smaller = 2 * m - pair0 < 0;
      const float edge_blend = ((e_closer < 0) != centre_smaller) ? 0.5f - d / span : 0.0f;
      const float t = std::max(edge_blend, subpix);
      if (t <= 0) continue;
      // 7. Blend with the neighbour across the edge (a bilinear sample t pixels that way).
      const int nx = horizontal ? x : x + across, ny = horizontal ? y + across : y;
      const uint8_t* p = in + ((size_t)y * w + x) * 4;
      const uint8_t* q = in + ((size_t)ny * w + nx) * 4;
      FxaaBuffers::Change ch;
      ch.index = (uint32_t)((size_t)y * w + x);
      Ops::blend(p, q, t, ch.rgb);
      buf.changes.push_back(ch);
    }
  }
  for (const FxaaBuffers::Change& ch : buf.changes) std::memcpy(img + 4 * (size_t)ch.index, ch.rgb, 3);
}

__attribute__((target("avx2"))) void fxaa_avx2(uint8_t* img, int w, int h, FxaaBuffers& buf) {
  fxaa_with<Avx2Ops>(img, w, h, buf);
}

}  // namespace

void fxaa_portable(uint8_t* img, int w, int h, FxaaBuffers& buf) {
  fxaa_with<PortableOps>(img, w, h, buf);
}

// With AVX2 (picked once): the contrast pass 32 pixels to a vector, and the luma pass, the edge
// search and the blend by Avx2Ops; both versions give the same bytes, as nothing here can be
// contracted into fused multiply-adds.
void fxaa(uint8_t* img, int w, int h, FxaaBuffers& buf) {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2)
    fxaa_avx2(img, w, h, buf);
  else
    fxaa_portable(img, w, h, buf);
}

}  // namespace simreel
