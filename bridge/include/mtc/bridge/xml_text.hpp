// Text fit for an XML 1.0 document. Strings from outside (a request URL, a
// device name announced over DDS, a Devices file) may hold bytes that are not
// UTF-8 or code points XML forbids (controls other than TAB, LF and CR,
// surrogates, U+FFFE, U+FFFF); pugixml copies them into the output as they
// are, and the document is no longer XML. Plain functions over bytes, so a
// fuzz target can call them.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace mtc::bridge {

// Offset of the first byte of `text` that starts an invalid UTF-8 sequence
// or a code point outside XML's Char production; npos when every byte is fit.
std::size_t find_unfit_xml_char(std::string_view text) noexcept;

// `text` with each unfit byte sequence replaced by U+FFFD (the replacement
// character), so that nothing is silently dropped; fit text is returned as is.
std::string make_xml_safe(std::string_view text);

// True when `text` is a name an MTConnect DataItem type may have: an
// uppercase word with underscores and digits ("MATERIAL_LOAD"), optionally
// behind a vendor prefix ("x:BAR_FEED"). Such a type gives a valid element
// name (element_name_for_type).
bool is_data_item_type(std::string_view text) noexcept;

}  // namespace mtc::bridge
