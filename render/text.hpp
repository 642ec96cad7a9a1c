// Text for the screen layer: FreeType rasterises, HarfBuzz shapes (kerning, ligatures, combining
// marks), from a Debian font (DejaVu Sans, fonts-dejavu-core). Deterministic: outlines are
// rasterised unhinted (FT_LOAD_NO_HINTING, the same coverage on every run whatever the hinting
// engine), pen positions are summed in 26.6 fixed point and each glyph is placed on a whole
// pixel, so a string's pixels depend only on the string, its size and its position.
#pragma once
#include <memory>
#include <string>
#include <string_view>

#include "render/screen.hpp"
#include "render/tex.hpp"

namespace simreel {

// The font simreel draws text in: DejaVu Sans from Debian's fonts-dejavu-core (or
// SIMREEL_FONT if set). Throws std::runtime_error naming the package if it is missing.
std::string default_font_path();

class Font {
 public:
  Font(const std::string& path, int pixel_size);  ///< throws std::runtime_error
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  // Shapes UTF-8 `text` and appends its glyphs to `out` with the pen starting at x (px) on the
  // baseline y (px, down). Returns the advance (px). With out == nullptr it only measures.
  // Glyphs are rasterised once and kept: the bitmaps `out` points at live as long as the Font.
  int draw(std::string_view text, int x, int baseline, const Rgba8& color, ScreenLayer* out);
  int width(std::string_view text) { return draw(text, 0, 0, {}, nullptr); }
  int ascent() const;       ///< px above the baseline
  int descent() const;      ///< px below the baseline (positive)
  int line_height() const;  ///< px, baseline to baseline
  int pixel_size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

// Text in the TeX subset of render/tex.hpp at one size: a Font for the text and a smaller one
// (0.7x) for subscripts, superscripts and the arrow of \vec. Superscripts are raised 0.36 em,
// subscripts lowered 0.22 em (em: the main size in px), both on whole pixels. Plain text draws
// exactly as Font::draw draws it.
class Typeface {
 public:
  Typeface(const std::string& path, int pixel_size);  ///< throws std::runtime_error
  // As Font::draw, for text in the TeX subset.
  int draw(std::string_view tex, int x, int baseline, const Rgba8& color, ScreenLayer* out);
  int width(std::string_view tex) { return draw(tex, 0, 0, {}, nullptr); }
  Font& main() { return *main_; }
  Font& script() { return *script_; }
  int pixel_size() const { return main_->pixel_size(); }
  int ascent() const { return main_->ascent(); }
  int descent() const { return main_->descent(); }
  int line_height() const { return main_->line_height(); }
  int superscript_shift() const { return sup_; }  ///< px up
  int subscript_shift() const { return sub_; }    ///< px down

 private:
  std::unique_ptr<Font> main_, script_;
  int sup_ = 0, sub_ = 0;
  TexText parsed_;  // storage reused
};

}  // namespace simreel
