// The scan of a STEP or IGES file's text that runs before OpenCASCADE reads it (Readers.h).
//
// STEP: one pass over the text tokenises every entity instance `#n = ...;` (strings, comments
// and complex instances included), keeps its references and its place in the text, and checks
// that the file ends: an entity, a string or a comment cut off, a DATA section without ENDSEC or
// a file without END-ISO-10303-21 is a truncated file. Then the reference graph is searched for
// cycles (an entity that refers to itself, directly or through others: the STEP entity graph is
// acyclic, and OpenCASCADE's transfer follows references without a guard), and every B-spline
// entity is parsed: its control points count against Import_limits, and its degrees, knots,
// multiplicities and weights are checked against ISO 10303-42's rules.
// IGES: the fixed 80-column records are split into their sections; the file must end with its
// Terminate record, every directory entry must point at parameter lines the file has, and the
// B-spline curves (126) and surfaces (128) announce counts that must fit the limits and the
// parameters the entity actually holds (OpenCASCADE sizes its arrays from the announcement).
// Memory: the text is held by the caller; the scan keeps about 40 bytes per entity and 8 per
// reference, and parses at most one B-spline entity at a time (within the patch limit).
#include "io/internal/Readers.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "kernel/Error.h"

namespace extremal::io::internal {

namespace {

// IGES entity types (IGES 5.3, section 4): the rational B-spline curve and surface.
constexpr long long kIgesBsplineCurve = 126;
constexpr long long kIgesBsplineSurface = 128;

// Parenthesis nesting of one STEP entity: B-spline surfaces with weights nest 4 deep inside a
// complex instance; 64 leaves room for any schema and bounds the recursive parse below.
constexpr int kMaxStepNesting = 64;
// The highest B-spline degree OpenCASCADE (Geom_BSplineSurface::MaxDegree) and the kernel read.
constexpr int kMaxDegree = 25;
// Cycles listed in a message: the entities named, at most.
constexpr std::size_t kCycleEntitiesShown = 6;

std::string limit_text(std::size_t value, const char* field, const char* option) {
  std::ostringstream os;
  os << value << " (Import_limits::" << field << ", extremal " << option << ")";
  return os.str();
}

// ---- STEP -----------------------------------------------------------------------------------

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_keyword_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || is_digit(c) || c == '_' || c == '-' ||
         c == '!';
}
bool is_keyword_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '!';
}

enum class Tok { End, Keyword, Ref, Number, String, Binary, Enum, Open, Close, Comma, Semicolon,
                 Equals, Unset, Derived, Other };

struct Token {
  Tok kind = Tok::End;
  std::size_t begin = 0, end = 0;  // text of the token
};

// Tokens of Part 21 text. A string, binary or comment that runs to the end of the text sets
// `cut_off` (and ends the token stream), so the caller can name a truncated file.
class Step_lexer {
 public:
  explicit Step_lexer(std::string_view text, std::size_t pos = 0) : m_s(text), m_pos(pos) {}

  Token next() {
    skip_blank();
    Token t;
    t.begin = m_pos;
    if (m_pos >= m_s.size()) return t;
    const char c = m_s[m_pos];
    if (c == '\'') {
      ++m_pos;
      while (true) {
        const std::size_t q = m_s.find('\'', m_pos);
        if (q == std::string_view::npos) return cut();
        m_pos = q + 1;
        if (m_pos < m_s.size() && m_s[m_pos] == '\'') {
          ++m_pos;  // '' inside a string
          continue;
        }
        break;
      }
      t.kind = Tok::String;
    } else if (c == '"') {
      const std::size_t q = m_s.find('"', m_pos + 1);
      if (q == std::string_view::npos) return cut();
      m_pos = q + 1;
      t.kind = Tok::Binary;
    } else if (c == '#' || c == '@') {
      ++m_pos;
      while (m_pos < m_s.size() && is_digit(m_s[m_pos])) ++m_pos;
      t.kind = c == '#' ? Tok::Ref : Tok::Other;
    } else if (c == '.' && m_pos + 1 < m_s.size() && is_keyword_start(m_s[m_pos + 1])) {
      const std::size_t q = m_s.find('.', m_pos + 1);
      m_pos = q == std::string_view::npos ? m_s.size() : q + 1;
      t.kind = Tok::Enum;
    } else if (is_digit(c) || c == '+' || c == '-' || c == '.') {
      ++m_pos;
      while (m_pos < m_s.size() &&
             (is_digit(m_s[m_pos]) || m_s[m_pos] == '.' || m_s[m_pos] == 'E' || m_s[m_pos] == 'e' ||
              ((m_s[m_pos] == '+' || m_s[m_pos] == '-') &&
               (m_s[m_pos - 1] == 'E' || m_s[m_pos - 1] == 'e'))))
        ++m_pos;
      t.kind = Tok::Number;
    } else if (is_keyword_start(c)) {
      while (m_pos < m_s.size() && is_keyword_char(m_s[m_pos])) ++m_pos;
      t.kind = Tok::Keyword;
    } else {
      ++m_pos;
      switch (c) {
        case '(': t.kind = Tok::Open; break;
        case ')': t.kind = Tok::Close; break;
        case ',': t.kind = Tok::Comma; break;
        case ';': t.kind = Tok::Semicolon; break;
        case '=': t.kind = Tok::Equals; break;
        case '$': t.kind = Tok::Unset; break;
        case '*': t.kind = Tok::Derived; break;
        default: t.kind = Tok::Other; break;
      }
    }
    t.end = m_pos;
    return t;
  }

  bool cut_off() const { return m_cut; }
  std::size_t pos() const { return m_pos; }

 private:
  void skip_blank() {
    while (m_pos < m_s.size()) {
      if (is_space(m_s[m_pos])) {
        ++m_pos;
      } else if (m_s[m_pos] == '/' && m_pos + 1 < m_s.size() && m_s[m_pos + 1] == '*') {
        const std::size_t q = m_s.find("*/", m_pos + 2);
        if (q == std::string_view::npos) {
          m_pos = m_s.size();
          m_cut = true;
          return;
        }
        m_pos = q + 2;
      } else {
        return;
      }
    }
  }

  Token cut() {
    m_pos = m_s.size();
    m_cut = true;
    return Token{};
  }

  std::string_view m_s;
  std::size_t m_pos;
  bool m_cut = false;
};

struct Step_entity {
  std::uint64_t id = 0;
  std::size_t begin = 0, end = 0;  // the record: from after '=' to before ';'
  std::uint32_t first_ref = 0, n_refs = 0;
  bool spline = false;             // a B-spline curve or surface (simple or complex)
};

bool is_spline_keyword(std::string_view k) {
  static const char* names[] = {"B_SPLINE_SURFACE_WITH_KNOTS", "B_SPLINE_SURFACE", "BEZIER_SURFACE",
                                "UNIFORM_SURFACE", "QUASI_UNIFORM_SURFACE",
                                "RATIONAL_B_SPLINE_SURFACE", "B_SPLINE_CURVE_WITH_KNOTS",
                                "B_SPLINE_CURVE", "BEZIER_CURVE", "UNIFORM_CURVE",
                                "QUASI_UNIFORM_CURVE", "RATIONAL_B_SPLINE_CURVE"};
  for (const char* n : names)
    if (k.size() == std::char_traits<char>::length(n) &&
        std::equal(k.begin(), k.end(), n, [](char a, char b) {
          return (a >= 'a' && a <= 'z' ? static_cast<char>(a - 32) : a) == b;
        }))
      return true;
  return false;
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 32);
  return u;
}

// One parsed parameter of a B-spline entity.
struct Value {
  enum Kind { List, Typed, Ref, Number, Other } kind = Other;
  double number = 0.0;
  bool integer = false;
  std::string keyword;        // Typed: the type (also a complex instance's part)
  std::vector<Value> items;   // List, Typed
};

class Record_parser {
 public:
  Record_parser(std::string_view text, std::size_t begin) : m_lex(text, begin), m_text(text) {
    advance();
  }

  // The record as a list of typed parts: one for a simple instance, several for a complex one.
  std::vector<Value> parts() {
    std::vector<Value> out;
    if (m_tok.kind == Tok::Open) {
      advance();
      while (m_tok.kind == Tok::Keyword) out.push_back(typed(0));
    } else if (m_tok.kind == Tok::Keyword) {
      out.push_back(typed(0));
    }
    return out;
  }

 private:
  Value typed(int depth) {
    Value v;
    v.kind = Value::Typed;
    v.keyword = upper(m_text.substr(m_tok.begin, m_tok.end - m_tok.begin));
    advance();
    if (m_tok.kind == Tok::Open) v.items = list(depth + 1);
    return v;
  }

  std::vector<Value> list(int depth) {
    std::vector<Value> items;
    advance();  // '('
    while (m_tok.kind != Tok::Close && m_tok.kind != Tok::End && m_tok.kind != Tok::Semicolon) {
      if (m_tok.kind == Tok::Comma) {
        advance();
        continue;
      }
      items.push_back(value(depth));
    }
    if (m_tok.kind == Tok::Close) advance();
    return items;
  }

  Value value(int depth) {
    Value v;
    if (depth > kMaxStepNesting) {  // the first pass refuses deeper records; never reached
      advance();
      return v;
    }
    switch (m_tok.kind) {
      case Tok::Open:
        v.kind = Value::List;
        v.items = list(depth + 1);
        return v;
      case Tok::Keyword:
        return typed(depth);
      case Tok::Ref:
        v.kind = Value::Ref;
        break;
      case Tok::Number: {
        std::string_view s = m_text.substr(m_tok.begin, m_tok.end - m_tok.begin);
        if (!s.empty() && s.front() == '+') s.remove_prefix(1);
        double x = 0.0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), x);
        if (r.ec == std::errc() && r.ptr == s.data() + s.size()) {
          v.kind = Value::Number;
          v.number = x;
          v.integer = s.find_first_of(".eE") == std::string_view::npos;
        }
        break;
      }
      default:
        break;
    }
    advance();
    return v;
  }

  void advance() { m_tok = m_lex.next(); }

  Step_lexer m_lex;
  std::string_view m_text;
  Token m_tok;
};

const Value* part(const std::vector<Value>& parts, const char* keyword) {
  for (const Value& p : parts)
    if (p.keyword == keyword) return &p;
  return nullptr;
}

const Value* item(const Value* v, std::size_t i) {
  return v && i < v->items.size() ? &v->items[i] : nullptr;
}

// "degree" -> the integer, or an explanation in `problem`.
bool read_degree(const Value* v, const char* what, int& degree, std::string& problem) {
  if (!v || v->kind != Value::Number || !v->integer) {
    problem = std::string(what) + " is not an integer";
    return false;
  }
  if (v->number < 1 || v->number > kMaxDegree) {
    std::ostringstream os;
    os << what << " " << v->number << " is outside 1.." << kMaxDegree;
    problem = os.str();
    return false;
  }
  degree = static_cast<int>(v->number);
  return true;
}

// ISO 10303-42 constraints_param_b_spline for one direction: distinct knots strictly
// increasing, multiplicities from 1 to degree + 1 (degree inside), and their sum the number of
// control points + degree + 1.
bool check_knots(const Value* mults, const Value* knots, int degree, std::size_t poles,
                 const std::string& what, std::string& problem) {
  std::ostringstream os;
  if (!mults || mults->kind != Value::List || !knots || knots->kind != Value::List) {
    problem = what + "multiplicities or knots are not lists";
    return false;
  }
  if (mults->items.size() != knots->items.size()) {
    os << what << "knots: " << mults->items.size() << " multiplicities for " << knots->items.size()
       << " distinct knots";
    problem = os.str();
    return false;
  }
  if (knots->items.size() < 2) {
    os << what << "knots: " << knots->items.size() << " distinct knots (at least 2 needed)";
    problem = os.str();
    return false;
  }
  std::uint64_t sum = 0;
  const std::size_t n = knots->items.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Value& k = knots->items[i];
    const Value& m = mults->items[i];
    if (k.kind != Value::Number || !std::isfinite(k.number)) {
      os << what << "knot " << i + 1 << " is not a finite number";
      problem = os.str();
      return false;
    }
    if (i > 0 && !(k.number > knots->items[i - 1].number)) {
      os << what << "knots are not strictly increasing: knot " << i + 1 << " (" << k.number
         << ") follows " << knots->items[i - 1].number;
      if (k.number == knots->items[i - 1].number) os << " (a zero-length knot span)";
      problem = os.str();
      return false;
    }
    const bool end = i == 0 || i + 1 == n;
    if (m.kind != Value::Number || !m.integer || m.number < 1 ||
        m.number > degree + (end ? 1 : 0)) {
      os << what << "knot " << i + 1 << " has multiplicity " << m.number << ", not 1.."
         << degree + (end ? 1 : 0) << (end ? "" : " (inside the knot range)");
      problem = os.str();
      return false;
    }
    sum += static_cast<std::uint64_t>(m.number);
  }
  if (sum != poles + static_cast<std::uint64_t>(degree) + 1) {
    os << what << "knot multiplicities add up to " << sum << ", expected " << poles + degree + 1 << " ("
       << poles << " control points + degree " << degree << " + 1)";
    problem = os.str();
    return false;
  }
  return true;
}

bool check_weights(const Value* w, std::size_t rows, std::size_t cols, bool grid,
                   std::string& problem) {
  auto positive = [&](const Value& x) {
    return x.kind == Value::Number && std::isfinite(x.number) && x.number > 0.0;
  };
  if (!w || w->kind != Value::List) {
    problem = "the weights are not a list";
    return false;
  }
  std::ostringstream os;
  if (!grid) {
    if (w->items.size() != cols) {
      os << w->items.size() << " weights for " << cols << " control points";
      problem = os.str();
      return false;
    }
    for (const Value& x : w->items)
      if (!positive(x)) {
        problem = "a weight is not a finite number > 0";
        return false;
      }
    return true;
  }
  if (w->items.size() != rows) {
    os << w->items.size() << " rows of weights for " << rows << " rows of control points";
    problem = os.str();
    return false;
  }
  for (const Value& row : w->items) {
    if (row.kind != Value::List || row.items.size() != cols) {
      problem = "the weights' rows do not match the control points' rows";
      return false;
    }
    for (const Value& x : row.items)
      if (!positive(x)) {
        problem = "a weight is not a finite number > 0";
        return false;
      }
  }
  return true;
}

// Checks one B-spline entity's parameters; returns the problem, empty when none.
std::string check_spline(const std::vector<Value>& parts) {
  std::string problem;
  if (parts.empty()) return "not a B-spline entity the scan understands";
  const bool simple = parts.size() == 1;
  const Value& first = parts.front();
  const bool surface = [&] {
    for (const Value& p : parts)
      if (p.keyword.find("SURFACE") != std::string::npos) return true;
    return false;
  }();
  // Where the geometry and the knots are: a simple instance holds both after its name; a
  // complex one holds them in its B_SPLINE_... and ..._WITH_KNOTS parts.
  // RATIONAL_B_SPLINE_... is only ever a part of a complex instance.
  if (simple && first.keyword.rfind("RATIONAL_", 0) == 0) return {};
  const Value* geometry = simple ? &first : part(parts, surface ? "B_SPLINE_SURFACE" : "B_SPLINE_CURVE");
  const std::size_t g0 = simple ? 1 : 0;
  const Value* knots_part =
      simple ? (first.keyword.find("WITH_KNOTS") != std::string::npos ? &first : nullptr)
             : part(parts, surface ? "B_SPLINE_SURFACE_WITH_KNOTS" : "B_SPLINE_CURVE_WITH_KNOTS");
  const Value* rational =
      simple ? nullptr : part(parts, surface ? "RATIONAL_B_SPLINE_SURFACE" : "RATIONAL_B_SPLINE_CURVE");
  if (!geometry) return "a complex B-spline instance without its B_SPLINE_ part";

  if (surface) {
    int du = 0, dv = 0;
    if (!read_degree(item(geometry, g0), "the u degree", du, problem) ||
        !read_degree(item(geometry, g0 + 1), "the v degree", dv, problem))
      return problem;
    const Value* cp = item(geometry, g0 + 2);
    if (!cp || cp->kind != Value::List || cp->items.empty())
      return "the control points are not a list of rows";
    const std::size_t rows = cp->items.size();
    const std::size_t cols = cp->items.front().items.size();
    for (const Value& row : cp->items) {
      if (row.kind != Value::List || row.items.size() != cols)
        return "the control points' rows are not lists of the same length";
      for (const Value& p : row.items)
        if (p.kind != Value::Ref) return "a control point is not an entity reference";
    }
    if (knots_part) {
      const std::size_t k0 = simple ? 8 : 0;
      if (!check_knots(item(knots_part, k0), item(knots_part, k0 + 2), du, rows, "u ", problem) ||
          !check_knots(item(knots_part, k0 + 1), item(knots_part, k0 + 3), dv, cols, "v ", problem))
        return problem;
    } else if (rows < static_cast<std::size_t>(du) + 1 || cols < static_cast<std::size_t>(dv) + 1) {
      return "fewer control points than the degree + 1";
    }
    if (rational && !check_weights(item(rational, 0), rows, cols, true, problem)) return problem;
    return {};
  }
  int d = 0;
  if (!read_degree(item(geometry, g0), "the degree", d, problem)) return problem;
  const Value* cp = item(geometry, g0 + 1);
  if (!cp || cp->kind != Value::List) return "the control points are not a list";
  for (const Value& p : cp->items)
    if (p.kind != Value::Ref) return "a control point is not an entity reference";
  const std::size_t n = cp->items.size();
  if (knots_part) {
    const std::size_t k0 = simple ? 6 : 0;
    if (!check_knots(item(knots_part, k0), item(knots_part, k0 + 1), d, n, "", problem))
      return problem;
  } else if (n < static_cast<std::size_t>(d) + 1) {
    return "fewer control points than the degree + 1";
  }
  if (rational && !check_weights(item(rational, 0), 1, n, false, problem)) return problem;
  return {};
}

class Step_scan {
 public:
  Step_scan(const std::string& name, const std::string& bytes, const Import_limits& limits,
            Cad_scan& out)
      : m_name(name), m_text(bytes), m_limits(limits), m_out(out) {}

  void run() {
    tokenise();
    resolve_references();
    find_cycles();
    check_splines();
  }

 private:
  [[noreturn]] void refuse(const std::string& what) const {
    throw Invalid_input(m_name + ": " + what);
  }

  std::size_t line_of(std::size_t pos) const {
    return 1 + static_cast<std::size_t>(std::count(m_text.begin(), m_text.begin() +
                                                   static_cast<std::ptrdiff_t>(std::min(pos, m_text.size())), '\n'));
  }

  std::string keyword_at(std::size_t pos) const {
    Step_lexer lex(m_text, pos);
    Token t = lex.next();
    if (t.kind == Tok::Open) {  // complex instance: its parts' keywords
      std::string names = "(";
      int depth = 1;
      while (depth > 0) {
        t = lex.next();
        if (t.kind == Tok::End || t.kind == Tok::Semicolon) break;
        if (t.kind == Tok::Open) ++depth;
        if (t.kind == Tok::Close) --depth;
        if (t.kind == Tok::Keyword && depth == 1) {
          if (names.size() > 1) names += ' ';
          names += upper(m_text.substr(t.begin, t.end - t.begin));
        }
      }
      return names + ")";
    }
    if (t.kind == Tok::Keyword) return upper(m_text.substr(t.begin, t.end - t.begin));
    return "?";
  }

  std::string label(const Step_entity& e) const {
    return "STEP #" + std::to_string(e.id) + " (" + keyword_at(e.begin) + ")";
  }

  void tokenise() {
    const std::string_view text(m_text);
    const bool bom = text.substr(0, 3) == "\xEF\xBB\xBF";
    Step_lexer lex(text, bom ? 3 : 0);
    Token t = lex.next();
    if (t.kind != Tok::Keyword || upper(text.substr(t.begin, t.end - t.begin)) != "ISO-10303-21")
      refuse("not a STEP file (it does not start with ISO-10303-21)");
    bool in_data = false, seen_data = false, seen_end = false;
    while (!seen_end) {
      t = lex.next();
      if (t.kind == Tok::End) break;
      if (t.kind == Tok::Keyword) {
        const std::string k = upper(text.substr(t.begin, t.end - t.begin));
        if (k == "DATA") {
          in_data = seen_data = true;
          skip_record(lex, t);  // DATA; or DATA(name, schemas);
        } else if (k == "ENDSEC") {
          in_data = false;
        } else if (k == "END-ISO-10303-21") {
          seen_end = true;
        } else if (in_data) {
          refuse("line " + std::to_string(line_of(t.begin)) + ": '" + std::string(k) +
                 "' where an entity instance (#n = ...) should be");
        } else {
          skip_record(lex, t);  // a header entity
        }
        continue;
      }
      if (t.kind == Tok::Ref && in_data) {
        read_instance(lex, t);
        continue;
      }
      if (t.kind == Tok::Semicolon || t.kind == Tok::Open || t.kind == Tok::Close ||
          t.kind == Tok::String || t.kind == Tok::Comma) {
        if (in_data && t.kind != Tok::Semicolon)
          refuse("line " + std::to_string(line_of(t.begin)) +
                 ": unexpected text where an entity instance (#n = ...) should be");
        if (t.kind == Tok::Open) skip_record(lex, t);
        continue;
      }
      if (in_data)
        refuse("line " + std::to_string(line_of(t.begin)) +
               ": unexpected text where an entity instance (#n = ...) should be");
    }
    if (lex.cut_off())
      refuse("the file ends inside a string or comment (line " +
             std::to_string(line_of(m_text.size())) + "): it is truncated");
    if (in_data)
      refuse("the DATA section has no ENDSEC: the file is truncated after " +
             (m_entities.empty() ? std::string("its DATA line") : label(m_entities.back())));
    if (!seen_data) refuse("no DATA section");
    if (!seen_end) refuse("no END-ISO-10303-21 after the data: the file is truncated");
  }

  // Skips a header entity's parameters: KEYWORD ( ... ) ;
  void skip_record(Step_lexer& lex, Token t) {
    int depth = t.kind == Tok::Open ? 1 : 0;
    while (true) {
      t = lex.next();
      if (t.kind == Tok::End) return;
      if (t.kind == Tok::Open) ++depth;
      if (t.kind == Tok::Close) --depth;
      if (t.kind == Tok::Semicolon && depth <= 0) return;
    }
  }

  void read_instance(Step_lexer& lex, const Token& name) {
    Step_entity e;
    const std::string_view digits(m_text.data() + name.begin + 1, name.end - name.begin - 1);
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), e.id);
    if (digits.empty() || r.ec != std::errc())
      refuse("line " + std::to_string(line_of(name.begin)) + ": bad entity name '" +
             std::string(m_text.substr(name.begin, name.end - name.begin)) + "'");
    const std::string who = "entity #" + std::to_string(e.id);
    Token t = lex.next();
    if (t.kind != Tok::Equals)
      refuse("line " + std::to_string(line_of(name.begin)) + ": " + who + " has no '='");
    e.begin = lex.pos();
    e.first_ref = static_cast<std::uint32_t>(m_refs.size());
    bool complex = false;
    int depth = 0;
    bool first = true;
    while (true) {
      t = lex.next();
      if (t.kind == Tok::End)
        refuse("the file ends inside " + who + " (line " + std::to_string(line_of(name.begin)) +
               "): it is truncated");
      if (first) {
        complex = t.kind == Tok::Open;
        first = false;
      }
      if (t.kind == Tok::Open) {
        if (++depth > kMaxStepNesting)
          refuse(who + " (line " + std::to_string(line_of(name.begin)) + ") nests lists deeper than " +
                 std::to_string(kMaxStepNesting) + " levels");
      } else if (t.kind == Tok::Close) {
        if (--depth < 0)
          refuse(who + " (line " + std::to_string(line_of(name.begin)) +
                 ") closes more parentheses than it opens");
      } else if (t.kind == Tok::Semicolon) {
        if (depth == 0) break;
        refuse(who + " (line " + std::to_string(line_of(name.begin)) +
               ") ends before its parentheses close");
      } else if (t.kind == Tok::Ref) {
        std::uint64_t id = 0;
        const auto rr = std::from_chars(m_text.data() + t.begin + 1, m_text.data() + t.end, id);
        if (rr.ec != std::errc() || t.end == t.begin + 1)
          refuse(who + " (line " + std::to_string(line_of(name.begin)) + "): bad reference '" +
                 std::string(m_text.substr(t.begin, t.end - t.begin)) + "'");
        if (m_refs.size() >= std::numeric_limits<std::uint32_t>::max())
          refuse("more than 2^32 references");
        m_refs.push_back(id);
      } else if (t.kind == Tok::Keyword && depth == (complex ? 1 : 0) &&
                 is_spline_keyword(m_text.substr(t.begin, t.end - t.begin))) {
        e.spline = true;
      }
    }
    e.end = t.begin;
    e.n_refs = static_cast<std::uint32_t>(m_refs.size() - e.first_ref);
    m_entities.push_back(e);
  }

  // References become entity indices (kNone for an undefined entity: OpenCASCADE reports
  // those); a name defined twice is refused.
  void resolve_references() {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> ids(m_entities.size());
    for (std::size_t i = 0; i < m_entities.size(); ++i)
      ids[i] = {m_entities[i].id, static_cast<std::uint32_t>(i)};
    std::sort(ids.begin(), ids.end());
    for (std::size_t i = 1; i < ids.size(); ++i)
      if (ids[i].first == ids[i - 1].first)
        refuse("entity #" + std::to_string(ids[i].first) + " is defined twice (lines " +
               std::to_string(line_of(m_entities[std::min(ids[i].second, ids[i - 1].second)].begin)) +
               " and " +
               std::to_string(line_of(m_entities[std::max(ids[i].second, ids[i - 1].second)].begin)) +
               ")");
    m_targets.resize(m_refs.size());
    for (std::size_t r = 0; r < m_refs.size(); ++r) {
      const auto it = std::lower_bound(ids.begin(), ids.end(),
                                       std::make_pair(m_refs[r], std::uint32_t{0}));
      m_targets[r] = it != ids.end() && it->first == m_refs[r] ? it->second : kNone;
    }
    m_refs.clear();
    m_refs.shrink_to_fit();
  }

  // Depth-first search without recursion; a reference to an entity on the current path closes a
  // cycle, which names every entity on it (up to kCycleEntitiesShown).
  void find_cycles() {
    enum : std::uint8_t { White, Grey, Black };
    std::vector<std::uint8_t> colour(m_entities.size(), White);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;  // entity, next reference
    for (std::uint32_t root = 0; root < m_entities.size(); ++root) {
      if (colour[root] != White) continue;
      stack.push_back({root, 0});
      colour[root] = Grey;
      while (!stack.empty()) {
        auto& [node, next] = stack.back();
        const Step_entity& e = m_entities[node];
        if (next == e.n_refs) {
          colour[node] = Black;
          stack.pop_back();
          continue;
        }
        const std::uint32_t child = m_targets[e.first_ref + next++];
        if (child == kNone) continue;
        if (colour[child] == Grey) report_cycle(stack, child);
        if (colour[child] == White) {
          colour[child] = Grey;
          stack.push_back({child, 0});
        }
      }
    }
  }

  [[noreturn]] void report_cycle(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& stack,
                                 std::uint32_t back_to) const {
    const Step_entity& target = m_entities[back_to];
    if (stack.back().first == back_to)
      refuse(label(target) + " refers to itself (line " + std::to_string(line_of(target.begin)) +
             ")");
    std::size_t at = stack.size() - 1;  // the stack from `at` on is the cycle, back_to first
    while (at > 0 && stack[at].first != back_to) --at;
    std::ostringstream os;
    os << label(target) << " refers back to itself:";
    std::size_t shown = 0;
    for (std::size_t k = at; k < stack.size(); ++k) {
      if (++shown > kCycleEntitiesShown) {
        os << " -> ... (" << stack.size() - at << " entities)";
        break;
      }
      os << (k == at ? " #" : " -> #") << m_entities[stack[k].first].id;
    }
    os << " -> #" << target.id << " (a reference cycle, line " << line_of(target.begin) << ")";
    refuse(os.str());
  }

  void check_splines() {
    std::uint64_t total = 0;
    for (const Step_entity& e : m_entities) {
      if (!e.spline) continue;
      // Every reference of a B-spline entity is a control point.
      if (m_limits.max_patch_poles > 0 && e.n_refs > m_limits.max_patch_poles)
        refuse(label(e) + " has " + std::to_string(e.n_refs) +
               " control points, above the limit of " +
               limit_text(m_limits.max_patch_poles, "max_patch_poles", "--max-patch-poles") +
               " per B-spline");
      total += e.n_refs;
      if (m_limits.max_total_poles > 0 && total > m_limits.max_total_poles)
        refuse("the B-splines up to " + label(e) + " have " + std::to_string(total) +
               " control points in all, above the limit of " +
               limit_text(m_limits.max_total_poles, "max_total_poles", "--max-total-poles"));
      const std::string problem = check_spline(Record_parser(m_text, e.begin).parts());
      if (!problem.empty()) m_out.entity_problems["#" + std::to_string(e.id)] = problem;
    }
  }

  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  const std::string& m_name;
  std::string_view m_text;
  const Import_limits& m_limits;
  Cad_scan& m_out;
  std::vector<Step_entity> m_entities;
  std::vector<std::uint64_t> m_refs;
  std::vector<std::uint32_t> m_targets;
};

// ---- IGES -----------------------------------------------------------------------------------

// Columns of a fixed-format record (1-based, inclusive), blank when the line is shorter.
std::string_view columns(std::string_view line, std::size_t from, std::size_t to) {
  if (line.size() < from) return {};
  return line.substr(from - 1, std::min(line.size(), to) - (from - 1));
}

bool parse_int(std::string_view s, long long& out) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) {
    out = 0;  // an empty IGES field is the default, 0
    return true;
  }
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_real(std::string_view s, double& out) {
  std::string t(s);
  t.erase(std::remove(t.begin(), t.end(), ' '), t.end());
  for (char& c : t)
    if (c == 'D' || c == 'd') c = 'E';
  std::string_view v(t);
  if (!v.empty() && v.front() == '+') v.remove_prefix(1);
  if (v.empty()) {
    out = 0.0;
    return true;
  }
  const auto r = std::from_chars(v.data(), v.data() + v.size(), out);
  return r.ec == std::errc() && r.ptr == v.data() + v.size();
}

class Iges_scan {
 public:
  Iges_scan(const std::string& name, const std::string& bytes, const Import_limits& limits,
            Cad_scan& out)
      : m_name(name), m_text(bytes), m_limits(limits), m_out(out) {}

  void run() {
    split_sections();
    read_delimiters();
    check_entities();
  }

 private:
  [[noreturn]] void refuse(const std::string& what) const {
    throw Invalid_input(m_name + ": " + what);
  }

  void split_sections() {
    std::size_t pos = 0, line_no = 0;
    bool terminated = false;
    while (pos < m_text.size()) {
      std::size_t eol = m_text.find('\n', pos);
      if (eol == std::string_view::npos) eol = m_text.size();
      std::string_view line = m_text.substr(pos, eol - pos);
      pos = eol + 1;
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.find_first_not_of(" \t") == std::string_view::npos) continue;
      if (terminated) continue;  // after the Terminate record
      if (line.size() < 73 && eol == m_text.size())
        refuse("the file ends inside line " + std::to_string(line_no) + " (column " +
               std::to_string(line.size()) + " of 80): it is truncated");
      if (line.size() < 73)
        refuse("line " + std::to_string(line_no) + " is not an IGES record (" +
               std::to_string(line.size()) + " columns; column 73 holds the section letter)");
      switch (line[72]) {
        case 'S': m_start.push_back(line); break;
        case 'G': m_global.push_back(line); break;
        case 'D': m_directory.push_back(line); break;
        case 'P': m_parameters.push_back(line); break;
        case 'T': m_terminate = line; terminated = true; break;
        default:
          refuse("line " + std::to_string(line_no) + " has section letter '" +
                 std::string(1, line[72]) + "' in column 73 (S, G, D, P or T expected)");
      }
    }
    if (!terminated)
      refuse("no Terminate (T) record at the end: the file is truncated after " +
             std::to_string(m_directory.size()) + " directory and " +
             std::to_string(m_parameters.size()) + " parameter lines");
    long long announced_d = 0, announced_p = 0;
    if (parse_int(columns(m_terminate, 18, 24), announced_d) &&
        parse_int(columns(m_terminate, 26, 32), announced_p) &&
        (announced_d > static_cast<long long>(m_directory.size()) ||
         announced_p > static_cast<long long>(m_parameters.size())))
      refuse("the Terminate record counts " + std::to_string(announced_d) + " directory and " +
             std::to_string(announced_p) + " parameter lines, the file has " +
             std::to_string(m_directory.size()) + " and " + std::to_string(m_parameters.size()) +
             ": it is truncated");
    if (m_directory.size() % 2 != 0)
      refuse("the directory section has an odd number of lines (" +
             std::to_string(m_directory.size()) + "): its last entry is cut off");
  }

  // The Global section's first two fields: the parameter and record delimiters (1H, and 1H;
  // by default).
  void read_delimiters() {
    std::string g;
    for (std::string_view l : m_global) g += columns(l, 1, 72);
    std::size_t i = 0;
    auto read_one = [&](char fallback) {
      if (g.compare(i, 2, "1H") == 0 && i + 2 < g.size()) {
        const char c = g[i + 2];
        i += 3;
        return c;
      }
      return fallback;
    };
    m_param_delim = read_one(',');
    if (i < g.size() && g[i] == m_param_delim) ++i;
    m_record_delim = read_one(';');
    if (m_param_delim == m_record_delim || m_param_delim == ' ' || m_record_delim == ' ')
      refuse("the Global section's delimiters are unusable ('" + std::string(1, m_param_delim) +
             "' and '" + std::string(1, m_record_delim) + "')");
  }

  // The parameters of the entity whose data starts at P line `first` (1-based) and spans
  // `count` lines, split at the delimiters (Hollerith strings are not expected in B-splines).
  std::vector<std::string_view> parameters(std::size_t first, std::size_t count,
                                           std::string& storage) const {
    storage.clear();
    for (std::size_t k = first; k < first + count; ++k) storage += columns(m_parameters[k - 1], 1, 64);
    std::vector<std::string_view> out;
    std::size_t start = 0;
    const std::string_view s(storage);
    for (std::size_t i = 0; i <= s.size(); ++i) {
      if (i == s.size() || s[i] == m_param_delim || s[i] == m_record_delim) {
        out.push_back(s.substr(start, i - start));
        start = i + 1;
        if (i < s.size() && s[i] == m_record_delim) break;
      }
    }
    return out;
  }

  void check_entities() {
    std::uint64_t total = 0;
    std::string storage;
    for (std::size_t k = 0; k + 1 < m_directory.size(); k += 2) {
      const std::string label = "IGES entity D" + std::to_string(k + 1);
      long long type = 0, pointer = 0, count = 0;
      if (!parse_int(columns(m_directory[k], 1, 8), type) ||
          !parse_int(columns(m_directory[k], 9, 16), pointer) ||
          !parse_int(columns(m_directory[k + 1], 25, 32), count))
        refuse(label + ": the directory entry's type, data pointer or line count is not a number");
      if (type == 0) continue;  // null entity
      if (pointer < 1 || count < 1 ||
          pointer + count - 1 > static_cast<long long>(m_parameters.size()))
        refuse(label + " (type " + std::to_string(type) + "): its parameter data (P lines " +
               std::to_string(pointer) + " to " + std::to_string(pointer + count - 1) +
               ") lie outside the file's " + std::to_string(m_parameters.size()) +
               " parameter lines");
      if (type != kIgesBsplineCurve && type != kIgesBsplineSurface) continue;
      const auto p = parameters(static_cast<std::size_t>(pointer), static_cast<std::size_t>(count), storage);
      const std::string what = label + " (type " + std::to_string(type) + ")";
      std::uint64_t poles = 0;
      if (!check_bspline(type, p, what, poles)) continue;
      if (m_limits.max_patch_poles > 0 && poles > m_limits.max_patch_poles)
        refuse(what + " has " + std::to_string(poles) + " control points, above the limit of " +
               limit_text(m_limits.max_patch_poles, "max_patch_poles", "--max-patch-poles") +
               " per B-spline");
      total += poles;
      if (m_limits.max_total_poles > 0 && total > m_limits.max_total_poles)
        refuse("the B-splines up to " + what + " have " + std::to_string(total) +
               " control points in all, above the limit of " +
               limit_text(m_limits.max_total_poles, "max_total_poles", "--max-total-poles"));
    }
  }

  // Counts and knots of a 126 curve or a 128 surface. Counts that the entity's own parameters
  // cannot hold refuse the file (the reader would size arrays from them); other problems are
  // recorded against the entity. Returns false when the counts are unusable.
  bool check_bspline(long long type, const std::vector<std::string_view>& p, const std::string& what,
                     std::uint64_t& poles) {
    const bool surface = type == kIgesBsplineSurface;
    const std::size_t n_ints = surface ? 5 : 3;  // type, K1, K2, M1, M2 / type, K, M
    std::vector<long long> v(n_ints, 0);
    for (std::size_t i = 1; i < n_ints; ++i)
      if (i >= p.size() || !parse_int(p[i], v[i])) {
        m_out.entity_problems[key(what)] = "its upper indices and degrees are not integers";
        return false;
      }
    const int dirs = surface ? 2 : 1;
    std::uint64_t knots = 0;
    poles = 1;
    std::string problem;
    for (int d = 0; d < dirs; ++d) {
      const long long k = v[1 + d], m = v[1 + dirs + d];
      if (k < 0 || m < 0) {
        m_out.entity_problems[key(what)] = "a negative upper index or degree";
        return false;
      }
      // Every count is bounded by the parameters present before it is multiplied.
      if (static_cast<std::uint64_t>(k) + 1 > p.size() || static_cast<std::uint64_t>(m) > p.size())
        refuse(what + " announces " + std::to_string(k + 1) + " control points of degree " +
               std::to_string(m) + " in a direction but holds " + std::to_string(p.size()) +
               " parameters");
      poles *= static_cast<std::uint64_t>(k) + 1;
      knots += static_cast<std::uint64_t>(k + m + 2);
      if (problem.empty() && (m < 1 || m > kMaxDegree || k < m)) {
        std::ostringstream os;
        os << "upper index " << k << " and degree " << m << ": the degree must be 1.." << kMaxDegree
           << ", with at least degree + 1 control points";
        problem = os.str();
      }
    }
    // type, counts, flags (4 for curves, 5 for surfaces), knots, weights, 3 coordinates per
    // control point, then the parameter range (and a curve's normal).
    const std::uint64_t needed = n_ints + (surface ? 5 : 4) + knots + 4 * poles + (surface ? 4 : 2);
    if (needed > p.size())
      refuse(what + " announces " + std::to_string(poles) + " control points and " +
             std::to_string(knots) + " knots (" + std::to_string(needed) +
             " parameters) but holds " + std::to_string(p.size()) + " parameters");
    if (!problem.empty()) {
      m_out.entity_problems[key(what)] = problem;
      return true;
    }
    // Knots: non-decreasing in each direction.
    std::size_t at = n_ints + (surface ? 5 : 4);
    for (int d = 0; d < dirs; ++d) {
      const long long k = v[1 + d], m = v[1 + dirs + d];
      double prev = -std::numeric_limits<double>::infinity();
      for (long long i = 0; i < k + m + 2; ++i, ++at) {
        double x = 0.0;
        if (!parse_real(p[at], x) || !std::isfinite(x)) {
          m_out.entity_problems[key(what)] = "knot " + std::to_string(i + 1) + " is not a number";
          return true;
        }
        if (x < prev) {
          std::ostringstream os;
          os << (surface ? (d == 0 ? "the u knots" : "the v knots") : "the knots")
             << " decrease: knot " << i + 1 << " (" << x << ") follows " << prev;
          m_out.entity_problems[key(what)] = os.str();
          return true;
        }
        prev = x;
      }
    }
    return true;
  }

  // The key OpenCASCADE's IGES model gives the entity: "D<line>".
  static std::string key(const std::string& what) {
    const std::size_t d = what.find(" D");
    const std::size_t end = what.find(' ', d + 1);
    return what.substr(d + 1, end - d - 1);
  }

  const std::string& m_name;
  std::string_view m_text;
  const Import_limits& m_limits;
  Cad_scan& m_out;
  std::vector<std::string_view> m_start, m_global, m_directory, m_parameters;
  std::string_view m_terminate;
  char m_param_delim = ',', m_record_delim = ';';
};

}  // namespace

void scan_step(const std::string& name, const std::string& bytes, const Import_limits& limits,
               Cad_scan& out) {
  Step_scan(name, bytes, limits, out).run();
}

void scan_iges(const std::string& name, const std::string& bytes, const Import_limits& limits,
               Cad_scan& out) {
  Iges_scan(name, bytes, limits, out).run();
}

}  // namespace extremal::io::internal
