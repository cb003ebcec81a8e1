// estimate_path_cost: a recursive-descent pass over the XPath 1.0 grammar
// that computes, instead of a tree, an upper bound on the work of evaluating
// each sub-expression once (see path_cost.hpp). Recursion is bounded by the
// nesting limit, which tokenize_path checks.
#include "mtc/bridge/path_cost.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <vector>

#include "path_tokens.hpp"

namespace mtc::bridge {
namespace {

using detail::Refused;
using detail::Tok;
using detail::Token;

constexpr double kCap = 1e30;  // saturate: no infinities, so no NaN

double add(double a, double b) {
  return std::min(a + b, kCap);
}
double mul(double a, double b) {
  return std::min(a * b, kCap);
}

struct Value {
  double cost = 0;        // work to compute it once
  bool node_set = false;  // else a string, number or boolean
  double size = 0;        // nodes in it, at most
  bool elements = false;  // may hold elements (string value = subtree text)
  double length = 24;     // characters, at most, of a string (or number) value
};

// Characters a number or boolean prints as, at most.
constexpr double kScalarLength = 24;

enum class Axis : std::uint8_t {
  Child,
  Descendant,
  DescendantOrSelf,
  Self,
  Parent,
  Ancestor,
  AncestorOrSelf,
  FollowingSibling,
  PrecedingSibling,
  Following,
  Preceding,
  Attribute,
  Namespace
};

// The axes of XPath 1.0 by name.
const std::map<std::string_view, Axis> kAxes{{"child", Axis::Child},
                                             {"descendant", Axis::Descendant},
                                             {"descendant-or-self", Axis::DescendantOrSelf},
                                             {"self", Axis::Self},
                                             {"parent", Axis::Parent},
                                             {"ancestor", Axis::Ancestor},
                                             {"ancestor-or-self", Axis::AncestorOrSelf},
                                             {"following-sibling", Axis::FollowingSibling},
                                             {"preceding-sibling", Axis::PrecedingSibling},
                                             {"following", Axis::Following},
                                             {"preceding", Axis::Preceding},
                                             {"attribute", Axis::Attribute},
                                             {"namespace", Axis::Namespace}};

Axis axis_named(std::string_view name) {
  const auto it = kAxes.find(name);
  if (it == kAxes.end()) throw Refused("unknown axis '" + std::string(name) + "'");
  return it->second;
}

// XPath 1.0's functions returning a number or boolean, and those
// returning a string no longer than their first argument (concat, count and
// sum are costed apart; id() is not supported).
const std::set<std::string_view> kScalarFunctions{
    "last",  "position",   "true",          "false",         "boolean", "not",
    "lang",  "local-name", "name",          "namespace-uri", "floor",   "ceiling",
    "round", "number",     "string-length", "starts-with",   "contains"};
const std::set<std::string_view> kStringFunctions{
    "string", "substring-before", "substring-after", "substring", "normalize-space", "translate"};

class Analyzer {
 public:
  Analyzer(std::vector<Token> tokens, const TreeShape& shape)
      : tokens_(std::move(tokens)),
        shape_(shape),
        nodes_(std::max<double>(1, static_cast<double>(shape.nodes))),
        height_(static_cast<double>(shape.height) + 1),
        text_(std::max<double>(1, static_cast<double>(shape.text_bytes))) {}

  Value run() {
    Value v = or_expr();
    if (kind() != Tok::End) throw Refused("unexpected '" + std::string(tokens_[at_].text) + "'");
    return v;
  }

 private:
  Tok kind() const { return tokens_[at_].kind; }
  std::string_view text() const { return tokens_[at_].text; }
  bool accept(Tok k) {
    if (kind() != k) return false;
    ++at_;
    return true;
  }
  void expect(Tok k, const char* what) {
    if (!accept(k)) throw Refused(std::string("expected ") + what);
  }

  // Longest attribute value (an attribute's string value is read in place).
  double attribute_length() const {
    return std::max<double>(1, static_cast<double>(shape_.max_attribute_bytes));
  }
  // Every string value of a node set: subtree text copied for elements.
  double string_values(const Value& v) const {
    if (!v.node_set) return 1;
    return v.elements ? std::min(mul(v.size, text_), mul(text_, height_))
                      : mul(v.size, attribute_length());
  }
  // A node set read as one string or number (its first node).
  double first_value(const Value& v) const {
    if (!v.node_set) return 1;
    return v.elements ? text_ : attribute_length();
  }
  // A node set compared with a string of `length` characters: each value
  // compared up to that length (elements' values built first).
  double compared_with(const Value& v, double length) const {
    const double each = std::min(v.elements ? text_ : attribute_length(), length + 1);
    return add(v.elements ? string_values(v) : 0, mul(v.size, each));
  }
  static Value scalar(double cost, double length = kScalarLength) {
    return Value{cost, false, 0, false, length};
  }
  // Characters of a value read as a string.
  double text_of(const Value& v) const { return v.node_set ? first_value(v) : v.length; }

  Value or_expr();
  Value and_expr();
  Value equality_expr();
  Value relational_expr();
  Value additive_expr();
  Value multiplicative_expr();
  Value unary_expr();
  Value union_expr();
  Value path_expr();
  Value primary_expr();
  Value function_call(std::string_view name);
  Value relative_path(Value in);
  Value step(const Value& in);
  Value axis_step(const Value& in, Axis axis);
  double predicates();
  Value compare(const Value& a, const Value& b) const;
  Value arithmetic(const Value& a, const Value& b) const {
    return scalar(add(add(a.cost, b.cost), add(first_value(a), first_value(b))));
  }
  double reach(Axis axis, double in) const;
  double named(Axis axis, std::string_view test) const;
  Value pushed_step(const Value& in, Axis axis, double named_total);

  std::vector<Token> tokens_;
  std::size_t at_ = 0;
  const TreeShape& shape_;
  double nodes_ = 1;
  double height_ = 1;
  double text_ = 1;
};

Value Analyzer::or_expr() {
  Value v = and_expr();
  while (accept(Tok::Or)) v = scalar(add(add(v.cost, and_expr().cost), 1));
  return v;
}

Value Analyzer::and_expr() {
  Value v = equality_expr();
  while (accept(Tok::And)) v = scalar(add(add(v.cost, equality_expr().cost), 1));
  return v;
}

Value Analyzer::equality_expr() {
  Value v = relational_expr();
  while (accept(Tok::Eq) || accept(Tok::Neq)) v = compare(v, relational_expr());
  return v;
}

Value Analyzer::relational_expr() {
  Value v = additive_expr();
  while (accept(Tok::Lt) || accept(Tok::Le) || accept(Tok::Gt) || accept(Tok::Ge)) {
    v = compare(v, additive_expr());
  }
  return v;
}

Value Analyzer::additive_expr() {
  Value v = multiplicative_expr();
  while (accept(Tok::Plus) || accept(Tok::Minus)) v = arithmetic(v, multiplicative_expr());
  return v;
}

Value Analyzer::multiplicative_expr() {
  Value v = unary_expr();
  while (accept(Tok::Multiply) || accept(Tok::Div) || accept(Tok::Mod)) {
    v = arithmetic(v, unary_expr());
  }
  return v;
}

Value Analyzer::unary_expr() {
  bool negated = false;
  while (accept(Tok::Minus)) negated = true;
  Value v = union_expr();
  return negated ? arithmetic(v, scalar(0)) : v;
}

Value Analyzer::union_expr() {
  Value v = path_expr();
  while (accept(Tok::Pipe)) {
    const Value w = path_expr();
    if (!v.node_set || !w.node_set) throw Refused("'|' joins node sets only");
    const double size = std::min(add(v.size, w.size), nodes_);
    // Merged and put in document order.
    const double sort = mul(size, std::log2(size + 2));
    v = Value{add(add(v.cost, w.cost), sort), true, size, v.elements || w.elements};
  }
  return v;
}

// A comparison: a node set against a string compares each of its values;
// two node sets compare every pair.
Value Analyzer::compare(const Value& a, const Value& b) const {
  double cost = add(add(a.cost, b.cost), 1);
  if (a.node_set && b.node_set) {
    const double pairs = mul(mul(a.size, b.size), std::min(first_value(a), first_value(b)));
    return scalar(add(add(cost, pairs), add(string_values(a), string_values(b))));
  }
  if (a.node_set) cost = add(cost, compared_with(a, b.length));
  if (b.node_set) cost = add(cost, compared_with(b, a.length));
  return scalar(cost);
}

Value Analyzer::path_expr() {
  const Value root{1, true, 1, true};
  if (accept(Tok::Slash)) {
    const Tok k = kind();
    const bool step_follows =
        k == Tok::Name || k == Tok::Star || k == Tok::At || k == Tok::Dot || k == Tok::DotDot;
    return step_follows ? relative_path(root) : root;
  }
  if (accept(Tok::SlashSlash)) return relative_path(axis_step(root, Axis::DescendantOrSelf));
  const Tok k = kind();
  const bool primary =
      k == Tok::LParen || k == Tok::Literal || k == Tok::Number ||
      (k == Tok::Name && tokens_[at_ + 1].kind == Tok::LParen && text() != "node" &&
       text() != "text" && text() != "comment" && text() != "processing-instruction");
  if (!primary) return relative_path(root);
  Value v = primary_expr();
  if (kind() == Tok::LBracket) {
    if (!v.node_set) throw Refused("predicates apply to node sets only");
    v.cost = add(v.cost, mul(v.size, predicates()));
  }
  if (accept(Tok::Slash)) return relative_path(v);
  if (accept(Tok::SlashSlash)) return relative_path(axis_step(v, Axis::DescendantOrSelf));
  return v;
}

Value Analyzer::primary_expr() {
  if (accept(Tok::LParen)) {
    Value v = or_expr();
    expect(Tok::RParen, "')'");
    return v;
  }
  if (kind() == Tok::Literal || kind() == Tok::Number) {
    const auto length = static_cast<double>(text().size());
    ++at_;
    return scalar(1, length);
  }
  const std::string_view name = text();
  ++at_;
  expect(Tok::LParen, "'('");
  return function_call(name);
}

Value Analyzer::function_call(std::string_view name) {
  std::vector<Value> args;
  if (!accept(Tok::RParen)) {
    do {
      args.push_back(or_expr());
    } while (accept(Tok::Comma));
    expect(Tok::RParen, "')'");
  }
  double cost = 1;
  double text = 0;  // characters of the arguments read as strings
  for (const Value& a : args) {
    cost = add(cost, a.cost);
    text = add(text, text_of(a));
  }
  // Without an argument these read the context node: a subtree's text.
  const double first = args.empty() ? text_ : text_of(args.front());
  if (name == "count") {
    for (const Value& a : args) cost = add(cost, a.size);
    return scalar(cost);
  }
  if (name == "sum") {
    for (const Value& a : args) cost = add(cost, string_values(a));
    return scalar(cost);
  }
  if (name == "concat") return scalar(add(cost, text), text);
  if (kStringFunctions.count(name) != 0) return scalar(add(add(cost, text), first), first);
  if (kScalarFunctions.count(name) != 0) {
    const bool reads_context = args.empty() && (name == "string-length" || name == "number");
    return scalar(add(add(cost, text), reads_context ? text_ : 0));
  }
  throw Refused("unknown or unsupported function '" + std::string(name) + "()'");
}

Value Analyzer::relative_path(Value in) {
  in = step(in);
  for (;;) {
    if (accept(Tok::Slash)) {
      in = step(in);
    } else if (accept(Tok::SlashSlash)) {
      in = step(axis_step(in, Axis::DescendantOrSelf));
    } else {
      return in;
    }
  }
}

Value Analyzer::step(const Value& in) {
  if (!in.node_set) throw Refused("a location step needs a node set");
  if (accept(Tok::Dot)) return axis_step(in, Axis::Self);
  if (accept(Tok::DotDot)) return axis_step(in, Axis::Parent);
  Axis axis = Axis::Child;
  if (accept(Tok::At)) {
    axis = Axis::Attribute;
  } else if (kind() == Tok::Name && tokens_[at_ + 1].kind == Tok::ColonColon) {
    axis = axis_named(text());
    at_ += 2;
  }
  std::string_view test = text();
  if (accept(Tok::Star)) {
    test = "*";
  } else if (kind() == Tok::Name) {
    ++at_;
    if (accept(Tok::LParen)) {  // node(), text(), comment(), processing-instruction('x')
      accept(Tok::Literal);
      expect(Tok::RParen, "')'");
      test = {};
    }
  } else {
    throw Refused("expected a node test");
  }
  return pushed_step(in, axis, named(axis, test));
}

// A step without a node test of its own: `//`, `.` and `..` (node()).
Value Analyzer::axis_step(const Value& in, Axis axis) {
  return pushed_step(in, axis, nodes_);
}

// A step whose test matches at most `named_total` nodes of the document:
// the axis walks `candidates` nodes; each context node pushes every match
// (so a node reached from several contexts is pushed, filtered by the
// predicates and sorted out again once per context); the duplicates go.
Value Analyzer::pushed_step(const Value& in, Axis axis, double named_total) {
  const double candidates = reach(axis, in.size);
  const bool unique = axis == Axis::Child || axis == Axis::Attribute || axis == Axis::Namespace ||
                      axis == Axis::Self;
  const double pushed = std::min(candidates, unique ? named_total : mul(in.size, named_total));
  const double each = kind() == Tok::LBracket ? predicates() : 0;
  double cost = add(add(in.cost, candidates), mul(pushed, add(each, 1)));
  cost = add(cost, mul(pushed, std::log2(pushed + 2)));
  const bool elements = axis != Axis::Attribute && axis != Axis::Namespace;
  return Value{cost, true, std::min({pushed, named_total, nodes_}), elements};
}

// The predicates of one step: the cost of running all of them on one node.
double Analyzer::predicates() {
  double each = 0;
  while (accept(Tok::LBracket)) {
    each = add(each, or_expr().cost);
    expect(Tok::RBracket, "']'");
  }
  return each;
}

// Nodes an axis walks from `in` context nodes.
double Analyzer::reach(Axis axis, double in) const {
  const auto wide = static_cast<double>(shape_.max_children);
  const auto attrs = static_cast<double>(shape_.max_attributes);
  switch (axis) {
    case Axis::Child:
      return std::min(mul(in, wide), nodes_);  // a node has one parent
    case Axis::Attribute:
    case Axis::Namespace:
      return std::min(mul(in, attrs), static_cast<double>(shape_.attributes));
    case Axis::Descendant:
    case Axis::DescendantOrSelf:
      return std::min(mul(in, nodes_), mul(nodes_, height_));  // each node under H others
    case Axis::Self:
    case Axis::Parent:
      return in;
    case Axis::Ancestor:
    case Axis::AncestorOrSelf:
      return mul(in, height_);
    case Axis::FollowingSibling:
    case Axis::PrecedingSibling:
      return mul(in, wide);
    case Axis::Following:
    case Axis::Preceding:
      return mul(in, nodes_);
  }
  return kCap;
}

// Nodes of the document a node test can match: those of its name.
double Analyzer::named(Axis axis, std::string_view test) const {
  const bool attribute = axis == Axis::Attribute || axis == Axis::Namespace;
  if (test.empty()) return nodes_;  // node(), text(), ...
  if (test == "*" || (test.size() > 2 && test.substr(test.size() - 2) == ":*")) {
    return static_cast<double>(attribute ? shape_.attributes : shape_.elements);
  }
  const auto& names = attribute ? shape_.attribute_names : shape_.element_names;
  const auto it = names.find(test);
  return it == names.end() ? 0.0 : static_cast<double>(it->second);
}

// "2000000", or "3.4e+21" for the absurd.
std::string approximate(double visits) {
  if (visits < 1e15) return std::to_string(static_cast<std::uint64_t>(visits));
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", visits);
  return text;
}

}  // namespace

PathCost estimate_path_cost(std::string_view xpath, const TreeShape& shape,
                            const PathLimits& limits) {
  PathCost result;
  if (xpath.size() > limits.max_length) {
    result.error = "the path is longer than " + std::to_string(limits.max_length) + " characters";
    return result;
  }
  try {
    Analyzer analyzer(detail::tokenize_path(xpath, limits.max_nesting), shape);
    result.visits = analyzer.run().cost;
  } catch (const Refused& e) {
    result.error = e.what();
    return result;
  }
  if (!(result.visits <= limits.max_visits)) {
    result.error = "the path could visit up to " + approximate(result.visits) +
                   " nodes of this model, more than the limit of " + approximate(limits.max_visits);
    return result;
  }
  result.accepted = true;
  return result;
}

}  // namespace mtc::bridge
