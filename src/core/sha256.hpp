// Incremental SHA-256 (OpenSSL's EVP), e.g. the `points_sha256` checksum of decoded records.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace lidarscout {

class Sha256 {
public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;

    void update(std::span<const std::uint8_t> bytes);
    // Lower-case hex digest; the object cannot be updated afterwards.
    std::string hex_digest();

private:
    struct State;
    std::unique_ptr<State> state_;
};

// The lower-case hex SHA-256 of `bytes` in one call.
std::string sha256_hex(std::span<const std::uint8_t> bytes);

}  // namespace lidarscout
