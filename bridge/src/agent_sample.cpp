// AgentImpl: /sample and streaming (interval) requests.
//
// count > 0: the first `count` matching observations from `from` (default:
// firstSequence) up to, not including, `to` (default: nextSequence);
// nextSequence is the sequence after the last one examined.
// count < 0, as the reference agent: the |count| matching observations
// walking back from `from` (default: lastSequence) to firstSequence,
// printed oldest first; nextSequence is the sequence below the oldest one
// examined (where a client walking back goes on). `to` takes no negative
// count.
// Either way a document stops at AgentOptions::max_document_bytes: a
// positive count then ends before the first observation left out (its
// nextSequence), a negative one keeps the newest.
#include <algorithm>

#include "agent_impl.hpp"

namespace mtc::bridge::detail {

namespace {

RequestError out_of_range(std::string text) {
  return {"OUT_OF_RANGE", 400, std::move(text)};
}

// Bytes one observation takes in a Streams document, about: the element's
// name twice, its attributes (timestamp 27 characters, the sequence up to
// 20 digits) and its value.
std::size_t printed_size(const DataItemInfo& item, const Observation& o) {
  constexpr std::size_t kFixed = 110;  // markup, timestamp and sequence
  return kFixed + 2 * item.element.size() + item.id.size() + item.name.size() +
         item.sub_type.size() + item.type.size() + o.value.size();
}

// Throws the error a /sample request with these from, to and count gets
// against a buffer holding [first, next).
void check_sample_range(const Query& q, std::int64_t first, std::int64_t next,
                        std::int64_t max_count) {
  const std::int64_t count = q.count.value();
  if (q.from && (*q.from < first || *q.from > next)) {
    throw out_of_range("'from' must be between " + std::to_string(first) + " and " +
                       std::to_string(next));
  }
  if (q.to && (*q.to <= q.from.value_or(first) || *q.to > next)) {
    throw out_of_range("'to' must be greater than 'from' (or firstSequence) and at most " +
                       std::to_string(next));
  }
  if (count == 0) throw out_of_range("'count' must not be zero");
  if (count > max_count || count < -max_count) {
    throw RequestError{"TOO_MANY", 400,
                       "'count' must be at most " + std::to_string(max_count) + " in magnitude"};
  }
  if (q.to && count < 0) throw out_of_range("'count' must be positive when 'to' is given");
}

// Shared stream parts (AgentImpl::part_cache_): at most this many queries
// at one position, and parts this large or larger are rendered per stream
// (a backlog's large part is rarely shared), so the cache holds at most
// kMaxSharedParts * kMaxSharedPartBytes, 4 MiB, whatever the clients ask.
constexpr std::size_t kMaxSharedParts = 64;
constexpr std::size_t kMaxSharedPartBytes = std::size_t{64} << 10;

// Everything a /sample part depends on besides the buffer and the model:
// the window, then what any cached document depends on.
std::string part_key(const Query& q) {
  std::string key;
  for (const std::optional<std::int64_t>& n : {q.from, q.to, q.count}) {
    key += n ? std::to_string(*n) : "-";
    key += '|';
  }
  return key + document_cache_key(q);
}

}  // namespace

Response AgentImpl::shared_part(const Query& q, std::uint64_t& next_out) const {
  const std::string key = part_key(q);
  const std::uint64_t position = buffer_.next_sequence();  // data_ held: fixed until we return
  {
    std::lock_guard lock(cache_mutex_);
    if (part_cache_.generation != generation_ || part_cache_.next_sequence != position) {
      part_cache_.parts.clear();  // something new: no part rendered before may be served
      part_cache_.bytes = 0;
      part_cache_.generation = generation_;
      part_cache_.next_sequence = position;
    }
    const auto it = part_cache_.parts.find(key);
    if (it != part_cache_.parts.end()) {
      ++parts_shared_;
      next_out = it->second.next_sequence;
      return {200, std::string(q.json ? "application/json" : "text/xml"),
              with_fresh_creation_time(it->second.body)};
    }
  }
  Response part = sample(q, next_out);
  std::lock_guard lock(cache_mutex_);
  ++parts_rendered_;
  // The state cannot have moved (data_ is held), but the cache is only
  // ever filled for the state it was emptied for.
  if (part_cache_.generation == generation_ && part_cache_.next_sequence == position &&
      part_cache_.parts.size() < kMaxSharedParts && part.body.size() < kMaxSharedPartBytes) {
    const auto [it, added] = part_cache_.parts.try_emplace(key, SharedPart{next_out, part.body});
    if (added) part_cache_.bytes += it->second.body.size();
  }
  return part;
}

Response AgentImpl::sample(const Query& q, std::uint64_t& next_out) const {
  const auto first = static_cast<std::int64_t>(buffer_.first_sequence());
  const auto next = static_cast<std::int64_t>(buffer_.next_sequence());
  const std::int64_t count = q.count.value();  // the route table gives its default
  check_sample_range(q, first, next, static_cast<std::int64_t>(max_count_));

  const std::vector<std::int32_t> filter = item_filter(q);
  auto selected = [&](std::uint64_t seq) -> const Observation* {
    const Observation* o = buffer_.find(seq);
    if (!o || o->slot >= filter.size() || filter[o->slot] < 0) return nullptr;
    return o;
  };
  std::vector<StreamEntry> entries;
  const auto lower = static_cast<std::uint64_t>(q.from.value_or(first));
  const auto upper = static_cast<std::uint64_t>(q.to.value_or(next));  // exclusive
  const auto wanted = static_cast<std::size_t>(count > 0 ? count : -count);
  std::size_t bytes = 0;
  // Takes the observation unless the document is full (never empty).
  auto take = [&](const Observation* o) {
    const auto item = static_cast<std::size_t>(filter[o->slot]);
    bytes += printed_size(model_.data_items()[item], *o);
    if (!entries.empty() && bytes > options_.max_document_bytes) return false;
    entries.push_back({item, o});
    return true;
  };
  std::uint64_t end = 0;
  if (count > 0) {
    std::uint64_t seq = lower;
    for (; seq < upper && entries.size() < wanted; ++seq) {
      const Observation* o = selected(seq);
      if (o && !take(o)) break;  // nextSequence: the one left out
    }
    end = seq;
  } else {
    const auto from = static_cast<std::uint64_t>(q.from.value_or(next));
    std::uint64_t seq = std::min(from, static_cast<std::uint64_t>(next) - 1);
    for (; seq >= static_cast<std::uint64_t>(first) && seq > 0 && entries.size() < wanted; --seq) {
      const Observation* o = selected(seq);
      if (o && !take(o)) break;  // the newest ones that fit
    }
    end = seq;
    std::reverse(entries.begin(), entries.end());
  }
  HeaderInfo h = header();
  h.next_sequence = end;
  next_out = end;
  return streams(q, h, entries);
}

Routed AgentImpl::stream(const Query& q, bool is_sample) const {
  // Validate everything the parts will need now, so a bad request gets an
  // error response instead of a stream.
  (void)item_filter(q);
  StreamPlan plan;
  plan.is_sample = is_sample;
  plan.interval = std::chrono::milliseconds(*q.interval);
  plan.heartbeat = std::chrono::milliseconds(q.heartbeat.value());  // or the route's default
  plan.parameters = static_cast<const RequestParameters&>(q);       // the parameters only
  if (is_sample) {
    std::uint64_t next = 0;
    Response first_part = sample(q, next);  // range checks of from/count
    (void)first_part;
    plan.next_sequence = static_cast<std::uint64_t>(
        q.from.value_or(static_cast<std::int64_t>(buffer_.first_sequence())));
  } else {
    plan.next_sequence = buffer_.next_sequence();
  }
  return Routed{std::nullopt, plan};
}

Response AgentImpl::next_part(StreamPlan& plan) noexcept {
  try {
    std::shared_lock lock(data_);
    Query q;
    static_cast<RequestParameters&>(q) = plan.parameters;
    // By name: a rebuilt model may have moved the device.
    if (q.device && !(q.device_index = model_.find_device(*q.device))) {
      throw RequestError{"NO_DEVICE", 404, "no device named '" + *q.device + "'"};
    }
    if (!plan.is_sample) {
      plan.next_sequence = buffer_.next_sequence();
      q.interval.reset();
      return handle_current(q).response.value();
    }
    if (plan.next_sequence < buffer_.first_sequence()) {
      throw RequestError{"OUT_OF_RANGE", 400,
                         "the stream fell behind the buffer: sequence " +
                             std::to_string(plan.next_sequence) + " was overwritten"};
    }
    q.from = static_cast<std::int64_t>(std::min(plan.next_sequence, buffer_.next_sequence()));
    if (q.count && *q.count < 0) q.count = -*q.count;
    std::uint64_t next = 0;
    Response part = shared_part(q, next);
    plan.next_sequence = next;
    return part;
  } catch (const RequestError& e) {
    return error(e, plan.parameters.json);
  } catch (const std::exception& e) {
    return error({"INTERNAL_ERROR", 500, e.what()}, plan.parameters.json);
  } catch (...) {
    Response r;
    r.status = 500;
    return r;
  }
}

}  // namespace mtc::bridge::detail
