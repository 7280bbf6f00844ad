// Benchmark: two ways of decoding LAZ's arithmetic coding that the decoder does not take, measured
// against it on a synthetic source (issue 32's evidence; nothing here is used by the
// library). The source: 16 streams of N symbols each, coded by laz::ArithmeticEncoder under six
// adaptive models per stream in turn, of 33, 256, 33, 256, 17 and 64 symbols (the sizes of
// LAZ's corrector classes, positions and bytes, intensity classes and change masks), with
// geometric symbol frequencies. Three figures, in ns per decoded symbol:
//   library:  laz::ArithmeticDecoder::decode_symbol, the streams one after another;
//   lanes:    the 16 streams stepped together in the lanes of AVX-512 registers (code value,
//             length and position per lane; the quotient by double division, the lookup table,
//             cdf entries and stream bytes by gathers; the models adapted by SymbolModel::record,
//             lane by lane), the way chunks would be decoded side by side;
//   compare:  one stream whose symbol is found as the count of cdf(s) * length <= value over all
//             33 entries at once (two AVX-512 multiplies and compares, no division or lookup),
//             against the library on the same stream of 33-symbol models.
// Every decoded symbol is checked against the source (the lanes in a run before the timed ones).
// Without AVX-512 the two vector figures are not measured (said so).
// Usage: bench_lanes [--symbols N] [--runs N]
#include <fmt/format.h>
#include <immintrin.h>

// GCC 12 warns of uninitialised values inside its own AVX-512 intrinsics (_mm512_undefined_*).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"

using namespace lidarscout;
using laz::SymbolModel;

namespace {

constexpr int kLanes = 16;
constexpr int kSlots = 6;
constexpr std::uint32_t kAlphabets[kSlots] = {33, 256, 33, 256, 17, 64};
constexpr std::size_t kPadding = 16;  // zero bytes after each stream: gathers read 4 bytes at a time

// Entry points compiled for AVX-512 (called only when the CPU has it), and the helpers inlined into them.
#define LIDARSCOUT_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,avx512cd")))
#define LIDARSCOUT_AVX512_INLINE [[gnu::always_inline]] inline LIDARSCOUT_AVX512

bool has_avx512() {
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512cd");
}

// One stream's models, in their start state.
std::vector<std::unique_ptr<SymbolModel>> fresh_models(std::span<const std::uint32_t> alphabets) {
    std::vector<std::unique_ptr<SymbolModel>> models;
    for (const std::uint32_t a : alphabets) models.push_back(std::make_unique<SymbolModel>(a));
    return models;
}

struct Source {
    std::vector<std::vector<std::uint32_t>> symbols;  // per stream
    std::vector<std::vector<std::uint8_t>> bytes;     // per stream, padded
};

// `streams` streams of `n` symbols under models of `alphabets` in turn.
Source make_source(int streams, int n, std::span<const std::uint32_t> alphabets) {
    Source src{std::vector<std::vector<std::uint32_t>>(streams), std::vector<std::vector<std::uint8_t>>(streams)};
    for (int l = 0; l < streams; ++l) {
        std::mt19937 rng(7 * l + 1);
        std::uniform_real_distribution<double> uniform(1e-9, 1.0);
        auto models = fresh_models(alphabets);
        laz::ArithmeticEncoder enc;
        enc.start(src.bytes[l]);
        for (int j = 0; j < n; ++j) {
            const std::size_t slot = j % alphabets.size();
            const std::uint32_t a = alphabets[slot];
            const double scale = a >= 256 ? 12.0 + l : 2.0 + 0.2 * l;
            const auto s = std::min<std::uint32_t>(a - 1, static_cast<std::uint32_t>(-std::log(uniform(rng)) * scale));
            src.symbols[l].push_back(s);
            enc.encode_symbol(*models[slot], s);
        }
        enc.done();
        src.bytes[l].resize(src.bytes[l].size() + kPadding, 0);
    }
    return src;
}

// The code value a stream starts with: its first four bytes, big-endian (as ArithmeticDecoder::start).
std::uint32_t first_code_value(const std::vector<std::uint8_t>& b) {
    return (std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) | (std::uint32_t{b[2]} << 8) | b[3];
}

// Decodes every stream with the library; returns the symbols that differ from the source.
std::uint64_t decode_library(const Source& src, std::span<const std::uint32_t> alphabets) {
    std::uint64_t wrong = 0;
    for (std::size_t l = 0; l < src.bytes.size(); ++l) {
        auto models = fresh_models(alphabets);
        laz::ArithmeticDecoder dec(src.bytes[l]);
        const auto& expected = src.symbols[l];
        for (std::size_t j = 0; j < expected.size(); ++j) {
            wrong += dec.decode_symbol(*models[j % alphabets.size()]) != expected[j];
        }
    }
    return wrong;
}

// ---- 16 streams in AVX-512 lanes

// Per slot, per lane: where a lane's model tables lie (byte offsets from `base`) and its shape.
// Every alphabet of kAlphabets is above 16 symbols, so every model has a lookup table.
struct LaneTables {
    alignas(64) std::int32_t cdf[kSlots][kLanes];
    alignas(64) std::int32_t lookup[kSlots][kLanes];
    alignas(64) std::uint32_t shift[kSlots][kLanes], size[kSlots][kLanes], last[kSlots][kLanes];
};

// Offset of `p` from `base`; the gathers take 32-bit offsets.
std::int32_t offset_from(const void* base, const void* p) {
    const std::ptrdiff_t d = static_cast<const char*>(p) - static_cast<const char*>(base);
    if (d < INT32_MIN || d > INT32_MAX) throw Error("model tables more than 2 GiB apart");
    return static_cast<std::int32_t>(d);
}

LaneTables lane_tables(const std::vector<std::vector<std::unique_ptr<SymbolModel>>>& models, const void* base) {
    LaneTables t{};
    for (int s = 0; s < kSlots; ++s) {
        for (int l = 0; l < kLanes; ++l) {
            const SymbolModel& m = *models[l][s];
            t.cdf[s][l] = offset_from(base, m.cdf_table());
            t.lookup[s][l] = offset_from(base, m.lookup());
            t.shift[s][l] = m.lookup_shift();
            t.size[s][l] = m.lookup_size();
            t.last[s][l] = m.last_symbol();
        }
    }
    return t;
}

// The 16-bit table entries at `byte_offsets` from `base`, one per lane. Each gather reads 4 bytes:
// the entry and the next one, which every table here has (a cdf table's sentinel, a lookup
// table's extra entry).
LIDARSCOUT_AVX512_INLINE __m512i gather16(__m512i byte_offsets, const void* base) {
    return _mm512_and_si512(_mm512_i32gather_epi32(byte_offsets, base, 1), _mm512_set1_epi32(0xFFFF));
}

// floor(value / length) per lane, exact through doubles: a quotient that is not an integer lies at
// least 1 / length below the next one, and rounding a quotient below 2^32 / length to a double moves
// it by less than 2^-21 / length.
LIDARSCOUT_AVX512_INLINE __m512i quotient(__m512i value, __m512i length) {
    const __m512d vl = _mm512_cvtepu32_pd(_mm512_castsi512_si256(value));
    const __m512d vh = _mm512_cvtepu32_pd(_mm512_extracti64x4_epi64(value, 1));
    const __m512d ll = _mm512_cvtepu32_pd(_mm512_castsi512_si256(length));
    const __m512d lh = _mm512_cvtepu32_pd(_mm512_extracti64x4_epi64(length, 1));
    const __m256i ql = _mm512_cvttpd_epu32(_mm512_div_pd(vl, ll));
    const __m256i qh = _mm512_cvttpd_epu32(_mm512_div_pd(vh, lh));
    return _mm512_inserti64x4(_mm512_castsi256_si512(ql), qh, 1);
}

struct LaneState {
    __m512i value, length, pos;
};

// One symbol in every lane under slot `s`'s models: the decoder's search (lookup table, then
// a scan up the cdf while any lane needs it), interval and renormalisation; returns the symbols.
LIDARSCOUT_AVX512_INLINE __m512i lane_symbol(LaneState& st, const LaneTables& t, int s, const void* base,
                                             const std::uint8_t* arena) {
    const __m512i one = _mm512_set1_epi32(1);
    const __m512i full = st.length;
    const __m512i length = _mm512_srli_epi32(st.length, laz::kSymbolProbabilityBits);
    const __m512i q = quotient(st.value, length);
    const __m512i slot = _mm512_min_epu32(_mm512_srlv_epi32(q, _mm512_load_si512(t.shift[s])),
                                          _mm512_load_si512(t.size[s]));
    const __m512i bound = _mm512_min_epu32(q, _mm512_set1_epi32(SymbolModel::kSentinel - 1));
    const __m512i cdf = _mm512_load_si512(t.cdf[s]);
    __m512i symbol = gather16(_mm512_add_epi32(_mm512_load_si512(t.lookup[s]), _mm512_add_epi32(slot, slot)), base);
    __m512i above;
    for (;;) {
        const __m512i next = _mm512_add_epi32(symbol, one);
        above = gather16(_mm512_add_epi32(cdf, _mm512_add_epi32(next, next)), base);
        const __mmask16 step = _mm512_cmple_epu32_mask(above, bound);
        if (!step) break;
        symbol = _mm512_mask_add_epi32(symbol, step, symbol, one);
    }
    const __m512i low = _mm512_mullo_epi32(gather16(_mm512_add_epi32(cdf, _mm512_add_epi32(symbol, symbol)), base),
                                           length);
    const __mmask16 is_last = _mm512_cmpeq_epi32_mask(symbol, _mm512_load_si512(t.last[s]));
    const __m512i high = _mm512_mask_blend_epi32(is_last, _mm512_mullo_epi32(above, length), full);
    const __m512i value = _mm512_sub_epi32(st.value, low);
    const __m512i left = _mm512_sub_epi32(high, low);
    // Renormalise: shift in the whole bytes that bring each length back to at least 2^24.
    const __m512i bytes = _mm512_srli_epi32(_mm512_lzcnt_epi32(left), 3);
    const __m512i bits = _mm512_slli_epi32(bytes, 3);
    const __m512i big_endian = _mm512_set4_epi32(0x0C0D0E0F, 0x08090A0B, 0x04050607, 0x00010203);
    const __m512i word = _mm512_shuffle_epi8(_mm512_i32gather_epi32(st.pos, arena, 1), big_endian);
    st.value = _mm512_or_si512(_mm512_sllv_epi32(value, bits),
                               _mm512_srlv_epi32(word, _mm512_sub_epi32(_mm512_set1_epi32(32), bits)));
    st.pos = _mm512_add_epi32(st.pos, bytes);
    st.length = _mm512_sllv_epi32(left, bits);
    return symbol;
}

// Decodes the 16 streams side by side; `wrong` counts symbols that differ from the source (when
// `check`).
LIDARSCOUT_AVX512 std::uint64_t decode_lanes(const Source& src, bool check) {
    std::vector<std::uint8_t> arena;
    alignas(64) std::uint32_t value[kLanes], pos[kLanes], got[kLanes];
    for (int l = 0; l < kLanes; ++l) {
        const auto& b = src.bytes[l];
        value[l] = first_code_value(b);
        pos[l] = static_cast<std::uint32_t>(arena.size() + 4);
        arena.insert(arena.end(), b.begin(), b.end());
    }
    std::vector<std::vector<std::unique_ptr<SymbolModel>>> models;
    for (int l = 0; l < kLanes; ++l) models.push_back(fresh_models(kAlphabets));
    const void* base = models[0][0]->cdf_table();
    const LaneTables tables = lane_tables(models, base);
    std::vector<SymbolModel*> by_slot(kSlots * kLanes);
    for (int s = 0; s < kSlots; ++s) {
        for (int l = 0; l < kLanes; ++l) by_slot[s * kLanes + l] = models[l][s].get();
    }
    LaneState st{_mm512_load_si512(value), _mm512_set1_epi32(-1), _mm512_load_si512(pos)};
    std::uint64_t wrong = 0;
    const std::size_t n = src.symbols[0].size();
    for (std::size_t j = 0; j < n; ++j) {
        const int s = static_cast<int>(j % kSlots);
        _mm512_store_si512(got, lane_symbol(st, tables, s, base, arena.data()));
        SymbolModel* const* m = by_slot.data() + s * kLanes;
        for (int l = 0; l < kLanes; ++l) m[l]->record(got[l]);
        if (check) {
            for (int l = 0; l < kLanes; ++l) wrong += got[l] != src.symbols[l][j];
        }
    }
    return wrong;
}

// ---- one stream, the symbol found by a vector compare

// Which of the 16 entries at `cdf` have cdf * length <= value.
LIDARSCOUT_AVX512_INLINE __mmask16 count_half(const SymbolModel::Entry* cdf, std::uint32_t value,
                                               std::uint32_t length) {
    const __m512i c = _mm512_cvtepu16_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(cdf)));
    const __m512i capped = _mm512_min_epu32(c, _mm512_set1_epi32(1 << laz::kSymbolProbabilityBits));
    return _mm512_cmple_epu32_mask(_mm512_mullo_epi32(capped, _mm512_set1_epi32(static_cast<int>(length))),
                                   _mm512_set1_epi32(static_cast<int>(value)));
}

// The last symbol s of a 33-symbol model with cdf(s) * length <= value: a count over cdf(1 .. 32)
// (its table holds 34 entries, the sentinel last). The cap at 2^15 only guards the products' 32 bits:
// every entry read is below it, and a length is below 2^17.
LIDARSCOUT_AVX512_INLINE std::uint32_t count_at_or_below(const SymbolModel& m, std::uint32_t value,
                                                         std::uint32_t length) {
    const SymbolModel::Entry* cdf = m.cdf_table();
    const std::uint32_t s = __builtin_popcount(count_half(cdf + 1, value, length)) +
                            __builtin_popcount(count_half(cdf + 17, value, length));
    return std::min(s, m.last_symbol());
}

// The library's arithmetic around a different search (renormalisation as the decoder's).
struct CompareDecoder {
    const std::uint8_t* data;
    std::size_t pos = 4;
    std::uint32_t value, length = 0xFFFFFFFFu;

    explicit CompareDecoder(const std::vector<std::uint8_t>& b)
        : data(b.data()),
          value(first_code_value(b)) {}

    LIDARSCOUT_AVX512_INLINE std::uint32_t decode(SymbolModel& m) {
        const std::uint32_t full = length;
        length >>= laz::kSymbolProbabilityBits;
        const std::uint32_t s = count_at_or_below(m, value, length);
        const std::uint32_t low = m.cdf(s) * length;
        const std::uint32_t high = s == m.last_symbol() ? full : m.cdf(s + 1) * length;
        value -= low;
        length = high - low;
        const auto bytes = static_cast<std::uint32_t>(__builtin_clz(length)) >> 3;
        std::uint32_t next;
        std::memcpy(&next, data + pos, 4);
        const std::uint64_t joined = (std::uint64_t{value} << 32) | __builtin_bswap32(next);
        value = static_cast<std::uint32_t>((joined << (8 * bytes)) >> 32);
        pos += bytes;
        length <<= 8 * bytes;
        m.record(s);
        return s;
    }
};

LIDARSCOUT_AVX512 std::uint64_t decode_compare(const Source& src, std::span<const std::uint32_t> alphabets) {
    auto models = fresh_models(alphabets);
    CompareDecoder dec(src.bytes[0]);
    std::uint64_t wrong = 0;
    const auto& expected = src.symbols[0];
    for (std::size_t j = 0; j < expected.size(); ++j) wrong += dec.decode(*models[j % alphabets.size()]) != expected[j];
    return wrong;
}

// Median ns per symbol of `runs` runs of `decode` over `symbols` symbols; fails on a wrong symbol.
template <class Decode>
double ns_per_symbol(const char* what, int runs, std::size_t symbols, Decode&& decode) {
    std::vector<double> t;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = bench::Clock::now();
        const std::uint64_t wrong = decode();
        t.push_back(bench::seconds_since(t0) * 1e9 / static_cast<double>(symbols));
        if (wrong) throw Error(fmt::format("{} decoded {} symbols wrong", what, wrong));
    }
    return bench::median(t);
}

}  // namespace

int main(int argc, char** argv) {
    return bench::bench_main("bench_lanes", "[--symbols N] [--runs N]", argc, argv, [](int argc, char** argv) {
        int n = 300000, runs = 5;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--symbols" && i + 1 < argc) n = std::stoi(argv[++i]);
            else if (a == "--runs" && i + 1 < argc) runs = std::stoi(argv[++i]);
            else throw Error("unknown argument " + a + "; see --help");
        }
        if (n < kSlots || runs < 1) throw Error("--symbols must be at least 6 and --runs at least 1");
        const Source mixed = make_source(kLanes, n, kAlphabets);
        const std::uint32_t classes[4] = {33, 33, 33, 33};
        const Source single = make_source(1, kLanes * n, classes);
        const std::size_t total = static_cast<std::size_t>(kLanes) * n;
        fmt::print("{} streams of {} symbols under models of 33, 256, 33, 256, 17, 64 symbols in turn\n", kLanes, n);
        const double library =
            ns_per_symbol("the library", runs, total, [&] { return decode_library(mixed, kAlphabets); });
        fmt::print("  library, one stream after another:  {:6.2f} ns/symbol\n", library);
        if (!has_avx512()) {
            fmt::print("  (no AVX-512 on this CPU: the lane and compare figures are not measured)\n");
            return 0;
        }
        if (const std::uint64_t wrong = decode_lanes(mixed, true)) {
            throw Error(fmt::format("the lanes decoded {} symbols wrong", wrong));
        }
        const double lanes = ns_per_symbol("the lanes", runs, total, [&] { return decode_lanes(mixed, false); });
        fmt::print("  16 streams in AVX-512 lanes:         {:6.2f} ns/symbol ({:.2f}x)\n", lanes, library / lanes);
        fmt::print("one stream of {} symbols under four 33-symbol models\n", total);
        const double one = ns_per_symbol("the library", runs, total, [&] { return decode_library(single, classes); });
        const double cmp = ns_per_symbol("the compare", runs, total, [&] { return decode_compare(single, classes); });
        fmt::print("  library (division, lookup table):   {:6.2f} ns/symbol\n", one);
        fmt::print("  count of cdf * length <= value:     {:6.2f} ns/symbol ({:.2f}x)\n", cmp, one / cmp);
        return 0;
    });
}
