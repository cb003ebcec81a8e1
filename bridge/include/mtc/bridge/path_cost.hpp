// A bound on what an XPath `path` filter may cost, known before it runs.
//
// pugixml evaluates XPath to the end once it starts: it cannot be timed out
// or interrupted, and an 87-byte request (`count()` nested six deep over
// `//*`) takes minutes. So every expression is analysed first, from its text
// and the shape of the document it will run on: its length, its nesting, the
// functions it calls, and an upper bound on the nodes its evaluation visits
// (each step's axis, the nodes its name test can match, every predicate
// counted once per node it filters, node-set comparisons and conversions).
// An expression over the limits is refused before pugixml sees it, so the
// time any accepted one takes is bounded whatever the model's size
// (docs/bridge.md gives the measured worst case).
//
// Plain functions over strings, so a fuzz target can call them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace mtc::bridge {

struct PathLimits {
  // Characters of the expression (after %-decoding).
  std::size_t max_length = 1024;
  // Parentheses and brackets nested inside each other.
  std::size_t max_nesting = 8;
  // Estimated node visits, including DeviceModel::select's walk collecting
  // the DataItems. mtc-bench-bridge-path-cost measured at most 57 ns of CPU
  // per estimated visit and 21 ms for the slowest accepted path (on a
  // 48,000-node model; under 2 ms up to 4,800 nodes), so the default bounds
  // a request to well under a second on any model.
  double max_visits = 2'000'000;
};

// What the analysis needs of the document the expression runs on.
struct TreeShape {
  std::uint64_t nodes = 1;                // every node (elements, text, ...)
  std::uint64_t elements = 0;             // element nodes
  std::uint64_t attributes = 0;           // attributes of all elements
  std::uint64_t max_children = 0;         // widest element
  std::uint64_t max_attributes = 0;       // most attributes on one element
  std::uint64_t height = 0;               // deepest nesting
  std::uint64_t text_bytes = 0;           // names, values and text of all nodes
  std::uint64_t max_attribute_bytes = 0;  // longest attribute value
  // Elements and attributes per name: a name test matches at most these.
  std::map<std::string, std::uint64_t, std::less<>> element_names;
  std::map<std::string, std::uint64_t, std::less<>> attribute_names;
};

struct PathCost {
  bool accepted = false;
  double visits = 0;  // the estimate (when the text could be analysed)
  std::string error;  // why not, when refused
};

// Analyses `xpath` for a document of `shape`. Refuses what it cannot parse,
// what exceeds `limits`, variables, and functions XPath 1.0 does not define.
PathCost estimate_path_cost(std::string_view xpath, const TreeShape& shape,
                            const PathLimits& limits);

}  // namespace mtc::bridge
