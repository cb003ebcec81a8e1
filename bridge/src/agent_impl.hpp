// The concrete agent: model + buffer + printer + routes. Internal to
// mtc_bridge; users see MtconnectAgent (mtconnect_agent.hpp).
//
// Locking: `data_` (shared_mutex) guards model, slots, buffer, announced
// devices and stats; ingest takes it exclusively, rendering shares it.
// `cache_mutex_` guards the rendered-document cache only; `wait_mutex_`
// pairs with `wait_cv_` for streams; subscriber callbacks run with no lock
// held.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "json_printer.hpp"
#include "mtc/bridge/device_model.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/bridge/observation_buffer.hpp"
#include "mtc/bridge/printer.hpp"
#include "route_table.hpp"

namespace mtc::bridge::detail {

// A rendered document (XML or JSON) with its header's creationTime set to
// now: a document served again is created at the time of the response, as
// from the reference agent.
std::string with_fresh_creation_time(std::string body);

// What a rendered document depends on besides the buffer and the model:
// device, path filter, format and layout (the /current cache's key, and
// with the window in front, a shared stream part's).
std::string document_cache_key(const Query& q);

class AgentImpl final : public MtconnectAgent {
 public:
  explicit AgentImpl(const AgentOptions& options);

  using Agent::route;
  Routed route(const Request& request) noexcept override;
  Response next_part(StreamPlan& plan) noexcept override;
  Response error_document(int status, std::string_view code,
                          std::string_view message) noexcept override;
  std::uint64_t next_sequence() const noexcept override;
  bool wait_for(std::uint64_t from, std::chrono::milliseconds timeout) const override;
  std::uint64_t subscribe(std::function<void()> on_new_data) override;
  void unsubscribe(std::uint64_t id) override;

  // Text from DDS peers is made fit for XML first (make_xml_safe).
  void add_device(const core::ObservedDevice& announced) override;
  void add_value(const core::ObservedValue& received) override;
  void items_lost(const std::string& received_uuid,
                  const std::vector<std::string>& received_ids) override;
  void device_lost(const std::string& received_uuid) override;
  std::vector<ItemObservation> latest_observations(std::uint64_t& next) const override;
  bool observations_since(std::uint64_t from, std::size_t max, std::vector<ItemObservation>& out,
                          std::uint64_t& next) const override;
  AgentStats stats() const override;
  SchemaVersion schema_version() const noexcept override { return printer_.version(); }
  std::uint64_t instance_id() const noexcept override { return instance_id_; }

 private:
  // --- ingest (caller holds data_ exclusively) ---
  bool append_if_changed(std::uint32_t slot, const std::string& value, std::int64_t time_ns);
  void rebuild_model();
  // Room for one more announced device: true when below the limit or a
  // departed device was dropped to make it. Holds data_.
  bool make_room_for_announcement();
  // The file device an announcement maps onto (by uuid, or by name when
  // unclaimed); a warning when it claims one another announcement holds.
  std::optional<std::size_t> file_device_of(const core::ObservedDevice& device,
                                            std::string& warning);
  void mark_unobserved_unavailable(std::int64_t time_ns);
  void set_available(std::size_t device, std::int64_t time_ns);
  void notify(std::size_t appended);
  // The model's uuid for a DDS device uuid (a Devices file may know the
  // device under another uuid but the same name).
  const std::string& model_uuid(const std::string& dds_uuid) const;
  // Devices-file models: find (or map) the file's item for a DDS item.
  void resolve_announced(const core::ObservedDevice& device);
  std::optional<std::size_t> resolve_value(const core::ObservedValue& value);

  // --- requests (caller holds data_ shared) ---
  // The route table (agent_routes.cpp), with defaults from options_.
  RouteTable make_routes() const;
  Routed handle_root(const Query& q);
  Routed handle_web_file(const Query& q);
  Routed handle_probe(const Query& q);
  Routed handle_current(const Query& q);
  Routed handle_sample(const Query& q);
  Routed handle_assets(const Query& q);
  Routed handle_asset(const Query& q);
  std::vector<std::int32_t> item_filter(const Query& q) const;
  // model_.select under the path limits, remembered per model generation.
  std::vector<std::size_t> select(const std::string& path, std::optional<std::size_t> device) const;
  HeaderInfo header() const;
  Response current(const Query& q, const std::string& cache_key);
  Response sample(const Query& q, std::uint64_t& next_out) const;
  Response probe(const Query& q);
  // Error documents in the format the request asked for.
  Response error(const RequestError& e, bool json = false) const;
  Response error_locked(const RequestError& e, bool json) const;
  // A Streams document in the query's format.
  Response streams(const Query& q, const HeaderInfo& h,
                   const std::vector<StreamEntry>& entries) const;
  Routed stream(const Query& q, bool is_sample) const;
  // One part of a /sample stream at q.from, rendered once and shared by
  // every stream at the same position with the same query (part_cache_).
  Response shared_part(const Query& q, std::uint64_t& next_out) const;

  AgentOptions options_;
  Printer printer_;
  JsonPrinter json_printer_;
  std::uint64_t instance_id_ = 0;
  std::size_t max_count_ = 0;
  bool from_file_ = false;
  RouteTable routes_;  // make_routes(), once options_ and max_count_ are set

  mutable std::shared_mutex data_;
  DeviceModel model_;
  SlotRegistry slots_;
  ObservationBuffer buffer_;
  std::vector<core::ObservedDevice> announced_;
  std::vector<std::string> departed_;  // announced devices lost, oldest first
  // Announcement models: latest value of items not (yet) in the model,
  // applied when an announcement brings them.
  std::map<std::pair<std::string, std::string>, core::ObservedValue> pending_;
  AgentStats stats_;
  std::unordered_map<std::string, std::string> uuid_aliases_;  // DDS uuid -> file uuid
  std::set<std::pair<std::string, std::string>> warned_;       // unknown items reported
  std::uint64_t generation_ = 1;
  std::int64_t model_change_ns_ = 0;

  struct CachedDoc {
    std::uint64_t generation = 0;
    std::uint64_t next_sequence = 0;
    std::string body;
  };
  mutable std::mutex cache_mutex_;
  std::unordered_map<std::string, CachedDoc> cache_;
  // Stream parts of the buffer's present state: every entry was rendered
  // at (generation, next_sequence); the first part asked for after either
  // moves empties it, so a part is never served once something new could
  // be in it. Bounded in entries and bytes (kMaxSharedParts and
  // kMaxSharedPartBytes, agent_sample.cpp).
  struct SharedPart {
    std::uint64_t next_sequence = 0;  // the plan's position after the part
    std::string body;
  };
  struct PartCache {
    std::uint64_t generation = 0;
    std::uint64_t next_sequence = 0;
    std::size_t bytes = 0;
    std::unordered_map<std::string, SharedPart> parts;
  };
  mutable PartCache part_cache_;
  mutable std::uint64_t parts_rendered_ = 0;  // guarded by cache_mutex_
  mutable std::uint64_t parts_shared_ = 0;    // guarded by cache_mutex_
  // "<device>|<path>" -> (generation, selected items).
  mutable std::unordered_map<std::string, std::pair<std::uint64_t, std::vector<std::size_t>>>
      selections_;

  mutable std::mutex wait_mutex_;
  mutable std::condition_variable wait_cv_;
  std::atomic<std::uint64_t> next_sequence_{1};

  std::mutex subscribers_mutex_;
  std::map<std::uint64_t, std::function<void()>> subscribers_;
  std::uint64_t next_subscriber_ = 1;
};

}  // namespace mtc::bridge::detail
