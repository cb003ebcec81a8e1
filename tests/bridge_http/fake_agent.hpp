// A small but real Agent for the HTTP server tests: a sequence-numbered list
// of observations, /probe, /current, /sample (with from/interval/heartbeat),
// UNSUPPORTED for other methods, INVALID_URI for unknown paths and targets
// the server could not split.
// Documents are tiny MTConnect-shaped XML built with pugixml, so tests can
// assert on them with XPath. It stands in for helper-made agents only where
// the server, not the XML, is under test.
#pragma once

#include <algorithm>
#include <atomic>
#include <charconv>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <pugixml.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mtc/bridge/agent.hpp"

namespace mtc::bridge::test {

class FakeAgent : public Agent {
 public:
  struct Observation {
    std::uint64_t sequence;
    std::string item;
    std::string value;
  };

  // Adds an observation and wakes every subscriber (outside the lock, as a
  // producer thread would).
  std::uint64_t add(const std::string& item, const std::string& value) {
    std::vector<std::function<void()>> to_call;
    std::uint64_t sequence = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      sequence = next_++;
      observations_.push_back({sequence, item, value});
      for (auto& entry : subscribers_) to_call.push_back(entry.second);
    }
    cv_.notify_all();
    for (auto& callback : to_call) callback();
    return sequence;
  }

  // From now on next_part answers OUT_OF_RANGE, as an agent does for a
  // stream that fell behind its buffer.
  void fail_parts() { parts_fail_ = true; }

  std::size_t subscriber_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return subscribers_.size();
  }

  Response error_document(int status, std::string_view code,
                          std::string_view message) noexcept override {
    return make_error(status, code, message);
  }

  static Response make_error(int status, std::string_view code, std::string_view message) {
    pugi::xml_document doc;
    auto root = doc.append_child("MTConnectError");
    root.append_child("Header").append_attribute("sender") = "fake";
    auto error = root.append_child("Errors").append_child("Error");
    error.append_attribute("errorCode") = std::string(code).c_str();
    error.text() = std::string(message).c_str();
    return {status, "text/xml", print(doc)};
  }

  // The last request routed, as the server handed it over.
  Request last_request() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_request_;
  }

  using Agent::route;
  Routed route(const Request& request) noexcept override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last_request_ = request;
    }
    Routed routed;
    if (request.method != "GET") {
      routed.response = make_error(405, "UNSUPPORTED", "only GET is supported");
      return routed;
    }
    if (!request.target) {
      routed.response = make_error(400, "INVALID_URI", request.target_error);
      return routed;
    }
    const auto& segments = request.target->segments;
    const auto& query = request.target->query;
    const std::string path = segments.size() == 1 ? segments[0] : std::string();
    if (path == "probe") {
      routed.response =
          Response{200, "text/xml", "<MTConnectDevices><Devices/></MTConnectDevices>"};
    } else if (path == "current" || path == "sample") {
      const bool sample = path == "sample";
      if (number(query, "interval")) {
        StreamPlan plan;
        plan.is_sample = sample;
        plan.interval = std::chrono::milliseconds(*number(query, "interval"));
        plan.heartbeat = std::chrono::milliseconds(number(query, "heartbeat").value_or(10000));
        plan.next_sequence =
            sample ? number(query, "from").value_or(next_sequence()) : next_sequence();
        routed.stream = plan;
      } else {
        StreamPlan once;
        once.is_sample = sample;
        once.next_sequence = number(query, "from").value_or(sample ? 1 : 0);
        routed.response = next_part(once);
      }
    } else {
      routed.response = make_error(404, "INVALID_URI", "no such path");
    }
    return routed;
  }

  Response next_part(StreamPlan& plan) noexcept override {
    if (parts_fail_) return make_error(400, "OUT_OF_RANGE", "fell behind the buffer");
    std::lock_guard<std::mutex> lock(mutex_);
    pugi::xml_document doc;
    auto root = doc.append_child("MTConnectStreams");
    auto header = root.append_child("Header");
    header.append_attribute("nextSequence") = static_cast<unsigned long long>(next_);
    auto events = root.append_child("Streams").append_child("Events");
    if (plan.is_sample) {
      std::uint64_t last = plan.next_sequence;
      for (const auto& o : observations_) {
        if (o.sequence < plan.next_sequence) continue;
        append(events, o);
        last = o.sequence + 1;
      }
      plan.next_sequence = std::max(last, plan.next_sequence);
    } else {
      std::map<std::string, const Observation*> latest;
      for (const auto& o : observations_) latest[o.item] = &o;
      for (const auto& entry : latest) append(events, *entry.second);
      plan.next_sequence = next_;
    }
    return {200, "text/xml", print(doc)};
  }

  std::uint64_t next_sequence() const noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_;
  }

  bool wait_for(std::uint64_t from, std::chrono::milliseconds timeout) const override {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return next_ > from; });
  }

  std::uint64_t subscribe(std::function<void()> on_new_data) override {
    std::lock_guard<std::mutex> lock(mutex_);
    subscribers_.emplace(++last_subscription_, std::move(on_new_data));
    return last_subscription_;
  }

  void unsubscribe(std::uint64_t id) override {
    std::lock_guard<std::mutex> lock(mutex_);
    subscribers_.erase(id);
  }

 private:
  static std::string print(const pugi::xml_document& doc) {
    std::ostringstream out;
    doc.save(out, "", pugi::format_raw);
    return out.str();
  }

  static void append(pugi::xml_node events, const Observation& o) {
    auto node = events.append_child("Event");
    node.append_attribute("dataItemId") = o.item.c_str();
    node.append_attribute("sequence") = static_cast<unsigned long long>(o.sequence);
    node.text() = o.value.c_str();
  }

  // A query parameter as a number; nullopt when absent (the fake is lenient
  // with malformed numbers: the server, not parameter checking, is tested).
  static std::optional<std::uint64_t> number(
      const std::vector<std::pair<std::string, std::string>>& query, std::string_view name) {
    for (const auto& [key, text] : query) {
      if (key != name) continue;
      std::uint64_t value = 0;
      std::from_chars(text.data(), text.data() + text.size(), value);
      return value;
    }
    return std::nullopt;
  }

  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::vector<Observation> observations_;
  std::map<std::uint64_t, std::function<void()>> subscribers_;
  std::uint64_t next_ = 1;
  std::atomic<bool> parts_fail_{false};
  std::uint64_t last_subscription_ = 0;
  Request last_request_;
};

}  // namespace mtc::bridge::test
