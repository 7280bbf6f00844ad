// Bounds-checked little-endian reader over a byte buffer taken from a file. Every read past
// the end throws lidarscout::Error with the file name and the absolute file offset.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>

#include "core/error.hpp"

namespace lidarscout::io {

class ByteReader {
public:
    // `base` is the file offset of data[0]; `file` is used in error messages.
    ByteReader(std::span<const std::uint8_t> data, std::uint64_t base, std::string file)
        : data_(data), base_(base), file_(std::move(file)) {}

    std::size_t position() const noexcept { return pos_; }
    std::uint64_t file_offset() const noexcept { return base_ + pos_; }
    std::size_t remaining() const noexcept { return data_.size() - pos_; }
    const std::string& file() const noexcept { return file_; }

    void seek(std::size_t pos, const char* what = "field") {
        if (pos > data_.size()) fail(what, pos - pos_);
        pos_ = pos;
    }
    void skip(std::size_t n, const char* what = "field") { take(n, what); }

    std::span<const std::uint8_t> bytes(std::size_t n, const char* what = "field") { return take(n, what); }
    std::string fixed_string(std::size_t n, const char* what = "string");

    std::uint8_t u8(const char* what = "field") { return take(1, what)[0]; }
    std::uint16_t u16(const char* what = "field") { return get<std::uint16_t>(what); }
    std::uint32_t u32(const char* what = "field") { return get<std::uint32_t>(what); }
    std::uint64_t u64(const char* what = "field") { return get<std::uint64_t>(what); }
    std::int8_t i8(const char* what = "field") { return static_cast<std::int8_t>(u8(what)); }
    std::int16_t i16(const char* what = "field") { return get<std::int16_t>(what); }
    std::int32_t i32(const char* what = "field") { return get<std::int32_t>(what); }
    std::int64_t i64(const char* what = "field") { return get<std::int64_t>(what); }
    double f64(const char* what = "field") { return get<double>(what); }

    [[noreturn]] void fail(const char* what, std::size_t needed) const;

private:
    std::span<const std::uint8_t> take(std::size_t n, const char* what) {
        if (n > remaining()) fail(what, n);
        auto s = data_.subspan(pos_, n);
        pos_ += n;
        return s;
    }
    template <typename T>
    T get(const char* what) {
        T v;  // host is little-endian (x86_64 / aarch64), as the LAS format
        std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
        return v;
    }

    std::span<const std::uint8_t> data_;
    std::uint64_t base_;
    std::string file_;
    std::size_t pos_ = 0;
};

// Little-endian loads from raw memory (no bounds checks; callers check sizes once).
template <typename T>
inline T load_le(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

}  // namespace lidarscout::io
