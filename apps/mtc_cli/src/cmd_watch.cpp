// `mtc watch`: a live view of every device, interface and data item on a
// domain, one line per transition with source time, reception time and the
// latency between them. Items whose device's heartbeats stopped turn
// UNAVAILABLE, and come back with their last value when they resume.
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "command_session.hpp"
#include "commands.hpp"
#include "exit_codes.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "observed_format.hpp"

namespace mtc::cli {
namespace {

// Renders observer callbacks; runs on the observer's dispatch thread.
class WatchPrinter {
 public:
  WatchPrinter(Output& out, bool json, bool heartbeats)
      : out_(out), json_(json), heartbeats_(heartbeats) {}

  void device(const dds::ObservedDevice& d) {
    if (json_) {
      JsonLine line;
      line.field("event", "device").field("device", d.device_uuid).field("name", d.name);
      out_.line(line.raw_field("interfaces", interfaces_json(d))
                    .field("reception_time_ns", now_ns())
                    .str());
      return;
    }
    std::string text = format_utc(now_ns()) + "  device " + d.device_uuid + " '" + d.name + "'\n" +
                       interfaces_text(d, "    ");
    text.pop_back();
    out_.line(text);
  }

  void value(const dds::ObservedValue& v) {
    const std::string text = core::to_string(v.state);
    std::string previous;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      labels_[{v.device_uuid, v.data_item_id}] = v.interface_id + "  " + item_label(v);
      auto& slot = last_[{v.device_uuid, v.data_item_id}];
      previous = slot.empty() ? "-" : slot;
      slot = text;
    }
    // The same value again (a device writes an unchanged item again to keep
    // its writer's history short): not a transition.
    if (previous == text) {
      return;
    }
    const std::int64_t latency = v.reception_time_ns - v.source_time_ns;
    if (json_) {
      JsonLine line;
      line.field("event", "value")
          .field("device", v.device_uuid)
          .field("interface", v.interface_id)
          .field("item", v.data_item_id)
          .field("kind", to_string(v.kind()))
          .field("label", item_label(v))
          .field("previous", previous)
          .field("value", text)
          .field("sequence", v.sequence_number)
          .field("heartbeat_group", static_cast<std::uint64_t>(v.heartbeat_group))
          .field("redelivered", v.redelivered)
          .field("source_time_ns", v.source_time_ns)
          .field("reception_time_ns", v.reception_time_ns)
          .field("latency_ms", static_cast<double>(latency) / 1e6);
      out_.line(line.str());
      return;
    }
    out_.line(format_utc(v.reception_time_ns) + "  " + v.device_uuid + "/" + v.interface_id + "  " +
              item_label(v) + "  " + previous + " -> " + text + "  (source " +
              format_utc(v.source_time_ns) + ", latency " + format_ms(latency) + ", seq " +
              std::to_string(v.sequence_number) + (v.redelivered ? ", last value again" : "") +
              ")");
  }

  // With --heartbeats: every heartbeat, with the change numbers it announces.
  void heartbeat(const dds::ObservedHeartbeat& h) {
    if (!heartbeats_) {
      return;
    }
    if (json_) {
      JsonLine line;
      out_.line(line.field("event", "heartbeat")
                    .field("device", h.device_uuid)
                    .field("group", static_cast<std::uint64_t>(h.group))
                    .field("beat", h.beat)
                    .field("period_ms", static_cast<std::uint64_t>(h.period_ms))
                    .field("lease_ms", static_cast<std::uint64_t>(h.lease_ms))
                    .field("request_changes", h.request_changes)
                    .field("response_changes", h.response_changes)
                    .field("interface_state_changes", h.interface_state_changes)
                    .field("door_state_changes", h.door_state_changes)
                    .field("chuck_state_changes", h.chuck_state_changes)
                    .field("source_time_ns", h.source_time_ns)
                    .field("reception_time_ns", h.reception_time_ns)
                    .str());
      return;
    }
    // period_ms 0 is a group's last heartbeat: the device is leaving.
    const std::string period =
        h.period_ms == 0 ? "leaving" : "every " + std::to_string(h.period_ms) + " ms";
    out_.line(format_utc(h.reception_time_ns) + "  " + h.device_uuid + "  heartbeat group " +
              std::to_string(h.group) + " #" + std::to_string(h.beat) + "  (" + period +
              ", lease " + std::to_string(h.lease_ms) + " ms; changes: request " +
              std::to_string(h.request_changes) + ", response " +
              std::to_string(h.response_changes) + ", interface state " +
              std::to_string(h.interface_state_changes) + ")");
  }

  void items_lost(const std::string& device, const std::vector<std::string>& items) {
    const std::int64_t now = now_ns();
    for (const auto& item : items) {
      std::string previous;
      std::string label = item;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = labels_.find({device, item}); it != labels_.end()) {
          label = it->second;
        }
        auto& slot = last_[{device, item}];
        previous = slot.empty() ? "-" : slot;
        slot = "UNAVAILABLE";
      }
      if (json_) {
        JsonLine line;
        line.field("event", "lost")
            .field("device", device)
            .field("item", item)
            .field("label", label)
            .field("previous", previous)
            .field("value", "UNAVAILABLE")
            .field("reception_time_ns", now);
        out_.line(line.str());
      } else {
        std::string text = format_utc(now);
        text += "  ";
        text += device;
        text += '/';
        text += label;
        text += "  ";
        text += previous;
        text += " -> UNAVAILABLE  (heartbeats stopped, or disposed)";
        out_.line(text);
      }
    }
  }

  void device_lost(const std::string& device) {
    const std::int64_t now = now_ns();
    if (json_) {
      JsonLine line;
      out_.line(line.field("event", "device_lost")
                    .field("device", device)
                    .field("reception_time_ns", now)
                    .str());
    } else {
      out_.line(format_utc(now) + "  device " + device + " lost");
    }
  }

 private:
  Output& out_;
  bool json_;
  bool heartbeats_;
  std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, std::string> last_;
  // "mh  MATERIAL_LOAD REQUEST" per (device, data item id), for lost items.
  std::map<std::pair<std::string, std::string>, std::string> labels_;
};

int run_watch(const ParsedArgs& args, Context& context) {
  const CommonOptions common = parse_common_options(args);
  std::optional<std::chrono::milliseconds> duration;
  if (auto d = args.value("duration")) {
    duration = to_duration("duration", *d);
  }
  WatchPrinter printer(context.out, common.json, args.has("heartbeats"));

  const dds::DomainObserverOptions options = observer_options(common, args);
  dds::DomainObserverCallbacks callbacks;
  callbacks.on_device = [&](const dds::ObservedDevice& d) { printer.device(d); };
  callbacks.on_value = [&](const dds::ObservedValue& v) { printer.value(v); };
  callbacks.on_items_lost = [&](const std::string& dev, const std::vector<std::string>& items) {
    printer.items_lost(dev, items);
  };
  callbacks.on_device_lost = [&](const std::string& dev) { printer.device_lost(dev); };
  if (args.has("heartbeats")) {
    callbacks.on_heartbeat = [&](const dds::ObservedHeartbeat& h) { printer.heartbeat(h); };
  }
  dds::DomainObserver observer(options, std::move(callbacks));
  StartNotice notice;
  notice.json.field("event", "watching").field("domain", common.domain);
  notice.text = "watching domain " + std::to_string(common.domain) + " (Ctrl-C to stop)";
  announce(context, common.json, notice);
  if (duration) {
    context.shutdown.wait_for(*duration);
  } else {
    while (!context.shutdown.wait_for(std::chrono::hours(24))) {
    }
  }
  return ExitOk;
}

}  // namespace

Command watch_command() {
  CommandSpec spec;
  spec.name = "watch";
  spec.summary = "live view of every device, interface and data item on a domain";
  spec.description =
      "Prints each device announcement and every state transition of every interface\n"
      "data item (REQUEST/RESPONSE of each service, INTERFACE_STATE, DOOR_STATE,\n"
      "CHUCK_STATE) as it arrives: previous -> new value, the writer's source time, the\n"
      "local reception time and the latency between them. Devices write changes only\n"
      "and a heartbeat per timing group: when a device's heartbeats stop (crash, cable\n"
      "pull) its items are shown as UNAVAILABLE, and with their last value again when\n"
      "the heartbeats resume. --heartbeats also prints every heartbeat.\n"
      "Runs until Ctrl-C / SIGTERM or --duration.";
  spec.options = {
      {"duration", "TIME", "stop after this long (e.g. 30s, 500ms, 2m)", "until Ctrl-C"},
      {"device", "UUID", "only this device (repeatable)", "all devices", false, true},
      {"heartbeats", "", "also print every device heartbeat (10/s per device by default)", ""},
  };
  add_observer_options(spec);
  add_common_options(spec);
  spec.examples =
      "  mtc watch --domain 5\n"
      "  mtc watch --domain 5 --device robot-1 --duration 30s\n"
      "  mtc watch --domain 5 --json | jq 'select(.event==\"value\")'\n";
  return {spec, &run_watch};
}

}  // namespace mtc::cli
