// SHDR line formatting (shdr_adapter.hpp).
#include "mtc/bridge/printer.hpp"
#include "mtc/bridge/shdr_adapter.hpp"

namespace mtc::bridge {

std::string shdr_line(const ItemObservation& o) {
  std::string line = format_timestamp(o.time_ns);
  line.reserve(line.size() + o.item.size() + o.value.size() + 8);
  line += '|';
  line += o.item;
  line += '|';
  for (const char c : o.value) line += (c == '|' || c == '\n' || c == '\r') ? ' ' : c;
  // A condition: level|native code|native severity|qualifier|message.
  if (o.condition) line += "||||";
  line += '\n';
  return line;
}

}  // namespace mtc::bridge
