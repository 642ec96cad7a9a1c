// HUD and plot expressions (app/scene/scene_overlays.hpp, parse_field): a recursive-descent parser
// that compiles "{a.m * a.v.x + b.m * b.v.x}" to postfix code over the quantities parse_quantity
// reads, so that a frame evaluates it on a fixed stack without allocating.
//
//   expr  := term (('+' | '-') term)*
//   term  := unary (('*' | '/') unary)*
//   unary := '-' unary | power
//   power := atom ('^' unary)?             right-associative: 2^3^2 = 2^9
//   atom  := number | pi | quantity | '(' expr ')' | '|' expr '|' | name '(' args ')'
#include <cctype>
#include <cmath>
#include <numbers>
#include <string>

#include "app/scene/scene.hpp"
#include "app/scene/scene_overlays.hpp"
#include "app/scene/text.hpp"

namespace simreel {

bool HudField::scalar() const {
  if (is_expr() || is_meter() || joint >= 0 || norm || component >= 0) return true;
  if (name == "P") return false;
  if (body < 0) return true;  // t, E, frame, ...
  const auto& n = hud_body_scalar_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

bool HudField::uses(const std::string& n) const {
  if (name == n) return true;
  for (const HudField& t : terms)
    if (t.uses(n)) return true;
  return false;
}

namespace {

double deg(double x) {
  return x * 180.0 / std::numbers::pi;
}
double rad(double x) {
  return x * std::numbers::pi / 180.0;
}
double abs_(double x) {
  return std::fabs(x);
}
double sqrt_(double x) {
  return std::sqrt(x);
}
double sin_(double x) {
  return std::sin(x);
}
double cos_(double x) {
  return std::cos(x);
}
double tan_(double x) {
  return std::tan(x);
}
double exp_(double x) {
  return std::exp(x);
}
double log_(double x) {
  return std::log(x);
}

struct Fn1 {
  const char* name;
  double (*fn)(double);
};
const Fn1 kFns[] = {{"sqrt", sqrt_}, {"abs", abs_}, {"deg", deg},  {"rad", rad}, {"sin", sin_},
                    {"cos", cos_},   {"tan", tan_}, {"exp", exp_}, {"log", log_}};
const char* kMeters = "mean(q) or mean(q, seconds), period(q), last_zero(q), first_contact(a, b)";

std::string strip(const std::string& s) {
  std::string o;
  for (char c : s)
    if (!std::isspace((unsigned char)c)) o += c;
  return o;
}

class Parser {
 public:
  Parser(const std::string& src, const Scene& s, int default_body,
         const std::function<void(const std::string&)>& bad, int nest = 0)
      : src_(src), s_(s), body_(default_body), bad_(bad), nest_(nest) {}

  HudField run() {
    // Nesting is recursion here: a bound keeps a hostile line from exhausting the stack.
    if (nest_ > kMaxNest) fail("nested more than " + std::to_string(kMaxNest) + " deep");
    HudField f;
    f.name = "expr";
    f.source = src_;
    out_ = &f;
    expr();
    skip();
    if (i_ < src_.size()) fail("unexpected '" + src_.substr(i_, 1) + "'");
    // The stack depth the code needs, checked once here so evaluation can use a fixed array.
    int depth = 0, most = 0;
    for (const HudField::Op& op : f.code) {
      depth += op.kind == HudField::Op::number || op.kind == HudField::Op::term ? 1
               : op.kind == HudField::Op::neg || op.kind == HudField::Op::fn1   ? 0
                                                                                : -1;
      most = std::max(most, depth);
    }
    if (most > HudField::kMaxDepth)
      fail("too deeply nested (more than " + std::to_string(HudField::kMaxDepth) + " pending values)");
    return f;
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    bad_(what);
    throw InputError(what);  // bad_ throws; this keeps the compiler's flow analysis honest
  }
  void skip() {
    while (i_ < src_.size() && std::isspace((unsigned char)src_[i_])) ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < src_.size() && src_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void emit(HudField::Op::Kind k) {
    HudField::Op op;
    op.kind = k;
    out_->code.push_back(op);
  }
  void emit_term(HudField t) {
    HudField::Op op;
    op.kind = HudField::Op::term;
    op.arg = (int)out_->terms.size();
    out_->terms.push_back(std::move(t));
    out_->code.push_back(op);
  }

  void expr() {
    term();
    for (;;) {
      if (eat('+'))
        term(), emit(HudField::Op::add);
      else if (eat('-'))
        term(), emit(HudField::Op::sub);
      else
        return;
    }
  }
  void term() {
    unary();
    for (;;) {
      if (eat('*'))
        unary(), emit(HudField::Op::mul);
      else if (eat('/'))
        unary(), emit(HudField::Op::div);
      else
        return;
    }
  }
  void unary() {
    if (eat('-')) {
      unary();
      emit(HudField::Op::neg);
      return;
    }
    eat('+');
    atom();
    if (eat('^')) {
      unary();
      emit(HudField::Op::pow);
    }
  }

  std::string identifier() {
    skip();
    const size_t a = i_;
    while (i_ < src_.size() && (std::isalnum((unsigned char)src_[i_]) || src_[i_] == '_' || src_[i_] == '.'))
      ++i_;
    return src_.substr(a, i_ - a);
  }

  void atom() {
    skip();
    if (i_ >= src_.size()) fail("an expression ends where a value was expected");
    const char c = src_[i_];
    if (std::isdigit((unsigned char)c) ||
        (c == '.' && i_ + 1 < src_.size() && std::isdigit((unsigned char)src_[i_ + 1]))) {
      size_t used = 0;
      double v = 0;
      try {
        v = std::stod(src_.substr(i_), &used);
      } catch (const std::exception&) {
        fail("'" + src_.substr(i_) + "' is not a number");
      }
      i_ += used;
      HudField::Op op;
      op.kind = HudField::Op::number, op.value = v;
      out_->code.push_back(op);
      return;
    }
    if (eat('(')) {
      if (++nest_ > kMaxNest) fail("nested more than " + std::to_string(kMaxNest) + " deep");
      expr();
      --nest_;
      if (!eat(')')) fail("a '(' without its ')'");
      return;
    }
    if (c == '|') {
      ++i_;
      const size_t close = src_.find('|', i_);
      if (close == std::string::npos) fail("a '|' without its closing '|'");
      const std::string inner = src_.substr(i_, close - i_);
      i_ = close + 1;
      Parser sub(inner, s_, body_, bad_, nest_ + 1);
      HudField in = sub.run();
      // |v| of a vector quantity is its length; of a number, its absolute value.
      if (in.code.size() == 1 && in.code[0].kind == HudField::Op::term && !in.terms[0].scalar()) {
        HudField q = in.terms[0];
        if (q.component >= 0) fail("'|" + inner + "|': a component or |...|, not both");
        q.norm = true;
        emit_term(std::move(q));
        return;
      }
      splice(in);
      HudField::Op op;
      op.kind = HudField::Op::fn1, op.fn = abs_;
      out_->code.push_back(op);
      return;
    }
    const std::string id = identifier();
    if (id.empty()) fail("unexpected '" + src_.substr(i_, 1) + "'");
    if (eat('(')) {
      call(id, arguments(id));
      return;
    }
    if (id == "first_contact") {  // of any two bodies: no arguments, no parentheses needed
      call(id, {});
      return;
    }
    if (id == "pi") {
      HudField::Op op;
      op.kind = HudField::Op::number, op.value = std::numbers::pi;
      out_->code.push_back(op);
      return;
    }
    for (const Fn1& f : kFns)
      if (id == f.name) fail("'" + id + "' is a function: write " + id + "(x)");
    HudField q = parse_quantity(id, s_, body_, [&](const std::string& what) { fail(what); });
    if (!q.scalar())
      fail("'" + id + "' is a vector: take a component (" + id + ".x) or its length |" + id + "|");
    emit_term(std::move(q));
  }

  // The code and terms of a sub-expression appended to ours (its term indices shifted).
  void splice(const HudField& in) {
    const int base = (int)out_->terms.size();
    for (const HudField& t : in.terms) out_->terms.push_back(t);
    for (HudField::Op op : in.code) {
      if (op.kind == HudField::Op::term) op.arg += base;
      out_->code.push_back(op);
    }
  }

  // The text of a call's arguments up to its ')' (commas at depth 0 split them).
  std::vector<std::string> arguments(const std::string& fn) {
    std::vector<std::string> args;
    int depth = 0;
    std::string cur;
    bool bar = false;
    for (; i_ < src_.size(); ++i_) {
      const char c = src_[i_];
      if (c == '|') bar = !bar;
      if (c == '(') ++depth;
      if (c == ')' && depth-- == 0) {
        ++i_;
        if (!strip(cur).empty() || !args.empty()) args.push_back(cur);
        return args;
      }
      if (c == ',' && depth == 0 && !bar) {
        args.push_back(cur), cur.clear();
        continue;
      }
      cur += c;
    }
    fail("'" + fn + "(' without its ')'");
  }

  // A measured value's argument: a number of the present state, not itself measured.
  HudField argument(const std::string& fn, const std::string& text) {
    Parser sub(text, s_, body_, bad_, nest_ + 1);
    HudField a = sub.run();
    for (const HudField& t : a.terms) {
      if (t.is_meter() || t.name.starts_with("period"))
        fail(fn + "(...) measures a quantity of the present state; '" + strip(text) +
             "' is already measured over time");
      if (t.name == "frame" || t.name == "video_t")
        fail(fn + "(...) is measured at each physics step, where there is no video frame: '" + t.name +
             "' has no value there (use t)");
    }
    // A lone quantity is kept as itself (a joint's angle keeps its exact rate for period()).
    if (a.code.size() == 1 && a.code[0].kind == HudField::Op::term) return a.terms[0];
    return a;
  }

  int body_named(const std::string& text) {
    const std::string name = strip(text);
    for (size_t b = 0; b < s_.bodies.size(); ++b)
      if (s_.bodies[b].name == name) return (int)b;
    std::vector<std::string> names;
    for (const BodyDef& b : s_.bodies) names.push_back(b.name);
    std::string msg = "no body is named '" + name + "'";
    if (auto sug = nearest(name, names)) msg += "; did you mean '" + *sug + "'?";
    fail(msg);
  }

  void call(const std::string& fn, const std::vector<std::string>& args) {
    auto count = [&](size_t lo, size_t hi) {
      if (args.size() < lo || args.size() > hi)
        fail(fn + "(...) takes " +
             (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi)) +
             " argument" + (hi == 1 ? "" : "s") + ", got " + std::to_string(args.size()));
    };
    for (const Fn1& f : kFns)
      if (fn == f.name) {
        count(1, 1);
        Parser sub(args[0], s_, body_, bad_, nest_ + 1);
        splice(sub.run());
        HudField::Op op;
        op.kind = HudField::Op::fn1, op.fn = f.fn;
        out_->code.push_back(op);
        return;
      }
    if (fn == "atan2") {
      count(2, 2);
      for (int k = 0; k < 2; ++k) {
        Parser sub(args[k], s_, body_, bad_, nest_ + 1);
        splice(sub.run());
      }
      emit(HudField::Op::atan2);
      return;
    }
    HudField m;
    m.source = fn + "(";
    for (size_t k = 0; k < args.size(); ++k) m.source += (k ? "," : "") + strip(args[k]);
    m.source += ")";
    if (fn == "mean") {
      count(1, 2);
      m.name = "mean";
      m.terms.push_back(argument(fn, args[0]));
      if (args.size() == 2) {
        const std::string w = strip(args[1]);
        size_t used = 0;
        double T = 0;
        try {
          T = std::stod(w, &used);
        } catch (const std::exception&) {
        }
        if (used != w.size() || !(T > 0) || !std::isfinite(T))
          fail("mean(q, T): T is the averaging window, a number of seconds > 0, got '" + w + "'");
        m.window = T;
      }
    } else if (fn == "period") {
      count(1, 1);
      HudField a = argument(fn, args[0]);
      if (a.joint >= 0 && a.name.starts_with("angle")) {  // a joint's own period, from its exact rate
        a.name = a.coord == 1 ? "period2" : "period";
        if (s_.joints[a.joint].type == JointType::spherical)
          fail("joint '" + s_.joints[a.joint].name +
               "' is spherical: its angle never changes sign, so it has no period to measure");
        emit_term(std::move(a));
        return;
      }
      m.name = "period_of";
      m.terms.push_back(std::move(a));
    } else if (fn == "last_zero") {
      count(1, 1);
      m.name = "last_zero";
      m.terms.push_back(argument(fn, args[0]));
    } else if (fn == "first_contact") {
      count(0, 2);
      m.name = "first_contact";
      if (args.size() >= 1) m.body = body_named(args[0]);
      if (args.size() == 2) m.body2 = body_named(args[1]);
      if (m.body >= 0 && m.body == m.body2) fail("first_contact(a, b) of a body with itself");
    } else {
      std::vector<std::string> names = {"atan2", "mean", "period", "last_zero", "first_contact"};
      for (const Fn1& f : kFns) names.push_back(f.name);
      std::string msg = "unknown function '" + fn + "'";
      if (auto sug = nearest(fn, names)) msg += "; did you mean '" + *sug + "'?";
      fail(msg + " (sqrt, abs, deg, rad, sin, cos, tan, exp, log, atan2; measured: " + kMeters + ")");
    }
    emit_term(std::move(m));
  }

  static constexpr int kMaxNest = 64;
  const std::string& src_;
  const Scene& s_;
  int body_;
  const std::function<void(const std::string&)>& bad_;
  int nest_ = 0;
  size_t i_ = 0;
  HudField* out_ = nullptr;
};

// Whether `field` is written as a single quantity ([|][name][.name...][|]), the old form that
// also names whole vectors.
bool plain_quantity(const std::string& field) {
  std::string f = strip(field);
  if (f.size() >= 2 && f.front() == '|' && f.back() == '|') f = f.substr(1, f.size() - 2);
  if (f.empty() || std::isdigit((unsigned char)f[0])) return false;
  for (char c : f)
    if (!(std::isalnum((unsigned char)c) || c == '_' || c == '.')) return false;
  if (f == "pi" || f == "first_contact") return false;
  for (const Fn1& fn : kFns)
    if (f == fn.name) return false;
  return true;
}

}  // namespace

HudField parse_field(const std::string& field, const Scene& s, int default_body,
                     const std::function<void(const std::string&)>& bad) {
  if (plain_quantity(field)) return parse_quantity(strip(field), s, default_body, bad);
  Parser p(field, s, default_body, bad);
  HudField f = p.run();
  // A lone term (a measured value, or a quantity in parentheses) is that term.
  if (f.code.size() == 1 && f.code[0].kind == HudField::Op::term) {
    return f.terms[0];
  }
  return f;
}

}  // namespace simreel
