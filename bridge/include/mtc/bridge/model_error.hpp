// The device model's error, in a header of its own: the model throws it and
// make_agent() lets it through, so both see it without the model depending
// on the agent.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace mtc::bridge {

// A Devices file that cannot be used: unreadable, not XML, or not an
// MTConnectDevices document the agent can serve. what() reads
// "<file>:<line>: <reason>".
class ModelError : public std::runtime_error {
 public:
  ModelError(std::string file, std::size_t line, std::string reason);
  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }  // 0 when unknown
  const std::string& reason() const noexcept { return reason_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string reason_;
};

}  // namespace mtc::bridge
