// Text and JSON renderings of what a DomainObserver reports, shared by
// `mtc watch` and `mtc list`.
#pragma once

#include <string>
#include <string_view>

#include "equipment_options.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "output.hpp"

namespace mtc::cli {

std::string_view to_string(dds::ItemKind kind);
// Observer options from the common and observer flags.
dds::DomainObserverOptions observer_options(const CommonOptions& common, const ParsedArgs& args);
// "MATERIAL_LOAD REQUEST", "INTERFACE_STATE", "DOOR_STATE" ...
std::string item_label(const dds::ObservedValue& v);
// JSON array of a device's interfaces with their data items.
std::string interfaces_json(const dds::ObservedDevice& device);
// One line per interface: "mh (MATERIAL_HANDLER): MATERIAL_LOAD REQUEST, ..."
std::string interfaces_text(const dds::ObservedDevice& device, std::string_view indent);

}  // namespace mtc::cli
