// `mtc watch`: a live view of every device, interface and data item on a
// domain, one line per transition with source time, reception time and the
// latency between them. Items whose writer lost liveliness turn UNAVAILABLE.
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
    const bool repeat = previous == text && v.heartbeat_count > 0;
    if (repeat && !heartbeats_) {
      return;
    }
    const std::int64_t latency = v.reception_time_ns - v.source_time_ns;
    if (json_) {
      JsonLine line;
      line.field("event", repeat ? "heartbeat" : "value")
          .field("device", v.device_uuid)
          .field("interface", v.interface_id)
          .field("item", v.data_item_id)
          .field("kind", to_string(v.kind()))
          .field("label", item_label(v))
          .field("previous", previous)
          .field("value", text)
          .field("sequence", v.sequence_number)
          .field("heartbeat", v.heartbeat_count)
          .field("source_time_ns", v.source_time_ns)
          .field("reception_time_ns", v.reception_time_ns)
          .field("latency_ms", static_cast<double>(latency) / 1e6);
      out_.line(line.str());
      return;
    }
    out_.line(format_utc(v.reception_time_ns) + "  " + v.device_uuid + "/" + v.interface_id + "  " +
              item_label(v) + "  " + previous + " -> " + text + "  (source " +
              format_utc(v.source_time_ns) + ", latency " + format_ms(latency) + ", seq " +
              std::to_string(v.sequence_number) + (repeat ? ", heartbeat" : "") + ")");
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
        text += "  " + device + "/" + label + "  " + previous;
        text += " -> UNAVAILABLE  (writer lost: liveliness or disposal)";
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
      "local reception time and the latency between them. When a writer stops\n"
      "asserting liveliness (crash, cable pull) its items are shown as UNAVAILABLE.\n"
      "Periodic heartbeat repeats of an unchanged value are hidden unless --heartbeats.\n"
      "Runs until Ctrl-C / SIGTERM or --duration.";
  spec.options = {
      {"duration", "TIME", "stop after this long (e.g. 30s, 500ms, 2m)", "until Ctrl-C"},
      {"device", "UUID", "only this device (repeatable)", "all devices", false, true},
      {"heartbeats", "", "also print heartbeat repeats of unchanged values", ""},
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
