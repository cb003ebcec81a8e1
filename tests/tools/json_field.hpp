// Value of a string or number field in one of mtc's JSON lines
// ({"event":"outcome","result":"COMPLETE",...}); nullopt when absent. Enough for
// the flat objects mtc prints; not a general JSON parser.
#pragma once

#include <optional>
#include <string>

namespace mtc::test {

std::optional<std::string> json_field(const std::string& line, const std::string& key);

}  // namespace mtc::test
