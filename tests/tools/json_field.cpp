#include "json_field.hpp"

namespace mtc::test {

std::optional<std::string> json_field(const std::string& line, const std::string& key) {
  const std::string quoted = "\"" + key + "\":";
  const auto pos = line.find(quoted);
  if (pos == std::string::npos) {
    return std::nullopt;
  }
  std::size_t i = pos + quoted.size();
  if (i < line.size() && line[i] == '"') {
    std::string value;
    for (++i; i < line.size() && line[i] != '"'; ++i) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        ++i;
      }
      value += line[i];
    }
    return value;
  }
  const auto end = line.find_first_of(",}", i);
  return line.substr(i, end == std::string::npos ? std::string::npos : end - i);
}

}  // namespace mtc::test
