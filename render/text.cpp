#include "render/text.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include <hb-ft.h>
#include <hb.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <unordered_map>

namespace simreel {

std::string default_font_path() {
  if (const char* env = std::getenv("SIMREEL_FONT"); env && *env) return env;
  for (const char* p : {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                        "/usr/share/fonts/dejavu/DejaVuSans.ttf", "/usr/local/share/fonts/DejaVuSans.ttf"}) {
    std::error_code ec;
    if (std::filesystem::exists(p, ec)) return p;
  }
  throw std::runtime_error(
      "no font for text overlays: DejaVu Sans not found (Debian: apt-get install fonts-dejavu-core; or set "
      "SIMREEL_FONT to a .ttf file)");
}

namespace {
constexpr FT_Int32 kLoadFlags = FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP;
}

struct Font::Impl {
  FT_Library lib = nullptr;
  FT_Face face = nullptr;
  hb_font_t* hb = nullptr;
  hb_buffer_t* buf = nullptr;
  int size = 0;
  std::unordered_map<uint32_t, std::unique_ptr<GlyphBitmap>> cache;  // by glyph index

  const GlyphBitmap& glyph(uint32_t index) {
    auto it = cache.find(index);
    if (it != cache.end()) return *it->second;
    auto g = std::make_unique<GlyphBitmap>();
    if (FT_Load_Glyph(face, index, kLoadFlags) == 0 &&
        FT_Render_Glyph(face->glyph, FT_RENDER_MODE_NORMAL) == 0) {
      const FT_Bitmap& b = face->glyph->bitmap;
      g->width = (int)b.width;
      g->height = (int)b.rows;
      g->left = face->glyph->bitmap_left;
      g->top = face->glyph->bitmap_top;
      g->coverage.resize((size_t)g->width * g->height);
      for (int y = 0; y < g->height; ++y)
        for (int x = 0; x < g->width; ++x) g->coverage[(size_t)y * g->width + x] = b.buffer[y * b.pitch + x];
    }
    return *cache.emplace(index, std::move(g)).first->second;
  }
};

Font::Font(const std::string& path, int pixel_size) : p_(std::make_unique<Impl>()) {
  Impl& P = *p_;
  P.size = pixel_size;
  if (FT_Init_FreeType(&P.lib)) throw std::runtime_error("FreeType failed to start");
  if (FT_New_Face(P.lib, path.c_str(), 0, &P.face)) {
    FT_Done_FreeType(P.lib);
    P.lib = nullptr;
    throw std::runtime_error("cannot read the font '" + path + "'");
  }
  FT_Set_Pixel_Sizes(P.face, 0, (FT_UInt)pixel_size);
  P.hb = hb_ft_font_create_referenced(P.face);
  hb_ft_font_set_load_flags(P.hb, kLoadFlags);
  P.buf = hb_buffer_create();
}

Font::~Font() {
  Impl& P = *p_;
  if (P.buf) hb_buffer_destroy(P.buf);
  if (P.hb) hb_font_destroy(P.hb);
  if (P.face) FT_Done_Face(P.face);
  if (P.lib) FT_Done_FreeType(P.lib);
}

int Font::draw(std::string_view text, int x, int baseline, const Rgba8& color, ScreenLayer* out) {
  Impl& P = *p_;
  hb_buffer_clear_contents(P.buf);
  hb_buffer_add_utf8(P.buf, text.data(), (int)text.size(), 0, (int)text.size());
  hb_buffer_guess_segment_properties(P.buf);
  hb_shape(P.hb, P.buf, nullptr, 0);
  unsigned n = 0;
  const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(P.buf, &n);
  const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(P.buf, &n);
  long pen = 0, pen_y = 0;  // 26.6
  for (unsigned i = 0; i < n; ++i) {
    if (out) {
      const GlyphBitmap& g = P.glyph(info[i].codepoint);
      if (g.width > 0 && g.height > 0) {
        const int gx = x + (int)((pen + pos[i].x_offset + 32) >> 6) + g.left;
        const int gy = baseline - (int)((pen_y + pos[i].y_offset + 32) >> 6) - g.top;
        out->glyphs.push_back({&g, gx, gy, color});
      }
    }
    pen += pos[i].x_advance;
    pen_y += pos[i].y_advance;
  }
  return (int)((pen + 32) >> 6);
}

int Font::ascent() const {
  return (int)((p_->face->size->metrics.ascender + 32) >> 6);
}
int Font::descent() const {
  return (int)((-p_->face->size->metrics.descender + 32) >> 6);
}
int Font::line_height() const {
  return (int)((p_->face->size->metrics.height + 32) >> 6);
}
int Font::pixel_size() const {
  return p_->size;
}

}  // namespace simreel

namespace simreel {

Typeface::Typeface(const std::string& path, int pixel_size)
    : main_(std::make_unique<Font>(path, pixel_size)),
      script_(std::make_unique<Font>(path, std::max(6, (int)std::lround(0.7 * pixel_size)))),
      sup_((int)std::lround(0.36 * pixel_size)),
      sub_((int)std::lround(0.22 * pixel_size)) {}

int Typeface::draw(std::string_view tex, int x, int baseline, const Rgba8& color, ScreenLayer* out) {
  parse_tex(tex, parsed_);
  int pen = x;
  for (const TexSpan& sp : parsed_.spans) {
    const std::string_view s(parsed_.text.data() + sp.begin, sp.end - sp.begin);
    Font& f = sp.shift ? *script_ : *main_;
    const int base = baseline - (sp.shift > 0 ? sup_ : sp.shift < 0 ? -sub_ : 0);
    const size_t first = out ? out->glyphs.size() : 0;
    const int adv = f.draw(s, pen, base, color, out);
    if (out && sp.accent == TexAccent::overline && out->glyphs.size() > first) {
      // A rule over the span's ink, a gap above its top: a square root's vinculum, from the
      // radical's top across its argument.
      int left = 1 << 30, right = -(1 << 30), top = 1 << 30;
      for (size_t k = first; k < out->glyphs.size(); ++k) {
        const ScreenGlyph& g = out->glyphs[k];
        left = std::min(left, g.x), right = std::max(right, g.x + g.bitmap->width);
        top = std::min(top, g.y);
      }
      const int gap = std::max(1, main_->pixel_size() / 12), thick = std::max(1, main_->pixel_size() / 16);
      out->rects.push_back({left - gap, top - gap - thick, right, top - gap, color});
    } else if (out && sp.accent != TexAccent::none && out->glyphs.size() > first) {
      // The ink box of the span, then the accent's glyph centred over it, a gap above its top.
      int left = 1 << 30, right = -(1 << 30), top = 1 << 30;
      for (size_t k = first; k < out->glyphs.size(); ++k) {
        const ScreenGlyph& g = out->glyphs[k];
        left = std::min(left, g.x), right = std::max(right, g.x + g.bitmap->width);
        top = std::min(top, g.y);
      }
      const char* mark = sp.accent == TexAccent::vec    ? "→"
                         : sp.accent == TexAccent::dot  ? "˙"
                         : sp.accent == TexAccent::ddot ? "¨"
                         : sp.accent == TexAccent::hat  ? "ˆ"
                                                        : "¯";
      Font& af = sp.accent == TexAccent::vec ? *script_ : f;
      const size_t a0 = out->glyphs.size();
      af.draw(mark, 0, 0, color, out);
      if (out->glyphs.size() > a0) {
        int aleft = 1 << 30, aright = -(1 << 30), abottom = -(1 << 30);
        for (size_t k = a0; k < out->glyphs.size(); ++k) {
          const ScreenGlyph& g = out->glyphs[k];
          aleft = std::min(aleft, g.x), aright = std::max(aright, g.x + g.bitmap->width);
          abottom = std::max(abottom, g.y + g.bitmap->height);
        }
        const int gap = std::max(1, main_->pixel_size() / 12);
        const int dx = (left + right) / 2 - (aleft + aright) / 2, dy = top - gap - abottom;
        for (size_t k = a0; k < out->glyphs.size(); ++k) out->glyphs[k].x += dx, out->glyphs[k].y += dy;
      }
    }
    pen += adv;
  }
  return pen - x;
}

}  // namespace simreel
