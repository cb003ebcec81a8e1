// AgentImpl: the route table, and the probe, current and assets handlers.
//
// Routes (device = name or uuid), each a row of make_routes():
//   /                                            the live page for browsers
//                                                (Accept: text/html), else probe
//   /web/{file}                                  the page's scripts and style
//   /probe  /{device}  /{device}/probe           MTConnectDevices
//   /current   /{device}/current                 MTConnectStreams (path, at, interval)
//   /sample    /{device}/sample                  MTConnectStreams (path, from, to, count,
//                                                interval, heartbeat)
//   /assets    /{device}/assets  /asset(s)/{id}  MTConnectAssets (always empty)
// Status codes follow the reference agent: parameter errors 400, unknown
// device 404, unknown route 404, methods other than GET/HEAD 405.
// Every document is XML or, when asked for (format=json, or Accept naming
// application/json), MTConnect JSON: see negotiate().
#include <algorithm>
#include <chrono>

#include "agent_impl.hpp"
#include "web_files.hpp"

namespace mtc::bridge::detail {

namespace {

// Longest interval or heartbeat: what a signed 32-bit millisecond timer holds.
constexpr std::int64_t kMaxMillis = 2147483646;

using P = RequestParameters;

// Every query parameter an MTConnect request may carry, with its type and
// range; the routes below pick theirs and give some a default.
const Param kPath = text_param("path", &P::path);
const Param kPretty = flag_param("pretty", &P::pretty);
const Param kAt = integer_param("at", &P::at);
const Param kFrom = integer_param("from", &P::from);
const Param kTo = integer_param("to", &P::to);
const Param kCount = integer_param("count", &P::count);
const Param kInterval = integer_param("interval", &P::interval).between(0, kMaxMillis);
const Param kHeartbeat = integer_param("heartbeat", &P::heartbeat).between(1, kMaxMillis);

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

RequestError out_of_range(std::string text) {
  return {"OUT_OF_RANGE", 400, std::move(text)};
}

constexpr std::string_view kJsonType = "application/json";
constexpr std::string_view kXmlType = "text/xml";

bool names_media_type(std::string_view accept, std::string_view type) {
  return accept.find(type) != std::string_view::npos;
}

// The format a request asks for, as the reference agent reads it: the
// `format` parameter (xml or json) decides; without it an Accept header
// naming application/json asks for JSON, and one naming text/html marks a
// browser (served the live page at `/`). Throws RequestError for another
// `format`.
void negotiate(const Request& request, RequestParameters& out) {
  const auto& query = request.target->query;
  const auto format = std::find_if(query.begin(), query.end(),
                                   [](const auto& pair) { return pair.first == "format"; });
  if (format == query.end()) {
    out.json = names_media_type(request.accept, kJsonType);
    out.browser = names_media_type(request.accept, "text/html");
  } else if (format->second == "json" || format->second == "xml") {
    out.json = format->second == "json";
  } else {
    out.json = names_media_type(request.accept, kJsonType);
    throw RequestError{"INVALID_REQUEST", 400,
                       "'format' must be xml or json, not '" + format->second.substr(0, 64) + "'"};
  }
}

}  // namespace

// Unambiguous whatever bytes the path holds: the device index has no '|'
// and the format and layout come after the path's last '|'.
std::string document_cache_key(const Query& q) {
  return std::to_string(q.device_index ? *q.device_index : SIZE_MAX) + '|' + q.path.value_or("") +
         '|' + (q.json ? "j" : "x") + (q.pretty ? "p" : "");
}

// A cached document's header creationTime set to now: it is the time of
// the response (as from the reference agent), not of the render. Both the
// XML (creationTime="...") and the JSON ("creationTime":"...") forms.
std::string with_fresh_creation_time(std::string body) {
  constexpr std::string_view kName = "creationTime";
  const std::size_t name = body.find(kName);
  if (name == std::string::npos) return body;
  std::size_t i = name + kName.size();
  if (i < body.size() && body[i] == '"') ++i;  // JSON: the key's closing quote
  const std::size_t open = body.find('"', i);
  const std::size_t close = open == std::string::npos ? open : body.find('"', open + 1);
  if (close == std::string::npos) return body;
  body.replace(open + 1, close - open - 1, format_creation_time(now_ns()));
  return body;
}

RouteTable AgentImpl::make_routes() const {
  const auto heartbeat = static_cast<std::int64_t>(options_.stream_heartbeat.count());
  // The configured default, but never more than the buffer holds.
  const auto count = static_cast<std::int64_t>(std::min(options_.default_count, max_count_));
  // probe and assets read the query as current does.
  const QuerySpec current{{kPath, kAt, kInterval, kHeartbeat.or_default(heartbeat), kPretty},
                          {kFrom, kTo, kCount},
                          "'from', 'to' and 'count' apply to sample only",
                          {{"at", "interval"}}};
  const QuerySpec sample{{kPath, kFrom, kTo, kCount.or_default(count), kInterval,
                          kHeartbeat.or_default(heartbeat), kPretty},
                         {kAt},
                         "'at' applies to current only",
                         {{"to", "interval"}}};
  return RouteTable({
      {{"/asset/{asset}", "/assets/{asset}"}, std::nullopt, &AgentImpl::handle_asset},
      {{"/"}, current, &AgentImpl::handle_root},
      {{"/probe", "/{device}", "/{device}/probe"}, current, &AgentImpl::handle_probe},
      {{"/current", "/{device}/current"}, current, &AgentImpl::handle_current},
      {{"/sample", "/{device}/sample"}, sample, &AgentImpl::handle_sample},
      {{"/assets", "/{device}/assets"}, current, &AgentImpl::handle_assets},
      // Last: a device named "web" keeps its /web/probe and the like.
      {{"/web/{asset}"}, std::nullopt, &AgentImpl::handle_web_file},
  });
}

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

Response AgentImpl::error_locked(const RequestError& e, bool json) const {
  Response r;
  r.status = e.status;
  const std::vector<ErrorEntry> errors{ErrorEntry{e.code, e.text}};
  r.content_type = json ? kJsonType : kXmlType;
  r.body = json ? json_printer_.error(header(), errors) : printer_.error(header(), errors);
  return r;
}

Response AgentImpl::error(const RequestError& e, bool json) const {
  std::shared_lock lock(data_);
  return error_locked(e, json);
}

Response AgentImpl::streams(const Query& q, const HeaderInfo& h,
                            const std::vector<StreamEntry>& entries) const {
  if (q.json) {
    return {200, std::string(kJsonType),
            json_printer_.streams(h, model_, q.device_index, entries, q.pretty)};
  }
  return {200, std::string(kXmlType),
          printer_.streams(h, model_, q.device_index, entries, q.pretty)};
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

Routed AgentImpl::route(const Request& request) noexcept {
  RequestParameters wanted;  // the format, known before anything can fail
  try {
    if (request.method != "GET" && request.method != "HEAD") {
      return Routed{error({"UNSUPPORTED", 405,
                           "only GET is supported, not '" + request.method.substr(0, 32) + "'"}),
                    std::nullopt};
    }
    if (!request.target) throw RequestError{"INVALID_URI", 400, request.target_error};
    negotiate(request, wanted);
    std::shared_lock lock(data_);
    RouteTable::Match match = routes_.match(*request.target, model_);
    match.query.json = wanted.json;
    match.query.browser = wanted.browser;
    return (this->*match.route->handler)(match.query);
  } catch (const RequestError& e) {
    return Routed{error(e, wanted.json), std::nullopt};
  } catch (const std::exception& e) {
    return Routed{error({"INTERNAL_ERROR", 500, e.what()}, wanted.json), std::nullopt};
  } catch (...) {
    Response r;
    r.status = 500;
    return Routed{r, std::nullopt};
  }
}

// A member like the other handlers, because the route table holds member
// pointers, though it needs no state.
// NOLINTNEXTLINE(readability-convert-member-functions-to-static)
Routed AgentImpl::handle_asset(const Query& q) {
  throw RequestError{"ASSET_NOT_FOUND", 404, "the bridge stores no assets: '" + *q.asset + "'"};
}

Routed AgentImpl::handle_root(const Query& q) {
  // Browsers get the live page; every other client the probe, as from the
  // reference agent.
  if (!q.browser) return handle_probe(q);
  Query page;
  page.asset = std::string(kPageFile);
  return handle_web_file(page);
}

// A member like the other handlers, because the route table holds member
// pointers, though it needs no state.
// NOLINTNEXTLINE(readability-convert-member-functions-to-static)
Routed AgentImpl::handle_web_file(const Query& q) {
  const WebFile* file = find_web_file(*q.asset);
  if (!file) throw RequestError{"INVALID_URI", 404, "the bridge has no file '" + *q.asset + "'"};
  return Routed{Response{200, std::string(file->content_type), std::string(file->body)},
                std::nullopt};
}

Routed AgentImpl::handle_probe(const Query& q) {
  return Routed{probe(q), std::nullopt};
}

Routed AgentImpl::handle_assets(const Query& q) {
  if (q.json) {
    return Routed{Response{200, std::string(kJsonType), json_printer_.assets(header(), q.pretty)},
                  std::nullopt};
  }
  return Routed{Response{200, std::string(kXmlType), printer_.assets(header(), q.pretty)},
                std::nullopt};
}

Routed AgentImpl::handle_current(const Query& q) {
  if (q.interval) return stream(q, false);
  return Routed{current(q, document_cache_key(q)), std::nullopt};
}

Routed AgentImpl::handle_sample(const Query& q) {
  if (q.interval) return stream(q, true);
  std::uint64_t next = 0;
  return Routed{sample(q, next), std::nullopt};
}

std::vector<std::size_t> AgentImpl::select(const std::string& path,
                                           std::optional<std::size_t> device) const {
  // Remembered per model: a stream re-reads its path for every part.
  const std::string key = std::to_string(device ? *device : SIZE_MAX) + '|' + path;
  {
    std::lock_guard lock(cache_mutex_);
    const auto it = selections_.find(key);
    if (it != selections_.end() && it->second.first == generation_) return it->second.second;
  }
  std::vector<std::size_t> items;
  try {
    items = model_.select(path, device, options_.path_limits);
  } catch (const std::invalid_argument& e) {
    throw RequestError{"INVALID_PATH", 400, "the path is not accepted: " + std::string(e.what())};
  }
  std::lock_guard lock(cache_mutex_);
  if (selections_.size() > 256) selections_.clear();  // bound memory against path variety
  selections_[key] = {generation_, items};
  return items;
}

std::vector<std::int32_t> AgentImpl::item_filter(const Query& q) const {
  std::vector<std::size_t> items;
  if (q.path) {
    items = select(*q.path, q.device_index);
    if (items.empty()) {
      throw RequestError{"INVALID_PATH", 400, "the path selects no data items: " + *q.path};
    }
  } else {
    items = model_.all_items(q.device_index);
  }
  std::vector<std::int32_t> by_slot(slots_.size(), -1);
  for (std::size_t i : items) by_slot[model_.data_items()[i].slot] = static_cast<std::int32_t>(i);
  return by_slot;
}

Response AgentImpl::probe(const Query& q) {
  const std::string key = "probe|" + std::to_string(q.device_index ? *q.device_index : SIZE_MAX) +
                          (q.json ? "j" : "x") + (q.pretty ? "p" : "");
  const std::string type(q.json ? kJsonType : kXmlType);
  {
    std::lock_guard lock(cache_mutex_);
    const auto it = cache_.find(key);
    if (it != cache_.end() && it->second.generation == generation_) {
      return {200, type, with_fresh_creation_time(it->second.body)};
    }
  }
  std::string body = q.json ? json_printer_.probe(header(), model_, q.device_index, q.pretty)
                            : printer_.probe(header(), model_, q.device_index, q.pretty);
  std::lock_guard lock(cache_mutex_);
  cache_[key] = CachedDoc{generation_, 0, body};
  return {200, type, std::move(body)};
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
      return {200, std::string(q.json ? kJsonType : kXmlType),
              with_fresh_creation_time(it->second.body)};
    }
  }
  const std::vector<std::int32_t> filter = item_filter(q);
  std::vector<StreamEntry> entries;
  std::vector<Observation> state;
  HeaderInfo h = header();
  // nextSequence stays the buffer's, after `at` too, as the reference
  // agent answers.
  if (q.at) state = buffer_.state_at(static_cast<std::uint64_t>(*q.at));
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
  Response response = streams(q, h, entries);
  if (!q.at) {
    std::lock_guard lock(cache_mutex_);
    if (cache_.size() > 256) cache_.clear();  // bound memory against path variety
    cache_[cache_key] = CachedDoc{generation_, buffer_.next_sequence(), response.body};
  }
  return response;
}

}  // namespace mtc::bridge::detail
