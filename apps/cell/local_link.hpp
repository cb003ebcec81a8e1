// An in-memory Link: both sides of every service live in one LocalBus and
// each change of one side is shown to the other at once, through the same
// core state machines the DDS runtime drives. It lets the station scripts be
// exercised in milliseconds without DDS (`mtc-cell --local`, the logic test);
// the real cell runs over the DDS Equipment runtime.
#pragma once

#include <memory>

#include "mtc/core/profile.hpp"
#include "ports.hpp"

namespace mtc::cell {

class LocalBus : public Link {
 public:
  explicit LocalBus(const core::MachineOptions& options);
  ~LocalBus() override;
  LocalBus(const LocalBus&) = delete;
  LocalBus& operator=(const LocalBus&) = delete;

  RequestPort& requester(core::Service service) override;
  ResponsePort& responder(core::Service service) override;
  std::optional<core::Service> wait_job(std::initializer_list<core::Service> services,
                                        Millis timeout) override;
  void set_door(core::DoorState state) override;
  void set_chuck(core::ChuckState state) override;
  bool holds(core::Service service) override;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::cell
