// A fluent description of the QoS of one DDS endpoint (topic + writer/reader),
// in the rclcpp style:
//
//   auto q = EndpointQos().reliable().transient_local().keep_last(1)
//                .deadline(300ms).liveliness_manual_by_topic(300ms);
//
// The value object keeps only the policies this project sets and names no
// middleware: it is the one description of a preset, which each middleware
// reads in its own terms (fastdds_qos.hpp for Fast DDS, cyclone_qos.hpp for
// Cyclone DDS). Nothing here may include a vendor header, so that code
// choosing QoS need not see the middleware (qos.neutral_headers_see_no_fast_dds).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace mtc::qos {

enum class Reliability : std::uint8_t { BestEffort, Reliable };
enum class Durability : std::uint8_t { Volatile, TransientLocal };
enum class Liveliness : std::uint8_t { Automatic, ManualByParticipant, ManualByTopic };
enum class Ownership : std::uint8_t { Shared, Exclusive };

class EndpointQos {
 public:
  EndpointQos& reliable() noexcept;
  EndpointQos& best_effort() noexcept;
  EndpointQos& transient_local() noexcept;
  EndpointQos& durability_volatile() noexcept;
  EndpointQos& keep_last(std::int32_t depth) noexcept;
  EndpointQos& keep_all() noexcept;
  EndpointQos& deadline(std::chrono::nanoseconds period) noexcept;
  EndpointQos& liveliness_manual_by_topic(std::chrono::nanoseconds lease) noexcept;
  // Provided for completeness and for compatibility tests only: in Fast DDS
  // 2.9.1 these kinds let one participant keep another's writers alive.
  EndpointQos& liveliness(Liveliness kind, std::chrono::nanoseconds lease) noexcept;
  EndpointQos& exclusive_ownership(std::int32_t strength) noexcept;
  EndpointQos& shared_ownership() noexcept;
  // Writer-side RTPS HEARTBEAT period (repair latency after a lost packet).
  EndpointQos& reliable_heartbeat(std::chrono::nanoseconds period) noexcept;
  // Upper bound on instances per endpoint (each data item is an instance).
  EndpointQos& max_instances(std::int32_t count) noexcept;
  // Reader-side bound (default: the same as max_instances): a reader may see
  // the items of many writers.
  EndpointQos& reader_max_instances(std::int32_t count) noexcept;
  // Reader-side history depth per instance (default: the same as keep_last).
  EndpointQos& reader_depth(std::int32_t depth) noexcept;

  Reliability reliability() const noexcept { return reliability_; }
  Durability durability() const noexcept { return durability_; }
  bool is_keep_all() const noexcept { return keep_all_; }
  std::int32_t depth() const noexcept { return depth_; }
  std::optional<std::chrono::nanoseconds> deadline() const noexcept { return deadline_; }
  Liveliness liveliness_kind() const noexcept { return liveliness_; }
  std::optional<std::chrono::nanoseconds> liveliness_lease() const noexcept { return lease_; }
  Ownership ownership() const noexcept { return ownership_; }
  std::int32_t ownership_strength() const noexcept { return strength_; }
  std::optional<std::chrono::nanoseconds> reliable_heartbeat() const noexcept {
    return rtps_heartbeat_;
  }
  std::int32_t max_instances() const noexcept { return max_instances_; }
  std::int32_t reader_depth() const noexcept { return reader_depth_ > 0 ? reader_depth_ : depth_; }
  std::int32_t reader_max_instances() const noexcept {
    return reader_max_instances_ > 0 ? reader_max_instances_ : max_instances_;
  }

 private:
  Reliability reliability_ = Reliability::Reliable;
  Durability durability_ = Durability::Volatile;
  bool keep_all_ = false;
  std::int32_t depth_ = 1;
  std::optional<std::chrono::nanoseconds> deadline_;
  Liveliness liveliness_ = Liveliness::Automatic;
  std::optional<std::chrono::nanoseconds> lease_;
  Ownership ownership_ = Ownership::Shared;
  std::int32_t strength_ = 0;
  std::optional<std::chrono::nanoseconds> rtps_heartbeat_;
  std::int32_t max_instances_ = 1024;
  std::int32_t reader_depth_ = 0;
  std::int32_t reader_max_instances_ = 0;
};

}  // namespace mtc::qos
