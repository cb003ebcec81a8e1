// Internal: map keys made of strings that are looked up for every sample
// received. Their comparator also takes keys whose strings are views, so
// finding a key that is already there allocates nothing; building the
// std::string key for the lookup cost one or two allocations per value.
#pragma once

#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

namespace mtc::dds::detail {

// A string as a view; anything else as it is.
template <typename T>
decltype(auto) viewed(const T& part) noexcept {
  if constexpr (std::is_convertible_v<const T&, std::string_view>) {
    return std::string_view(part);
  } else {
    return (part);
  }
}

// A key type that is a struct says what it is made of with parts() (a
// std::tie of its members, in the order keys sort by).
template <typename Key, typename = void>
struct HasParts : std::false_type {};
template <typename Key>
struct HasParts<Key, std::void_t<decltype(std::declval<const Key&>().parts())>> : std::true_type {};

// Orders pairs, tuples and keys with parts() element by element, strings by
// their characters, whether held or viewed: std::pair<Handle, std::string>
// against std::pair<Handle, std::string_view>.
struct ViewLess {
  using is_transparent = void;  // NOLINT(readability-identifier-naming): the standard name

  template <typename A, typename B>
  bool operator()(const A& a, const B& b) const noexcept {
    return as_views(a) < as_views(b);
  }

 private:
  template <typename Key>
  static auto as_views(const Key& key) noexcept {
    if constexpr (HasParts<Key>::value) {
      return as_views(key.parts());
    } else {
      return std::apply(
          [](const auto&... part) {
            return std::tuple<decltype(viewed(part))...>(viewed(part)...);
          },
          key);
    }
  }
};

// The value under `view`, added (with the key make_key() builds) if absent.
template <typename Map, typename View, typename MakeKey>
typename Map::mapped_type& find_or_add(Map& map, const View& view, MakeKey&& make_key) {
  auto it = map.find(view);
  if (it == map.end()) {
    it = map.emplace(std::forward<MakeKey>(make_key)(), typename Map::mapped_type{}).first;
  }
  return it->second;
}

}  // namespace mtc::dds::detail
