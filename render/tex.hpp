// A small TeX-like subset for every text simreel draws (titles, HUD lines, captions, labels,
// legends, plot labels): what a teacher writes in a label, and nothing more.
//
//   \omega \theta \Omega ...   Greek letters (lower and upper case, by their TeX names)
//   \cdot \times \pm \to \infty \partial \nabla \approx \le \ge \ne \deg \degree \circ
//                              the symbols ⋅ × ± → ∞ ∂ ∇ ≈ ≤ ≥ ≠ ° ° ∘
//   x_1  x^2                   a one-character subscript or superscript, smaller and lowered or
//                              raised, when the character after it is not a letter or a digit
//   I_{xx}  e^{-t}             a group of any length
//   \vec{L}  \vec L            an arrow over the letter(s); \dot, \ddot, \hat, \bar likewise
//   \sqrt{L/g}                 the radical sign with its argument under a rule: √ and L/g overlined
//   \frac{a+b}{2}              a fraction inline, a side of more than one term in parentheses: (a+b)/2
//   \\  \{  \}  \_  \^         the character itself; "\," a thin space
//
// Everything else is plain text, drawn as written: "omega_body" and "E_drift" stay as they are
// (the letter after '_' is followed by another letter), an unknown command such as "\foo" stays
// "\foo", and braces that open no group are literal.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace simreel {

// bar: a macron centred over the span (\bar x); overline: a rule over the span's whole width (a
// square root's vinculum).
enum class TexAccent : uint8_t { none, vec, dot, ddot, hat, bar, overline };

struct TexSpan {
  uint32_t begin = 0, end = 0;  ///< bytes of TexText::text (UTF-8)
  int8_t shift = 0;             ///< +1 superscript, -1 subscript, 0 on the baseline (script size if != 0)
  TexAccent accent = TexAccent::none;
};

struct TexText {
  std::string text;            ///< the UTF-8 to draw, commands replaced by their characters
  std::vector<TexSpan> spans;  ///< in order, covering `text`
  void clear() {
    text.clear();
    spans.clear();
  }
};

// Parses `src` into `out`, reusing its storage (no allocation once it has grown).
void parse_tex(std::string_view src, TexText& out);

// The UTF-8 character of a command name without its backslash ("omega" -> "ω"), or nullptr.
const char* tex_symbol(std::string_view name);

}  // namespace simreel
