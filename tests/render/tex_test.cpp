// The TeX subset (render/tex.hpp) and its layout (render/text.hpp, Typeface): commands become their
// characters, scripts are smaller and lowered or raised by the stated amounts, accents sit over
// their letters, and plain text is drawn exactly as before.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "render/tex.hpp"
#include "render/text.hpp"

namespace simreel {
namespace {

struct Span {
  std::string text;
  int shift;
  TexAccent accent;
  bool operator==(const Span& o) const { return text == o.text && shift == o.shift && accent == o.accent; }
};

std::vector<Span> spans(const std::string& src) {
  TexText t;
  parse_tex(src, t);
  std::vector<Span> out;
  size_t at = 0;
  for (const TexSpan& s : t.spans) {
    EXPECT_EQ(s.begin, at) << src << ": spans cover the text in order";
    at = s.end;
    out.push_back({t.text.substr(s.begin, s.end - s.begin), s.shift, s.accent});
  }
  EXPECT_EQ(at, t.text.size()) << src;
  return out;
}

constexpr TexAccent kNone = TexAccent::none;

TEST(Tex, PlainTextIsUnchanged) {
  for (const char* s :
       {"omega_body", "E_drift = 3", "t = 1.00 s", "a{b}c", "10^-3", "x_12", "ω₁ → θ̇", "", "under_score_"}) {
    const auto v = spans(s);
    std::string all;
    for (const Span& p : v) {
      all += p.text;
      EXPECT_EQ(p.shift, 0) << s;
      EXPECT_EQ(p.accent, kNone) << s;
    }
    EXPECT_EQ(all, s);
  }
}

TEST(Tex, CommandsScriptsAndAccents) {
  EXPECT_EQ(spans("\\omega_1"), (std::vector<Span>{{"ω", 0, kNone}, {"1", -1, kNone}}));
  EXPECT_EQ(spans("I_{xx} + x^2"),
            (std::vector<Span>{{"I", 0, kNone}, {"xx", -1, kNone}, {" + x", 0, kNone}, {"2", 1, kNone}}));
  EXPECT_EQ(spans("e^{-t}"), (std::vector<Span>{{"e", 0, kNone}, {"-t", 1, kNone}}));
  EXPECT_EQ(spans("\\vec{L} = I\\vec\\omega"),
            (std::vector<Span>{{"L", 0, TexAccent::vec}, {" = I", 0, kNone}, {"ω", 0, TexAccent::vec}}));
  EXPECT_EQ(spans("\\dot\\theta"), (std::vector<Span>{{"θ", 0, TexAccent::dot}}));
  EXPECT_EQ(spans("\\vec{a}\\vec{b}"),
            (std::vector<Span>{{"a", 0, TexAccent::vec}, {"b", 0, TexAccent::vec}}));
  EXPECT_EQ(spans("a \\cdot b \\times c"), (std::vector<Span>{{"a ⋅ b × c", 0, kNone}}));
  EXPECT_EQ(spans("\\Omega\\Delta\\alpha\\beta"), (std::vector<Span>{{"ΩΔαβ", 0, kNone}}));
  EXPECT_EQ(spans("E_0 - 1"), (std::vector<Span>{{"E", 0, kNone}, {"0", -1, kNone}, {" - 1", 0, kNone}}));
  EXPECT_EQ(spans("\\omega_\\alpha"), (std::vector<Span>{{"ω", 0, kNone}, {"α", -1, kNone}}));
  // Escapes, unknown commands and a lone backslash stay as written.
  EXPECT_EQ(spans("\\\\ \\{x\\} \\_ \\foo \\"), (std::vector<Span>{{"\\ {x} _ \\foo \\", 0, kNone}}));
  EXPECT_EQ(spans("a_{open"), (std::vector<Span>{{"a_{open", 0, kNone}}));
}

// \sqrt and \frac print no braces: the radical sign with its argument under a bar, a fraction
// inline with a side of several terms in parentheses.
TEST(Tex, SquareRootsAndFractions) {
  constexpr TexAccent kBar = TexAccent::overline;
  EXPECT_EQ(spans("T = 2\\pi\\sqrt{L/g}"), (std::vector<Span>{{"T = 2π√", 0, kNone}, {"L/g", 0, kBar}}));
  EXPECT_EQ(spans("\\frac{a+b}{2}"), (std::vector<Span>{{"(a+b)/2", 0, kNone}}));
  EXPECT_EQ(spans("\\sqrt{\\frac{L}{g}}"), (std::vector<Span>{{"√", 0, kNone}, {"L/g", 0, kBar}}));
  EXPECT_EQ(spans("\\frac{m v^2}{2}"),
            (std::vector<Span>{{"(m v", 0, kNone}, {"2", 1, kNone}, {")/2", 0, kNone}}));
  // Without a group, as before: the symbol alone, the name as written.
  EXPECT_EQ(spans("\\sqrt 2"), (std::vector<Span>{{"√ 2", 0, kNone}}));
  EXPECT_EQ(spans("\\frac{a}"), (std::vector<Span>{{"\\frac{a}", 0, kNone}}));
}

TEST(Tex, LayoutPlainTextIsFontDrawExactly) {
  Typeface tf(default_font_path(), 24);
  Font f(default_font_path(), 24);
  for (const char* s : {"omega_body = 1.25", "E/E₀ − 1 = -5.5e-11", "t = 3.00 s"}) {
    ScreenLayer a, b;
    EXPECT_EQ(tf.draw(s, 7, 30, {255, 255, 255, 255}, &a), f.draw(s, 7, 30, {255, 255, 255, 255}, &b));
    ASSERT_EQ(a.glyphs.size(), b.glyphs.size()) << s;
    for (size_t k = 0; k < a.glyphs.size(); ++k) {
      EXPECT_EQ(a.glyphs[k].x, b.glyphs[k].x) << s;
      EXPECT_EQ(a.glyphs[k].y, b.glyphs[k].y) << s;
      EXPECT_EQ(a.glyphs[k].bitmap->coverage, b.glyphs[k].bitmap->coverage) << s;
    }
  }
}

// The ink box {left, top, right, bottom} (bottom exclusive) of glyphs [a, b).
std::array<int, 4> ink(const ScreenLayer& l, size_t a, size_t b) {
  std::array<int, 4> box{1 << 20, 1 << 20, -(1 << 20), -(1 << 20)};
  for (size_t k = a; k < b; ++k) {
    const ScreenGlyph& g = l.glyphs[k];
    box = {std::min(box[0], g.x), std::min(box[1], g.y), std::max(box[2], g.x + g.bitmap->width),
           std::max(box[3], g.y + g.bitmap->height)};
  }
  return box;
}

TEST(Tex, SubscriptsAreSmallerAndLowerSuperscriptsSmallerAndHigher) {
  const int px = 40, x = 10, base = 60;
  Typeface tf(default_font_path(), px);
  EXPECT_EQ(tf.script().pixel_size(), 28);  // 0.7 em
  EXPECT_EQ(tf.subscript_shift(), 9);       // 0.22 em
  EXPECT_EQ(tf.superscript_shift(), 14);    // 0.36 em
  ScreenLayer plain, sub, sup;
  tf.draw("x1", x, base, {255, 255, 255, 255}, &plain);
  tf.draw("x_1", x, base, {255, 255, 255, 255}, &sub);
  tf.draw("x^1", x, base, {255, 255, 255, 255}, &sup);
  ASSERT_EQ(plain.glyphs.size(), 2u);
  ASSERT_EQ(sub.glyphs.size(), 2u);
  ASSERT_EQ(sup.glyphs.size(), 2u);
  // The base letter is where plain text puts it.
  EXPECT_EQ(sub.glyphs[0].x, plain.glyphs[0].x);
  EXPECT_EQ(sub.glyphs[0].y, plain.glyphs[0].y);
  const auto one = ink(plain, 1, 2), low = ink(sub, 1, 2), high = ink(sup, 1, 2);
  // A digit stands on the baseline: its ink ends on the row above it.
  EXPECT_EQ(one[3], base);
  EXPECT_EQ(low[3], base + 9) << "the subscript's baseline is 0.22 em below";
  EXPECT_EQ(high[3], base - 14) << "the superscript's baseline is 0.36 em above";
  // Smaller: the digit's height is 0.73 em in DejaVu Sans, 0.7 of that in a script.
  const double h = one[3] - one[1], hs = low[3] - low[1];
  EXPECT_NEAR(hs / h, 0.7, 0.06);
  EXPECT_EQ(high[3] - high[1], low[3] - low[1]);
  // Both start right after the base letter (its advance), as plain text would.
  EXPECT_EQ(sub.glyphs[1].x - sub.glyphs[0].x, sup.glyphs[1].x - sup.glyphs[0].x);
  // And the whole is the advance of the letter plus the script's.
  EXPECT_EQ(tf.width("x_1"), tf.width("x") + tf.script().width("1"));
}

TEST(Tex, AccentsSitCentredOverTheirLetters) {
  Typeface tf(default_font_path(), 40);
  for (const char* s : {"\\vec{L}", "\\dot\\theta", "\\hat{x}"}) {
    ScreenLayer l;
    tf.draw(s, 20, 60, {255, 255, 255, 255}, &l);
    ASSERT_EQ(l.glyphs.size(), 2u) << s;
    const auto letter = ink(l, 0, 1), mark = ink(l, 1, 2);
    EXPECT_LT(mark[3], letter[1]) << s << ": the accent is above the letter's ink";
    EXPECT_GE(mark[3], letter[1] - 6) << s << ": and close above it";
    EXPECT_NEAR(0.5 * (mark[0] + mark[2]), 0.5 * (letter[0] + letter[2]), 1.0) << s << ": centred";
  }
  // The arrow is as wide as a letter, roughly.
  ScreenLayer l;
  tf.draw("\\vec{L}", 20, 60, {255, 255, 255, 255}, &l);
  const auto mark = ink(l, 1, 2);
  EXPECT_GT(mark[2] - mark[0], 10);
  EXPECT_EQ(tf.width("\\vec{L}"), tf.width("L")) << "an accent takes no room";
}

}  // namespace
}  // namespace simreel
