#include "mtc/core/observation.hpp"

namespace mtc::core {

std::string to_string(const ObservedState& state) {
  if (!state.in_vocabulary()) return "INVALID(" + std::to_string(state.raw()) + ")";
  switch (state.kind()) {
    case ItemKind::Interaction:
      return std::string(to_string(*state.interaction()));
    case ItemKind::InterfaceState:
      return std::string(to_string(*state.interface_state()));
    case ItemKind::DoorState:
      return std::string(to_string(*state.door()));
    case ItemKind::ChuckState:
      return std::string(to_string(*state.chuck()));
  }
  return "INVALID(" + std::to_string(state.raw()) + ")";
}

}  // namespace mtc::core
