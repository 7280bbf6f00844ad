// Sha256: the FIPS 180-2 test vectors, whole and fed in pieces, and sha256_hex in one call.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "core/sha256.hpp"

namespace lidarscout {
namespace {

std::string digest(std::string_view text, std::size_t piece) {
    Sha256 sha;
    for (std::size_t at = 0; at < text.size(); at += piece) {
        const auto part = text.substr(at, piece);
        sha.update({reinterpret_cast<const std::uint8_t*>(part.data()), part.size()});
    }
    return sha.hex_digest();
}

TEST(Sha256, KnownVectors) {
    EXPECT_EQ(digest("", 1), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(digest("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    for (std::size_t piece : {1u, 7u, 64u, 1000u}) {
        EXPECT_EQ(digest(two_blocks, piece), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    }
}

TEST(Sha256, OneCall) {
    const std::string abc = "abc";
    EXPECT_EQ(sha256_hex({reinterpret_cast<const std::uint8_t*>(abc.data()), abc.size()}),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256_hex({}), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

}  // namespace
}  // namespace lidarscout
