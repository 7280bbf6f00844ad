// net/xml_text: the elements and decoded text of S3's XML answers (a ListObjectsV2 page, an
// error body), entities included.
#include <gtest/gtest.h>

#include "net/xml_text.hpp"

namespace lidarscout::net {
namespace {

TEST(XmlText, ElementsInOrderAndTheirDecodedText) {
    const std::string xml =
        "<ListBucketResult><Contents><Key>a&amp;b.laz</Key><Size>12</Size></Contents>"
        "<Contents><Key>c&lt;&#100;&#x65;&gt;.las</Key><Size>3</Size></Contents>"
        "<IsTruncated>true</IsTruncated></ListBucketResult>";
    const auto contents = xml_elements(xml, "Contents");
    ASSERT_EQ(contents.size(), 2u);
    EXPECT_EQ(xml_text(contents[0], "Key"), "a&b.laz");
    EXPECT_EQ(xml_text(contents[1], "Key"), "c<de>.las");
    EXPECT_EQ(xml_text(contents[1], "Size"), "3");
    EXPECT_EQ(xml_text(xml, "IsTruncated"), "true");
    EXPECT_EQ(xml_text(xml, "NextContinuationToken"), "");
}

TEST(XmlText, UnknownOrBrokenEntitiesStayAsWritten) {
    EXPECT_EQ(xml_decode("a &bogus; b & c &#xZZ; &quot;q&apos;"), "a &bogus; b & c &#xZZ; \"q'");
    EXPECT_EQ(xml_decode("&#233;"), "\xC3\xA9");
    EXPECT_TRUE(xml_elements("<Key>no end", "Key").empty());
}

}  // namespace
}  // namespace lidarscout::net
