#include "command_session.hpp"

namespace mtc::cli {
namespace {

// Points the shutdown signal's listener at `wake` for the guard's lifetime.
class ShutdownListener {
 public:
  ShutdownListener(ShutdownSignal& shutdown, std::function<void()> wake) : shutdown_(shutdown) {
    shutdown_.set_listener(std::move(wake));
  }
  ~ShutdownListener() { shutdown_.set_listener(nullptr); }
  ShutdownListener(const ShutdownListener&) = delete;
  ShutdownListener& operator=(const ShutdownListener&) = delete;

 private:
  ShutdownSignal& shutdown_;
};

}  // namespace

void announce(Context& context, bool json, const StartNotice& notice) {
  if (json) {
    context.out.line(notice.json.str());
  } else {
    context.err.line(notice.text);
  }
}

int run_with_equipment(const EquipmentConfig& equipment, core::Role role, const StartNotice& notice,
                       Context& context, const EquipmentLoop& loop) {
  EventQueue events;
  const ShutdownListener wake_on_shutdown(context.shutdown, [&events] { events.wake(); });
  EquipmentLink link(equipment, role, events);
  announce(context, equipment.common.json, notice);
  return loop(link, events);
}

}  // namespace mtc::cli
