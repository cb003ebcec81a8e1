// What runs for every value received must not allocate once the value's
// item is known: an inline step of the executor, and the lookups of the peer
// checks and the peer groups. Each allocation is a malloc and a free on the
// middleware's thread, in the middle of a transit; a handshake made about
// 90 of them before (docs/benchmarks.md, "Allocations per handshake").
//
// Counted on the counting thread only, between start and stop: through the
// sanitizer's allocation hook in a sanitizer build (its runtime owns
// operator new), else by replacing the global operator new.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <map>
#include <new>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "executor.hpp"
#include "lookup_keys.hpp"
#include "peer_checks.hpp"
#include "peer_groups.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define MTC_TEST_SANITIZER_HOOK 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MTC_TEST_SANITIZER_HOOK 1
#endif

namespace {

thread_local bool t_counting = false;
thread_local std::size_t t_allocations = 0;

}  // namespace

#ifdef MTC_TEST_SANITIZER_HOOK
#include <sanitizer/allocator_interface.h>

namespace {

void on_allocation(const volatile void* /*ptr*/, std::size_t /*size*/) {
  if (t_counting) ++t_allocations;
}
void on_free(const volatile void* /*ptr*/) {}
const int kHookInstalled = __sanitizer_install_malloc_and_free_hooks(on_allocation, on_free);

}  // namespace
#else
namespace {

void* counted_allocation(std::size_t size) {
  if (t_counting) ++t_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t size) {
  return counted_allocation(size);
}
void* operator new[](std::size_t size) {
  return counted_allocation(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
#endif

namespace {

using mtc::core::ObservedValue;
using mtc::dds::detail::Executor;
using mtc::dds::detail::Handle;
using mtc::dds::detail::PeerGroupKey;
using mtc::dds::detail::PeerGroupKeyView;
using mtc::dds::detail::ViewLess;

// The allocations fn() makes on this thread.
template <typename Fn>
std::size_t allocations_of(Fn&& fn) {
  t_allocations = 0;
  t_counting = true;
  fn();
  t_counting = false;
  return t_allocations;
}

// Longer than any short-string buffer: a copy of such a string allocates.
const std::string kDevice = "a-machine-tool-device-uuid-0001";
const std::string kItem = "material_load_request_state_01";

ObservedValue interface_state(std::uint64_t sequence) {
  ObservedValue v;
  v.device_uuid = kDevice;
  v.data_item_id = kItem;
  v.interface_id = "material-load-interface-0001";
  v.state = mtc::core::InterfaceState::Enabled;
  v.sequence_number = sequence;
  v.heartbeat_group = 1;
  return v;
}

TEST(HotPathAllocations, TheCounterSeesAnAllocation) {
  // Without this the zeros below would prove nothing.
#ifdef MTC_TEST_SANITIZER_HOOK
  ASSERT_NE(kHookInstalled, 0) << "the sanitizer took no allocation hook";
#endif
  EXPECT_GE(allocations_of([] { std::string copy = kDevice; }), 1U);
}

TEST(HotPathAllocations, AnInlineStepAllocatesNothing) {
  std::size_t steps = 0;
  Executor ex;
  ex.set_inline_steps(true);
  ex.start([] { return Executor::Clock::time_point::max(); }, [](Executor::Clock::time_point) {});
  // A step as big as one holding a DDS event: a Task would keep it on the heap.
  std::array<char, 256> event{};
  const auto step = [&steps, event] { steps += event[0] == 0 ? 1 : 0; };
  ex.dispatch(step);
  EXPECT_EQ(allocations_of([&] {
              for (int i = 0; i < 100; ++i) ex.dispatch(step);
            }),
            0U);
  EXPECT_EQ(steps, 101U);  // every one stepped inline, before dispatch returned
}

TEST(HotPathAllocations, AStepThatQueuesATaskAllocatesNothingOnceWarm) {
  // A task queued by a step (complete() from on_request) runs before the
  // step's thread lets go; the queue's storage is kept from one step to
  // the next.
  std::vector<int> order;
  order.reserve(1000);
  Executor ex;
  ex.set_inline_steps(true);
  ex.start([] { return Executor::Clock::time_point::max(); }, [](Executor::Clock::time_point) {});
  const auto step = [&] {
    order.push_back(1);
    ex.post([&order] { order.push_back(2); });  // fits a std::function's own buffer
  };
  ex.dispatch(step);
  ex.dispatch(step);
  EXPECT_EQ(allocations_of([&] {
              for (int i = 0; i < 100; ++i) ex.dispatch(step);
            }),
            0U);
  ASSERT_EQ(order.size(), 204U);
  for (std::size_t i = 0; i < order.size(); ++i) {
    EXPECT_EQ(order[i], i % 2 == 0 ? 1 : 2) << "at " << i;
  }
}

TEST(HotPathAllocations, ViewLessOrdersAsThePairsDoAndFindsByView) {
  const std::vector<std::pair<std::string, std::string>> keys{
      {"", ""},           {"", "b"},  {"a", ""},        {"a", "a"},
      {"ab", ""},         {"a", "b"}, {kDevice, kItem}, {kDevice, kItem + "x"},
      {kDevice + "x", ""}};
  std::map<std::pair<std::string, std::string>, int> plain;
  std::map<std::pair<std::string, std::string>, int, ViewLess> viewed;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    plain.emplace(keys[i], static_cast<int>(i));
    viewed.emplace(keys[i], static_cast<int>(i));
  }
  ASSERT_EQ(viewed.size(), plain.size());
  auto p = plain.begin();
  for (const auto& [key, index] : viewed) {
    EXPECT_EQ(key, p->first);
    EXPECT_EQ(index, p->second);
    ++p;
  }
  for (const auto& key : keys) {
    const std::pair<std::string_view, std::string_view> view(key.first, key.second);
    std::map<std::pair<std::string, std::string>, int, ViewLess>::iterator found;
    EXPECT_EQ(allocations_of([&] { found = viewed.find(view); }), 0U);
    ASSERT_NE(found, viewed.end());
    EXPECT_EQ(found->first, key);
  }
  EXPECT_EQ(viewed.find(std::pair<std::string_view, std::string_view>("zz", "")), viewed.end());
}

TEST(HotPathAllocations, FindOrAddAddsOnceThenOnlyFinds) {
  std::map<std::pair<std::string, std::string>, int, ViewLess> m;
  const std::pair<std::string_view, std::string_view> view(kDevice, kItem);
  const auto make = [] { return std::pair(kDevice, kItem); };
  mtc::dds::detail::find_or_add(m, view, make) = 7;
  int* again = nullptr;
  EXPECT_EQ(allocations_of([&] { again = &mtc::dds::detail::find_or_add(m, view, make); }), 0U);
  EXPECT_EQ(*again, 7);
  EXPECT_EQ(m.size(), 1U);
}

TEST(HotPathAllocations, ViewLessOrdersPeerGroupKeysAsTheirOwnLessDoes) {
  std::vector<PeerGroupKey> keys;
  for (const char* device : {"", "a", "ab", "b"}) {
    for (const std::uint32_t group : {0U, 1U}) {
      for (const int p : {0, 1}) {
        PeerGroupKey k{device, group, {}};
        k.participant[0] = static_cast<std::uint8_t>(p);
        keys.push_back(k);
      }
    }
  }
  const ViewLess less;
  for (const auto& a : keys) {
    for (const auto& b : keys) {
      EXPECT_EQ(less(a, b), a < b) << a.device << a.group << " " << b.device << b.group;
      const PeerGroupKeyView view{a.device, a.group, a.participant};
      EXPECT_EQ(less(view, b), a < b);
      EXPECT_EQ(less(b, view), b < a);
    }
  }
}

TEST(HotPathAllocations, AValueOfAKnownItemCostsThePeerChecksAndGroupsNothing) {
  mtc::dds::detail::PeerChecks checks;
  mtc::dds::detail::PeerGroups groups;
  const Handle writer{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0, 0, 1, 2};
  const auto topic = mtc::dds::detail::TopicKind::InterfaceState;
  const auto first = interface_state(1);
  ASSERT_TRUE(checks.check(0, writer, first).use);
  groups.on_value(writer, topic, first);
  const auto next = interface_state(2);
  mtc::dds::detail::PeerChecks::Verdict verdict;
  EXPECT_EQ(allocations_of([&] {
              verdict = checks.check(0, writer, next);
              groups.on_value(writer, topic, next);
            }),
            0U);
  EXPECT_TRUE(verdict.use);
  EXPECT_FALSE(verdict.report.has_value());
  const auto* group = groups.find(mtc::dds::detail::PeerGroups::key_of(writer, kDevice, 1));
  ASSERT_NE(group, nullptr);
  EXPECT_EQ(group->received[static_cast<std::size_t>(topic)], 2U);
}

}  // namespace
