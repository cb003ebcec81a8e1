// A small but real Agent for the HTTP server tests: a sequence-numbered list
// of observations, /probe, /current, /sample (with from/count/interval/
// heartbeat), UNSUPPORTED for other methods, INVALID_URI for unknown paths.
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
#include <pugixml.hpp>
#include <sstream>
#include <string>
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

  Routed route(std::string_view method, std::string_view target) noexcept override {
    Routed routed;
    if (method != "GET") {
      routed.response = make_error(405, "UNSUPPORTED", "only GET is supported");
      return routed;
    }
    const auto query_at = target.find('?');
    const auto path = target.substr(0, query_at);
    const auto query = parse_query(
        query_at == std::string_view::npos ? std::string_view() : target.substr(query_at + 1));
    if (path == "/probe") {
      routed.response =
          Response{200, "text/xml", "<MTConnectDevices><Devices/></MTConnectDevices>"};
    } else if (path == "/current" || path == "/sample") {
      const bool sample = path == "/sample";
      if (query.count("interval") != 0U) {
        StreamPlan plan;
        plan.is_sample = sample;
        plan.interval = std::chrono::milliseconds(number(query, "interval", 0));
        plan.heartbeat = std::chrono::milliseconds(number(query, "heartbeat", 10000));
        plan.next_sequence = sample ? number(query, "from", next_sequence()) : next_sequence();
        plan.target = std::string(target);
        routed.stream = plan;
      } else {
        StreamPlan once;
        once.is_sample = sample;
        once.next_sequence = number(query, "from", sample ? 1 : 0);
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

  static std::map<std::string, std::string> parse_query(std::string_view query) {
    std::map<std::string, std::string> result;
    while (!query.empty()) {
      const auto amp = query.find('&');
      const auto pair = query.substr(0, amp);
      const auto eq = pair.find('=');
      result[std::string(pair.substr(0, eq))] =
          eq == std::string_view::npos ? std::string() : std::string(pair.substr(eq + 1));
      query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    }
    return result;
  }

  static std::uint64_t number(const std::map<std::string, std::string>& query, const char* key,
                              std::uint64_t fallback) {
    const auto it = query.find(key);
    if (it == query.end()) return fallback;
    std::uint64_t value = fallback;
    std::from_chars(it->second.data(), it->second.data() + it->second.size(), value);
    return value;
  }

  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::vector<Observation> observations_;
  std::map<std::uint64_t, std::function<void()>> subscribers_;
  std::uint64_t next_ = 1;
  std::atomic<bool> parts_fail_{false};
  std::uint64_t last_subscription_ = 0;
};

}  // namespace mtc::bridge::test
