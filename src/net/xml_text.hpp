// Reading the few values an object store's XML answers hold (S3's ListObjectsV2 pages and
// error bodies): the elements of a tag, in order, and their text with the XML entities
// decoded. Flat documents only: no namespaces prefixes, attributes or CDATA are looked at.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace lidarscout::net {

// Calls `visit` with the raw content of each <tag>...</tag> element of `xml`, in order, until it
// returns false (so that a large document is read without a list of all its elements).
void for_each_xml_element(std::string_view xml, std::string_view tag,
                          const std::function<bool(std::string_view)>& visit);

// The raw content of every <tag>...</tag> element of `xml`, in order (nested tags kept).
std::vector<std::string_view> xml_elements(std::string_view xml, std::string_view tag);

// The decoded text of the first <tag> element ("" when there is none).
std::string xml_text(std::string_view xml, std::string_view tag);

// `text` with &amp; &lt; &gt; &quot; &apos; and numeric references (&#38; &#x26;) decoded.
std::string xml_decode(std::string_view text);

}  // namespace lidarscout::net
