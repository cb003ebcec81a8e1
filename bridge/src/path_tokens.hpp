// The tokens of an XPath 1.0 expression, for estimate_path_cost. Internal
// to mtc_bridge.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace mtc::bridge::detail {

enum class Tok : std::uint8_t {
  End,
  LParen,
  RParen,
  LBracket,
  RBracket,
  Dot,
  DotDot,
  At,
  Comma,
  ColonColon,
  Slash,
  SlashSlash,
  Pipe,
  Plus,
  Minus,
  Eq,
  Neq,
  Lt,
  Le,
  Gt,
  Ge,
  Star,
  Multiply,
  Literal,
  Number,
  Name,
  Variable,
  And,
  Or,
  Mod,
  Div
};

struct Token {
  Tok kind = Tok::End;
  std::string_view text;
};

// Thrown by the tokenizer and the analysis; becomes PathCost::error.
struct Refused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The tokens of `text`, ending with Tok::End. Throws Refused for a
// character XPath does not use, an unterminated literal, a variable,
// unbalanced or more than `max_nesting` nested parentheses and brackets.
// `*` and the names and/or/mod/div are told apart as XPath 1.0, 3.7 says.
std::vector<Token> tokenize_path(std::string_view text, std::size_t max_nesting);

}  // namespace mtc::bridge::detail
