// AgentImpl: routing, parameter validation and document rendering.
//
// Routes (device = name or uuid):
//   /  /probe  /{device}  /{device}/probe        MTConnectDevices
//   /current   /{device}/current                 MTConnectStreams (path, at, interval)
//   /sample    /{device}/sample                  MTConnectStreams (path, from, to, count,
//                                                interval, heartbeat)
//   /assets    /{device}/assets  /asset(s)/{id}  MTConnectAssets (always empty)
// Status codes follow the reference agent: parameter errors 400, unknown
// device 404, unknown route 404, methods other than GET/HEAD 405.
#include <algorithm>
#include <chrono>

#include "agent_impl.hpp"

namespace mtc::bridge::detail {

namespace {

constexpr std::int64_t kMaxMillis = 2147483646;

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool is_request(std::string_view s) {
  return s == "probe" || s == "current" || s == "sample" || s == "assets";
}

RequestError out_of_range(std::string text) { return {"OUT_OF_RANGE", 400, std::move(text)}; }

// Parameters that do not belong together or to this request, and the
// ranges that do not depend on the buffer.
void check_combination(const Query& q, bool sample) {
  if (sample && q.at) throw RequestError{"INVALID_REQUEST", 400, "'at' applies to current only"};
  if (!sample && (q.from || q.to || q.count)) {
    throw RequestError{"INVALID_REQUEST", 400, "'from', 'to' and 'count' apply to sample only"};
  }
  if (q.at && q.interval) {
    throw RequestError{"INVALID_REQUEST", 400, "'at' cannot be used with 'interval'"};
  }
  if (q.to && q.interval) {
    throw RequestError{"INVALID_REQUEST", 400, "'to' cannot be used with 'interval'"};
  }
  if (q.interval && (*q.interval < 0 || *q.interval > kMaxMillis)) {
    throw out_of_range("'interval' must be between 0 and " + std::to_string(kMaxMillis));
  }
  if (q.heartbeat && (*q.heartbeat < 1 || *q.heartbeat > kMaxMillis)) {
    throw out_of_range("'heartbeat' must be between 1 and " + std::to_string(kMaxMillis));
  }
}

}  // namespace

HeaderInfo AgentImpl::header() const {
  HeaderInfo h;
  h.instance_id = instance_id_;
  h.sender = options_.sender;
  h.buffer_size = buffer_.capacity();
  h.first_sequence = buffer_.first_sequence();
  // The schemas require lastSequence >= 1; before the first observation
  // (no device announced yet) report 1 rather than an invalid 0.
  h.last_sequence = std::max<std::uint64_t>(1, buffer_.last_sequence());
  h.next_sequence = buffer_.next_sequence();
  h.model_change_time_ns = model_change_ns_;
  h.creation_time_ns = now_ns();
  // The bridge stores no assets, but the schemas require assetBufferSize
  // >= 1; report the size agents use by default.
  h.asset_buffer_size = 1024;
  return h;
}

Response AgentImpl::error_locked(const RequestError& e) const {
  Response r;
  r.status = e.status;
  r.body = printer_.error(header(), {ErrorEntry{e.code, e.text}});
  return r;
}

Response AgentImpl::error(const RequestError& e) const {
  std::shared_lock lock(data_);
  return error_locked(e);
}

Response AgentImpl::error_document(int status, std::string_view code,
                                   std::string_view message) noexcept {
  try {
    return error(RequestError{code, status, std::string(message)});
  } catch (...) {
    Response r;  // out of memory: the status alone
    r.status = status;
    return r;
  }
}

Routed AgentImpl::route(std::string_view method, std::string_view target) noexcept {
  try {
    if (method != "GET" && method != "HEAD") {
      return Routed{error({"UNSUPPORTED", 405,
                           "only GET is supported, not '" + std::string(method.substr(0, 32)) + "'"}),
                    std::nullopt};
    }
    return route_target(target);
  } catch (const RequestError& e) {
    return Routed{error(e), std::nullopt};
  } catch (const std::exception& e) {
    return Routed{error({"INTERNAL_ERROR", 500, e.what()}), std::nullopt};
  } catch (...) {
    Response r;
    r.status = 500;
    return Routed{r, std::nullopt};
  }
}

Routed AgentImpl::route_target(std::string_view target) {
  std::string why;
  const auto parsed = parse_target(target, why);
  if (!parsed) throw RequestError{"INVALID_URI", 400, why};
  const auto& seg = parsed->segments;
  if (seg.size() >= 1 && (seg[0] == "asset" || seg[0] == "assets") && seg.size() == 2) {
    throw RequestError{"ASSET_NOT_FOUND", 404, "the bridge stores no assets: '" + seg[1] + "'"};
  }
  std::shared_lock lock(data_);
  std::optional<std::size_t> device;
  std::string request = "probe";
  if (seg.size() == 1) {
    if (is_request(seg[0])) {
      request = seg[0];
    } else if (!(device = model_.find_device(seg[0]))) {
      throw RequestError{"NO_DEVICE", 404, "no device named '" + seg[0] + "'"};
    }
  } else if (seg.size() == 2) {
    if (!(device = model_.find_device(seg[0]))) {
      throw RequestError{"NO_DEVICE", 404, "no device named '" + seg[0] + "'"};
    }
    if (!is_request(seg[1])) {
      throw RequestError{"INVALID_URI", 404, "unknown request '" + seg[1] + "'"};
    }
    request = seg[1];
  } else if (seg.size() > 2) {
    throw RequestError{"INVALID_URI", 404, "unknown request path"};
  }

  const bool sample = request == "sample";
  Query q = parse_query(*parsed, device, sample);
  if (request == "probe") return Routed{probe(q), std::nullopt};
  if (request == "assets") {
    HeaderInfo h = header();
    return Routed{Response{200, "text/xml", printer_.assets(h, q.pretty)}, std::nullopt};
  }
  if (q.interval) return stream(q, target, sample);
  if (sample) {
    std::uint64_t next = 0;
    return Routed{this->sample(q, next), std::nullopt};
  }
  const std::string key = std::to_string(device ? *device : SIZE_MAX) + '|' +
                          q.path.value_or("") + '|' + (q.pretty ? "p" : "");
  return Routed{current(q, key), std::nullopt};
}

Query AgentImpl::parse_query(const RequestTarget& t, std::optional<std::size_t> device,
                             bool sample) const {
  Query q;
  q.device = device;
  std::vector<std::string_view> seen;
  for (const auto& [name, value] : t.query) {
    for (std::string_view s : seen) {
      if (s == name) throw RequestError{"INVALID_REQUEST", 400, "'" + name + "' given twice"};
    }
    seen.push_back(name);
    if (name == "path") {
      q.path = value;
      continue;
    }
    if (name == "pretty") {
      if (value != "true" && value != "false") {
        throw RequestError{"INVALID_REQUEST", 400, "'pretty' must be true or false"};
      }
      q.pretty = value == "true";
      continue;
    }
    std::optional<std::int64_t>* slot = name == "at"          ? &q.at
                                         : name == "from"      ? &q.from
                                         : name == "to"        ? &q.to
                                         : name == "count"     ? &q.count
                                         : name == "interval"  ? &q.interval
                                         : name == "heartbeat" ? &q.heartbeat
                                                               : nullptr;
    if (!slot) continue;  // unknown parameters are ignored, as agents do
    std::int64_t v = 0;
    switch (parse_integer(value, v)) {
      case IntegerError::NotInteger:
        throw RequestError{"INVALID_REQUEST", 400, "'" + name + "' must be an integer, not '" +
                                                       value.substr(0, 64) + "'"};
      case IntegerError::Overflow:
        throw out_of_range("'" + name + "' is too large");
      case IntegerError::None:
        break;
    }
    *slot = v;
  }
  check_combination(q, sample);
  return q;
}

std::vector<std::int32_t> AgentImpl::item_filter(const Query& q) const {
  std::vector<std::size_t> items;
  if (q.path) {
    try {
      items = model_.select(*q.path, q.device);
    } catch (const std::invalid_argument& e) {
      throw RequestError{"INVALID_PATH", 400, "the path could not be parsed: " + std::string(e.what())};
    }
    if (items.empty()) {
      throw RequestError{"INVALID_PATH", 400, "the path selects no data items: " + *q.path};
    }
  } else {
    items = model_.all_items(q.device);
  }
  std::vector<std::int32_t> by_slot(slots_.size(), -1);
  for (std::size_t i : items) by_slot[model_.data_items()[i].slot] = static_cast<std::int32_t>(i);
  return by_slot;
}

Response AgentImpl::probe(const Query& q) {
  const std::string key = "probe|" + std::to_string(q.device ? *q.device : SIZE_MAX) + (q.pretty ? "p" : "");
  {
    std::lock_guard lock(cache_mutex_);
    const auto it = cache_.find(key);
    if (it != cache_.end() && it->second.generation == generation_) return {200, "text/xml", it->second.body};
  }
  std::string body = printer_.probe(header(), model_, q.device, q.pretty);
  std::lock_guard lock(cache_mutex_);
  cache_[key] = CachedDoc{generation_, 0, body};
  return {200, "text/xml", std::move(body)};
}

Response AgentImpl::current(const Query& q, const std::string& cache_key) {
  if (q.at) {
    if (buffer_.empty() || *q.at < static_cast<std::int64_t>(buffer_.first_sequence()) ||
        *q.at > static_cast<std::int64_t>(buffer_.last_sequence())) {
      throw out_of_range("'at' must be between " + std::to_string(buffer_.first_sequence()) +
                         " and " + std::to_string(buffer_.last_sequence()));
    }
  } else {
    std::lock_guard lock(cache_mutex_);
    const auto it = cache_.find(cache_key);
    if (it != cache_.end() && it->second.generation == generation_ &&
        it->second.next_sequence == buffer_.next_sequence()) {
      return {200, "text/xml", it->second.body};
    }
  }
  const std::vector<std::int32_t> filter = item_filter(q);
  std::vector<StreamEntry> entries;
  std::vector<Observation> state;
  HeaderInfo h = header();
  if (q.at) {
    state = buffer_.state_at(static_cast<std::uint64_t>(*q.at));
    h.next_sequence = static_cast<std::uint64_t>(*q.at) + 1;
  }
  for (std::size_t slot = 0; slot < filter.size(); ++slot) {
    if (filter[slot] < 0) continue;
    const Observation* o = nullptr;
    if (q.at) {
      if (slot < state.size() && state[slot].sequence != 0) o = &state[slot];
    } else {
      o = buffer_.latest(static_cast<std::uint32_t>(slot));
    }
    if (o) entries.push_back({static_cast<std::size_t>(filter[slot]), o});
  }
  std::sort(entries.begin(), entries.end(),
            [](const StreamEntry& a, const StreamEntry& b) { return a.item < b.item; });
  std::string body = printer_.streams(h, model_, q.device, entries, q.pretty);
  if (!q.at) {
    std::lock_guard lock(cache_mutex_);
    if (cache_.size() > 256) cache_.clear();  // bound memory against path variety
    cache_[cache_key] = CachedDoc{generation_, buffer_.next_sequence(), body};
  }
  return {200, "text/xml", std::move(body)};
}

}  // namespace mtc::bridge::detail
