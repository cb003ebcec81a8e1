#include "path_tokens.hpp"

#include <string>

namespace mtc::bridge::detail {
namespace {

bool name_start(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || u >= 0x80;
}
bool name_char(char c) {
  return name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
}
bool digit(char c) {
  return c >= '0' && c <= '9';
}

// XPath 1.0, 3.7: after these (or at the start) `*` is a name test and a
// name is a name; after anything else they are operators.
bool operand_expected(const std::vector<Token>& tokens) {
  if (tokens.empty()) return true;
  switch (tokens.back().kind) {
    case Tok::At:
    case Tok::ColonColon:
    case Tok::LParen:
    case Tok::LBracket:
    case Tok::Comma:
    case Tok::Slash:
    case Tok::SlashSlash:
    case Tok::Pipe:
    case Tok::Plus:
    case Tok::Minus:
    case Tok::Eq:
    case Tok::Neq:
    case Tok::Lt:
    case Tok::Le:
    case Tok::Gt:
    case Tok::Ge:
    case Tok::Multiply:
    case Tok::And:
    case Tok::Or:
    case Tok::Mod:
    case Tok::Div:
      return true;
    default:
      return false;
  }
}

class Lexer {
 public:
  Lexer(std::string_view text, std::size_t max_nesting) : text_(text), max_(max_nesting) {}

  std::vector<Token> run() {
    while (skip_space(), at_ < text_.size()) tokens_.push_back(next());
    if (depth_ != 0) throw Refused("unbalanced parentheses or brackets");
    tokens_.push_back({Tok::End, {}});
    return std::move(tokens_);
  }

 private:
  void skip_space() {
    while (at_ < text_.size() &&
           (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r')) {
      ++at_;
    }
  }
  Token take(Tok kind, std::size_t length) {
    const Token t{kind, text_.substr(at_, length)};
    at_ += length;
    return t;
  }
  Token open(Tok kind) {
    if (++depth_ > max_) {
      throw Refused("nested deeper than " + std::to_string(max_) + " parentheses or brackets");
    }
    return take(kind, 1);
  }
  Token close(Tok kind) {
    if (depth_-- == 0) throw Refused("unbalanced parentheses or brackets");
    return take(kind, 1);
  }
  char peek(std::size_t ahead = 0) const {
    return at_ + ahead < text_.size() ? text_[at_ + ahead] : '\0';
  }
  std::size_t name_length(std::size_t from) const {
    std::size_t end = from;
    while (end < text_.size() && name_char(text_[end])) ++end;
    return end - from;
  }
  Token next();
  Token word();

  std::string_view text_;
  std::size_t max_;
  std::size_t at_ = 0;
  std::size_t depth_ = 0;
  std::vector<Token> tokens_;
};

Token Lexer::next() {
  const char c = peek();
  switch (c) {
    case '(':
      return open(Tok::LParen);
    case '[':
      return open(Tok::LBracket);
    case ')':
      return close(Tok::RParen);
    case ']':
      return close(Tok::RBracket);
    case '@':
      return take(Tok::At, 1);
    case ',':
      return take(Tok::Comma, 1);
    case '|':
      return take(Tok::Pipe, 1);
    case '+':
      return take(Tok::Plus, 1);
    case '-':
      return take(Tok::Minus, 1);
    case '=':
      return take(Tok::Eq, 1);
    case '/':
      return peek(1) == '/' ? take(Tok::SlashSlash, 2) : take(Tok::Slash, 1);
    case '<':
      return peek(1) == '=' ? take(Tok::Le, 2) : take(Tok::Lt, 1);
    case '>':
      return peek(1) == '=' ? take(Tok::Ge, 2) : take(Tok::Gt, 1);
    case '*':
      return take(operand_expected(tokens_) ? Tok::Star : Tok::Multiply, 1);
    case ':':
      if (peek(1) == ':') return take(Tok::ColonColon, 2);
      break;
    case '!':
      if (peek(1) == '=') return take(Tok::Neq, 2);
      break;
    case '\'':
    case '"': {
      const auto end = text_.find(c, at_ + 1);
      if (end == std::string_view::npos) throw Refused("unterminated string literal");
      return take(Tok::Literal, end - at_ + 1);
    }
    case '.':
      if (peek(1) == '.') return take(Tok::DotDot, 2);
      if (!digit(peek(1))) return take(Tok::Dot, 1);
      break;
    case '$':
      throw Refused("variables are not supported");
    default:
      break;
  }
  if (digit(c) || c == '.') {
    std::size_t length = 0;
    while (digit(peek(length)) || peek(length) == '.') ++length;
    return take(Tok::Number, length);
  }
  if (name_start(c)) return word();
  throw Refused("unexpected character '" + std::string(1, c) + "'");
}

// An NCName, QName or prefix:*, or an operator name where one is expected.
Token Lexer::word() {
  std::size_t length = name_length(at_);
  if (!operand_expected(tokens_)) {
    const std::string_view w = text_.substr(at_, length);
    if (w == "and") return take(Tok::And, length);
    if (w == "or") return take(Tok::Or, length);
    if (w == "mod") return take(Tok::Mod, length);
    if (w == "div") return take(Tok::Div, length);
    throw Refused("expected an operator, not '" + std::string(w) + "'");
  }
  if (peek(length) == ':' && peek(length + 1) != ':') {
    if (peek(length + 1) == '*') {
      length += 2;
    } else if (name_start(peek(length + 1))) {
      length += 1 + name_length(at_ + length + 1);
    }
  }
  return take(Tok::Name, length);
}

}  // namespace

std::vector<Token> tokenize_path(std::string_view text, std::size_t max_nesting) {
  return Lexer(text, max_nesting).run();
}

}  // namespace mtc::bridge::detail
