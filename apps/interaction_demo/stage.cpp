#include "stage.hpp"

#include <chrono>

namespace mtc::demo {

using core::InteractionState;
using core::Notice;
using core::Role;
using core::StepResult;

Stage::Stage(core::Profile profile, const core::MachineOptions& requester_options,
             const core::MachineOptions& responder_options)
    : profile_(profile),
      requester_(core::Service::MaterialLoad, requester_options),
      responder_(core::Service::MaterialLoad, responder_options) {
  // Both sides learn each other's initial value; nothing to print.
  requester_.on_counterpart(responder_.state(), now_);
  responder_.on_counterpart(requester_.state(), now_);
}

void Stage::show(const StepResult& r) {
  if (r.notice == Notice::None && !r.changed()) return;
  const double t = std::chrono::duration<double>(now_ - core::TimePoint{}).count();
  const bool cnc = r.role == Role::Requester;
  std::string what{to_string(r.notice)};
  if (r.reason != core::Reason::None) {
    what += ": ";
    what += describe(r.reason);
  }
  const auto item = to_string(cnc ? core::SubType::Request : core::SubType::Response);
  std::printf("  t=%6.2fs  %-12s %-9s %-16s %-9s -> %-9s %s\n", t, cnc ? "cnc" : "robot",
              std::string(item).c_str(), std::string(to_string(r.event)).c_str(),
              std::string(to_string(r.previous)).c_str(), std::string(to_string(r.current)).c_str(),
              what.c_str());
}

void Stage::say(const std::string& text) {
  const double t = std::chrono::duration<double>(now_ - core::TimePoint{}).count();
  std::printf("  t=%6.2fs  -- %s\n", t, text.c_str());
}

void Stage::tick() {
  while (requester_.next_deadline() <= now_) show(requester_.on_tick(now_));
  while (responder_.next_deadline() <= now_) show(responder_.on_tick(now_));
}

void Stage::advance(std::chrono::milliseconds d) {
  // Step through deadlines in order so time stamps are exact.
  const core::TimePoint until = now_ + d;
  for (;;) {
    const core::TimePoint next = std::min(requester_.next_deadline(), responder_.next_deadline());
    if (next > until) break;
    now_ = std::max(now_, next);
    tick();
  }
  now_ = until;
}

void Stage::to_robot() {
  show(responder_.on_counterpart(requester_.state(), now_));
  tick();
}

void Stage::to_cnc() {
  show(requester_.on_counterpart(responder_.state(), now_));
  tick();
}

void Stage::settle() {
  for (int i = 0; i < 8; ++i) {
    const auto a = requester_.state();
    const auto b = responder_.state();
    to_robot();
    to_cnc();
    if (a == requester_.state() && b == responder_.state() &&
        requester_.counterpart() == responder_.state() &&
        responder_.counterpart() == requester_.state()) {
      return;
    }
  }
}

void Stage::recover_both() {
  for (int i = 0; i < 6; ++i) {
    settle();
    const bool cnc_fail = requester_.state() == InteractionState::Fail;
    const bool robot_fail = responder_.state() == InteractionState::Fail;
    if (!cnc_fail && !robot_fail) return;
    advance(std::chrono::milliseconds(500));  // resetting partial actions
    if (cnc_fail && requester_.fail_acknowledged()) {
      show(requester_.recover(InteractionState::Ready, now_));
    }
    if (robot_fail && responder_.fail_acknowledged()) {
      show(responder_.recover(InteractionState::Ready, now_));
    }
  }
  settle();
}

void Stage::finish() {
  std::printf("  final: cnc REQUEST %s, robot RESPONSE %s\n",
              std::string(to_string(requester_.state())).c_str(),
              std::string(to_string(responder_.state())).c_str());
}

void Stage::lose_link() {
  show(requester_.on_counterpart_lost(now_));
  show(responder_.on_counterpart_lost(now_));
}

}  // namespace mtc::demo
