// `mtc list`: the devices and interfaces announced on a domain, with the
// latest value of every data item, as a table or JSON.
#include <algorithm>
#include <map>
#include <mutex>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "observed_format.hpp"

namespace mtc::cli {
namespace {

// Latest value per (device, data item), fed from the observer thread.
class LatestValues {
 public:
  void set(const std::string& device, const std::string& item, const std::string& value) {
    std::lock_guard<std::mutex> lock(mutex_);
    values_[device + "\n" + item] = value;
  }
  bool has(const std::string& device, const std::string& item) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return values_.count(device + "\n" + item) != 0;
  }
  std::string get(const std::string& device, const std::string& item) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = values_.find(device + "\n" + item);
    return it == values_.end() ? "-" : it->second;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::string> values_;
};

// Enough devices announced, and every announced item has a value.
bool complete(const std::vector<dds::ObservedDevice>& devices, std::size_t expect,
              const LatestValues& latest) {
  if (devices.size() < expect) {
    return false;
  }
  for (const auto& d : devices) {
    for (const auto& itf : d.interfaces) {
      for (const auto& di : itf.data_items) {
        if (!latest.has(d.device_uuid, di.id)) {
          return false;
        }
      }
    }
  }
  return true;
}

void print_json(Output& out, const std::vector<dds::ObservedDevice>& devices,
                const LatestValues& latest) {
  for (const auto& d : devices) {
    std::string values = "{";
    const char* sep = "";
    for (const auto& itf : d.interfaces) {
      for (const auto& di : itf.data_items) {
        values += sep + json_quote(di.id) + ":" + json_quote(latest.get(d.device_uuid, di.id));
        sep = ",";
      }
    }
    JsonLine line;
    line.field("event", "device").field("device", d.device_uuid).field("name", d.name);
    line.raw_field("interfaces", interfaces_json(d)).raw_field("values", values + "}");
    out.line(line.str());
  }
}

void print_table(Output& out, const std::vector<dds::ObservedDevice>& devices,
                 const LatestValues& latest) {
  std::ostringstream table;
  table
      << "DEVICE           INTERFACE        TYPE               DATA ITEM                  VALUE\n";
  auto pad = [](const std::string& s, std::size_t w) {
    return s.size() >= w ? s + " " : s + std::string(w - s.size(), ' ');
  };
  for (const auto& d : devices) {
    if (d.interfaces.empty()) {
      table << pad(d.device_uuid, 17) << "(no interfaces)\n";
    }
    for (const auto& itf : d.interfaces) {
      for (const auto& di : itf.data_items) {
        const std::string label = di.type + (di.sub_type.empty() ? "" : " " + di.sub_type);
        table << pad(d.device_uuid, 17) << pad(itf.id, 17)
              << pad(std::string(core::to_string(itf.type)), 19) << pad(label, 27)
              << latest.get(d.device_uuid, di.id) << "\n";
      }
    }
  }
  table << devices.size() << " device(s)";
  out.line(table.str());
}

int run_list(const ParsedArgs& args, Context& context) {
  const CommonOptions common = parse_common_options(args);
  const std::chrono::milliseconds wait(
      to_int("wait-ms", args.value_or("wait-ms", "2000"), 0, 3600000));
  std::size_t expect = 0;
  if (auto e = args.value("expect-devices")) {
    expect = static_cast<std::size_t>(to_int("expect-devices", *e, 1, 100000));
  }
  LatestValues latest;
  const dds::DomainObserverOptions options = observer_options(common, args);
  dds::DomainObserverCallbacks callbacks;
  callbacks.on_device = [&](const dds::ObservedDevice&) { context.shutdown.poke(); };
  callbacks.on_value = [&](const dds::ObservedValue& v) {
    latest.set(v.device_uuid, v.data_item_id, core::to_string(v.state));
    context.shutdown.poke();
  };
  callbacks.on_items_lost = [&](const std::string& dev, const std::vector<std::string>& items) {
    for (const auto& item : items) {
      latest.set(dev, item, "UNAVAILABLE");
    }
  };
  dds::DomainObserver observer(options, std::move(callbacks));
  // Discovery has no "done" event: wait the full time, or until the
  // expected number of devices has announced itself.
  const auto deadline = std::chrono::steady_clock::now() + wait;
  while (!context.shutdown.wait_until(deadline) && std::chrono::steady_clock::now() < deadline) {
    if (expect > 0 && complete(observer.devices(), expect, latest)) {
      break;
    }
  }
  auto devices = observer.devices();
  std::sort(devices.begin(), devices.end(),
            [](const auto& a, const auto& b) { return a.device_uuid < b.device_uuid; });
  if (common.json) {
    print_json(context.out, devices, latest);
  } else {
    print_table(context.out, devices, latest);
  }
  if (context.shutdown.requested()) {
    return ExitInterrupted;
  }
  return expect > 0 && devices.size() < expect ? ExitTimeout : ExitOk;
}

}  // namespace

Command list_command() {
  CommandSpec spec;
  spec.name = "list";
  spec.summary = "devices and interfaces discovered on a domain";
  spec.description =
      "Listens for --wait-ms for device announcements, then prints every device, its\n"
      "interfaces and their data items with the latest value of each. With\n"
      "--expect-devices N it returns as soon as N devices and a value of each of their\n"
      "items are known (exit 4 if fewer devices appear within --wait-ms).";
  spec.options = {
      {"wait-ms", "MS", "how long to listen for announcements", "2000"},
      {"expect-devices", "N", "return as soon as N devices are known", ""},
      {"device", "UUID", "only this device (repeatable)", "all devices", false, true},
  };
  add_observer_options(spec);
  add_common_options(spec);
  spec.examples =
      "  mtc list --domain 5\n"
      "  mtc list --domain 5 --wait-ms 500 --json\n"
      "  mtc list --domain 5 --expect-devices 2 --wait-ms 10000   # in scripts\n";
  return {spec, &run_list};
}

}  // namespace mtc::cli
