#include "render/tex.hpp"

#include <cctype>

#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {

struct Symbol {
  const char* name;
  const char* utf8;
};

const Symbol kSymbols[] = {
    {"alpha", "α"},      {"beta", "β"},     {"gamma", "γ"},      {"delta", "δ"},     {"epsilon", "ε"},
    {"varepsilon", "ε"}, {"zeta", "ζ"},     {"eta", "η"},        {"theta", "θ"},     {"vartheta", "ϑ"},
    {"iota", "ι"},       {"kappa", "κ"},    {"lambda", "λ"},     {"mu", "μ"},        {"nu", "ν"},
    {"xi", "ξ"},         {"pi", "π"},       {"rho", "ρ"},        {"sigma", "σ"},     {"tau", "τ"},
    {"upsilon", "υ"},    {"phi", "φ"},      {"varphi", "φ"},     {"chi", "χ"},       {"psi", "ψ"},
    {"omega", "ω"},      {"Gamma", "Γ"},    {"Delta", "Δ"},      {"Theta", "Θ"},     {"Lambda", "Λ"},
    {"Xi", "Ξ"},         {"Pi", "Π"},       {"Sigma", "Σ"},      {"Upsilon", "Υ"},   {"Phi", "Φ"},
    {"Psi", "Ψ"},        {"Omega", "Ω"},    {"cdot", "⋅"},       {"times", "×"},     {"pm", "±"},
    {"mp", "∓"},         {"to", "→"},       {"rightarrow", "→"}, {"leftarrow", "←"}, {"infty", "∞"},
    {"partial", "∂"},    {"nabla", "∇"},    {"approx", "≈"},     {"le", "≤"},        {"leq", "≤"},
    {"ge", "≥"},         {"geq", "≥"},      {"ne", "≠"},         {"neq", "≠"},       {"deg", "°"},
    {"degree", "°"},     {"circ", "∘"},     {"hbar", "ħ"},       {"sim", "∼"},       {"propto", "∝"},
    {"sqrt", "√"},       {"parallel", "∥"}, {"perp", "⊥"},       {"ell", "ℓ"},
};

// The accents' command names; none has no command (its empty name parses to none, as any other
// word does).
constexpr EnumNames<TexAccent, 6> kAccents{{"", "vec", "dot", "ddot", "hat", "bar"}};
static_assert(kAccents.complete());

TexAccent accent_of(std::string_view name) {
  return kAccents.parse(name).value_or(TexAccent::none);
}

// Bytes of the UTF-8 character starting with lead byte c.
size_t utf8_length(unsigned char c) {
  return c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 1;
}

bool is_alnum(char c) {
  return std::isalnum((unsigned char)c) != 0;
}

class Parser {
 public:
  explicit Parser(TexText& out) : out_(out) {}

  // Parses src at `shift` with `accent`; scripts (_ ^) only at the top level.
  // `fresh`: start a span of its own (two accents side by side stay apart); a fraction's sides
  // continue the span they are in (one bar over a whole \sqrt{\frac{L}{g}}).
  void parse(std::string_view s, int8_t shift, TexAccent accent, bool top, bool fresh = true) {
    if (fresh) fresh_ = true;
    size_t i = 0;
    while (i < s.size()) {
      const char c = s[i];
      if (c == '\\') {
        i = command(s, i, shift, accent);
        continue;
      }
      if (top && (c == '_' || c == '^')) {
        const int8_t sh = c == '^' ? 1 : -1;
        if (i + 1 < s.size() && s[i + 1] == '{') {
          const size_t close = s.find('}', i + 2);
          if (close != std::string_view::npos) {
            parse(s.substr(i + 2, close - i - 2), sh, TexAccent::none, false);
            fresh_ = true;
            i = close + 1;
            continue;
          }
        } else if (i + 1 < s.size()) {
          const size_t end = atom_end(s, i + 1);
          if (end > i + 1 && (end >= s.size() || !is_alnum(s[end]))) {
            parse_atom(s.substr(i + 1, end - i - 1), sh, TexAccent::none);
            fresh_ = true;
            i = end;
            continue;
          }
        }
      }
      emit(s.substr(i, 1), shift, accent);
      ++i;
    }
  }

 private:
  // A command at s[i] == '\\': returns where parsing goes on.
  size_t command(std::string_view s, size_t i, int8_t shift, TexAccent accent) {
    if (i + 1 >= s.size()) {
      emit("\\", shift, accent);
      return i + 1;
    }
    const char n = s[i + 1];
    if (n == '\\' || n == '{' || n == '}' || n == '_' || n == '^' || n == ' ') {
      emit(s.substr(i + 1, 1), shift, accent);
      return i + 2;
    }
    if (n == ',') {
      emit("\u2009", shift, accent);  // thin space
      return i + 2;
    }
    size_t j = i + 1;
    while (j < s.size() && std::isalpha((unsigned char)s[j])) ++j;
    const std::string_view name = s.substr(i + 1, j - i - 1);
    if (name.empty()) {
      emit("\\", shift, accent);
      return i + 1;
    }
    if (name == "sqrt" || name == "frac") {
      // \sqrt{x}: the radical sign, then x under a bar (the vinculum). \frac{a}{b}: a/b inline,
      // each side in parentheses when it is more than one term ("(a+b)/2").
      size_t k = j;
      if (k < s.size() && s[k] == ' ') ++k;
      const size_t close = k < s.size() && s[k] == '{' ? group_end(s, k) : std::string_view::npos;
      if (name == "sqrt" && close != std::string_view::npos && close > k + 1 && accent == TexAccent::none) {
        emit("\u221a", shift, accent);
        parse(s.substr(k + 1, close - k - 1), shift, TexAccent::overline, false);
        fresh_ = true;
        return close + 1;
      }
      if (name == "frac" && close != std::string_view::npos && close + 1 < s.size() && s[close + 1] == '{') {
        const size_t close2 = group_end(s, close + 1);
        if (close2 != std::string_view::npos) {
          const std::string_view num = s.substr(k + 1, close - k - 1),
                                 den = s.substr(close + 2, close2 - close - 2);
          auto side = [&](std::string_view part) {
            const bool wrap = part.find_first_of("+- ") != std::string_view::npos;
            if (wrap) emit("(", shift, accent);
            parse(part, shift, accent, shift == 0 && accent == TexAccent::none, false);
            if (wrap) emit(")", shift, accent);
          };
          side(num);
          emit("/", shift, accent);
          side(den);
          return close2 + 1;
        }
      }
    }
    if (const TexAccent a = accent_of(name); a != TexAccent::none && accent == TexAccent::none) {
      size_t k = j;
      if (k < s.size() && s[k] == ' ') ++k;
      if (k < s.size() && s[k] == '{') {
        const size_t close = s.find('}', k + 1);
        if (close != std::string_view::npos && close > k + 1) {
          parse(s.substr(k + 1, close - k - 1), shift, a, false);
          fresh_ = true;
          return close + 1;
        }
      } else if (k < s.size()) {
        const size_t end = atom_end(s, k);
        if (end > k) {
          parse_atom(s.substr(k, end - k), shift, a);
          fresh_ = true;
          return end;
        }
      }
    }
    if (const char* sym = tex_symbol(name)) {
      emit(sym, shift, accent);
      return j;
    }
    emit(s.substr(i, j - i), shift, accent);  // unknown: as written
    return j;
  }

  // The '}' closing the group that opens at s[k] == '{' (groups inside it counted), or npos.
  static size_t group_end(std::string_view s, size_t k) {
    int depth = 0;
    for (size_t i = k; i < s.size(); ++i) {
      if (s[i] == '\\') {
        ++i;  // an escaped brace is no brace
        continue;
      }
      if (s[i] == '{') ++depth;
      if (s[i] == '}' && --depth == 0) return i;
    }
    return std::string_view::npos;
  }

  // The end of one character or one \command starting at s[i].
  size_t atom_end(std::string_view s, size_t i) const {
    if (s[i] == '\\') {
      size_t j = i + 1;
      while (j < s.size() && std::isalpha((unsigned char)s[j])) ++j;
      return j > i + 1 && tex_symbol(s.substr(i + 1, j - i - 1)) ? j : i;
    }
    if (s[i] == ' ' || s[i] == '{' || s[i] == '}') return i;
    const size_t n = utf8_length((unsigned char)s[i]);
    return i + n <= s.size() ? i + n : i;
  }

  void parse_atom(std::string_view a, int8_t shift, TexAccent accent) {
    fresh_ = true;
    if (a[0] == '\\')
      emit(tex_symbol(a.substr(1)), shift, accent);
    else
      emit(a, shift, accent);
  }

  void emit(std::string_view bytes, int8_t shift, TexAccent accent) {
    const bool same =
        !out_.spans.empty() && out_.spans.back().shift == shift && out_.spans.back().accent == accent;
    // An accent covers its own group: two accents side by side stay two spans.
    if (!same || (fresh_ && accent != TexAccent::none)) {
      TexSpan sp;
      sp.begin = sp.end = (uint32_t)out_.text.size();
      sp.shift = shift;
      sp.accent = accent;
      out_.spans.push_back(sp);
    }
    fresh_ = false;
    out_.text.append(bytes.data(), bytes.size());
    out_.spans.back().end = (uint32_t)out_.text.size();
  }

  TexText& out_;
  bool fresh_ = true;
};

}  // namespace

const char* tex_symbol(std::string_view name) {
  for (const Symbol& s : kSymbols)
    if (name == s.name) return s.utf8;
  return nullptr;
}

void parse_tex(std::string_view src, TexText& out) {
  out.clear();
  Parser(out).parse(src, 0, TexAccent::none, true);
}

}  // namespace simreel
