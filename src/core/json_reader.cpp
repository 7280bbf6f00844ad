// The bounded JSON reader: an input that pulls chunks from the source and cuts it at the document's
// limit, a parser of our own (nlohmann's SAX parser read a byte at a time through a stream: 1.1 s for
// a 100 MB catalog) that measures each string and number against its limit as its bytes go by and
// hands events to a SAX handler (nlohmann's interface) that builds the kept document and the streamed
// elements, each within its budget, and stops at the depth limit. Where threads parse a streamed array
// (JsonStreaming::threads), the parser cuts its elements apart and ParallelElements parses each on its own
// (a parser over the element's text, as deep as it lies in its document) and hands them on in order.
#include "core/json_reader.hpp"

#include <algorithm>
#include <any>
#include <array>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <variant>

#include "core/error.hpp"
#include "core/text.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lidarscout {
namespace {

using nlohmann::json;

constexpr std::size_t kFirstChunk = 64u << 10, kLastChunk = 1u << 20;  // the chunk grows to the last size

// Where and why reading stopped short of the document's end (a limit, or text that is not JSON).
struct Stop {
    std::uint64_t offset = 0;
    std::string cause;
};

// Thrown inside the reader when the handler refuses an event (a limit it keeps, or the sink stopping):
// what it is, the handler says.
struct Halt {};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string depth_cause(const JsonLimits& limits) {
    return "arrays and objects nested more than the limit of " + std::to_string(limits.max_depth) + " deep";
}

// The bytes a string holds as they are (printable ASCII but the quote and the backslash): 1, else 0.
constexpr std::array<bool, 256> kPlainStringBytes = [] {
    std::array<bool, 256> plain{};
    for (int c = 0x20; c < 0x80; ++c) plain[c] = c != '"' && c != '\\';
    return plain;
}();

// The bytes of a string that neither end it nor start an escape: 1, else 0.
constexpr std::array<bool, 256> kStringBodyBytes = [] {
    std::array<bool, 256> body{};
    for (int c = 0; c < 256; ++c) body[c] = c != '"' && c != '\\';
    return body;
}();

// The bytes that open or close an object, array or string: 1, else 0.
constexpr std::array<bool, 256> kBracketOrQuote = [] {
    std::array<bool, 256> marks{};
    for (const char c : {'"', '{', '}', '[', ']'}) marks[static_cast<unsigned char>(c)] = true;
    return marks;
}();

// What a scan (first_mark) stops at: a byte that ends a string's plain run (kPlainStringBytes: not printable ASCII,
// a quote or a backslash), a quote or backslash (the end of a string's body: kStringBodyBytes), a quote or bracket.
enum class Mark { kPlainStringEnd, kStringBodyEnd, kBracketOrQuote };

// The first byte of [p, end) that is a `M`, or end. 16 bytes at a time where the CPU has SSE2 (every x86-64),
// then one at a time: what a country's catalog costs is mostly such loops over its 250 MB (the reading thread
// cutting its items apart, the threads reading past what an item holds that is not kept).
template <Mark M>
const char* first_mark(const char* p, const char* end) {
#if defined(__SSE2__)
    const auto is = [](__m128i v, char c) { return _mm_cmpeq_epi8(v, _mm_set1_epi8(c)); };
    for (; end - p >= 16; p += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        __m128i marks;
        if constexpr (M == Mark::kBracketOrQuote) {  // ('[' and ']' are '{' and '}' but for bit 0x20)
            const __m128i folded = _mm_or_si128(v, _mm_set1_epi8(0x20));
            marks = _mm_or_si128(is(v, '"'), _mm_or_si128(is(folded, '{'), is(folded, '}')));
        } else {
            marks = _mm_or_si128(is(v, '"'), is(v, '\\'));
            if constexpr (M == Mark::kPlainStringEnd) {  // (signed: below 0x20, or from 0x80)
                marks = _mm_or_si128(marks, _mm_cmplt_epi8(v, _mm_set1_epi8(0x20)));
            }
        }
        if (const auto bits = static_cast<std::uint32_t>(_mm_movemask_epi8(marks))) return p + __builtin_ctz(bits);
    }
#endif
    const auto at = [](char c) {
        const auto b = static_cast<unsigned char>(c);
        if constexpr (M == Mark::kPlainStringEnd) return !kPlainStringBytes[b];
        if constexpr (M == Mark::kStringBodyEnd) return !kStringBodyBytes[b];
        return kBracketOrQuote[b];
    };
    while (p != end && !at(*p)) ++p;
    return p;
}

constexpr bool is_structural_or_space(char c) {
    switch (c) {
        case '[': case ']': case '{': case '}': case ':': case ',': case ' ': case '\t': case '\n': case '\r':
            return true;
        default:
            return false;
    }
}

// The bytes of a number or literal (what lies between structural characters, spaces and strings): 1, else 0.
constexpr std::array<bool, 256> kWordBytes = [] {
    std::array<bool, 256> word{};
    for (int c = 0; c < 256; ++c) word[c] = c != '"' && !is_structural_or_space(static_cast<char>(c));
    return word;
}();

bool is_word_byte(char c) { return kWordBytes[static_cast<unsigned char>(c)]; }

// An element of a streamed array being cut apart by its quotes and brackets (Parser::element_past), chunk by
// chunk: how deep in its brackets the cut is, and of which kinds (bit k: the container k deep, 0 the outermost,
// is an object), whether in a string, after a backslash, or wrong (a bracket closing the wrong kind, more than 64
// deep: then the element is read the usual way, which says what is wrong).
struct ElementCut {
    static constexpr std::size_t kMostDepth = 64;  // (a bit a level in `objects`)
    std::uint64_t objects = 0;
    std::size_t depth = 0;
    bool in_string = false, escaped = false, wrong = false;

    // An opening or closing bracket outside strings; true when the element ends with it (or is wrong).
    bool bracket(char c) {
        if (c == '{' || c == '[') {
            if (depth == kMostDepth) return wrong = true;
            objects = (objects & ~(std::uint64_t{1} << depth)) | (std::uint64_t{c == '{'} << depth);
            ++depth;
            return false;
        }
        if (depth == 0 || c != (((objects >> (depth - 1)) & 1) ? '}' : ']')) return wrong = true;
        return --depth == 0;
    }

    // Past whole 64-byte blocks of [p, end) while inside the element's brackets; where it stopped, `ended` when
    // past the element's last bracket (or at a wrong one). A block's strings are found all at once: its quotes
    // that no odd run of backslashes escapes, their running parity the bytes inside strings; then only its
    // brackets outside them are looked at, one by one. (A backslash outside a string escapes here as inside, where
    // the byte at a time reading ignores it: JSON has none there, and the element's parse refuses it where it is.)
    const char* blocks(const char* p, const char* end, bool& ended) {
#if defined(__SSE2__)
        for (; depth > 0 && end - p >= 64; p += 64) {
            std::uint64_t quote = 0, backslash = 0, brackets = 0;
            for (int k = 0; k < 4; ++k) {
                const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * k));
                const __m128i folded = _mm_or_si128(v, _mm_set1_epi8(0x20));  // ('[' ']' are '{' '}' but for 0x20)
                const auto bits = [&](__m128i m) {
                    return std::uint64_t{static_cast<std::uint16_t>(_mm_movemask_epi8(m))} << (16 * k);
                };
                quote |= bits(_mm_cmpeq_epi8(v, _mm_set1_epi8('"')));
                backslash |= bits(_mm_cmpeq_epi8(v, _mm_set1_epi8('\\')));
                brackets |= bits(_mm_or_si128(_mm_cmpeq_epi8(folded, _mm_set1_epi8('{')),
                                              _mm_cmpeq_epi8(folded, _mm_set1_epi8('}'))));
            }
            quote &= ~escaped_bits(backslash);
            std::uint64_t inside = quote;  // (each bit: the parity of the quotes up to it, itself included)
            for (int shift = 1; shift < 64; shift *= 2) inside ^= inside << shift;
            if (in_string) inside = ~inside;
            in_string = inside >> 63;
            for (std::uint64_t b = brackets & ~inside; b != 0; b &= b - 1) {
                const int at = __builtin_ctzll(b);
                if (bracket(p[at])) {
                    // (the element's end: what the byte at a time reading knows of it there)
                    in_string = false, escaped = false, ended = true;
                    return p + at + 1;
                }
            }
        }
#endif
        return p;
    }

private:
    // The bytes of a block escaped by a backslash before them (the block's first by one before it: `escaped`),
    // `escaped` left saying whether its last byte escapes the next block's first.
    std::uint64_t escaped_bits(std::uint64_t backslash) {
        std::uint64_t bits = escaped ? 1 : 0;
        if (backslash == 0) return escaped = false, bits;
        bool next = escaped;
        for (int i = 0; i < 64; ++i) {
            if (next) {
                bits |= std::uint64_t{1} << i, next = false;
            } else if ((backslash >> i) & 1) {
                next = true;
            }
        }
        escaped = next;
        return bits;
    }
};

// The source's bytes, chunk by chunk, cut at the document's limit; where the reader is in them. Bytes from a
// point on can be kept (keep_from_here) across refills, to be looked at whole or read again (rewind).
class Input {
public:
    Input(const JsonSource& source, const JsonLimits& limits) : source_(&source), limits_(limits) {}
    // Text in memory (a streamed element cut from its document), read in place.
    Input(std::string_view text, const JsonLimits& limits)
        : source_(nullptr), limits_(limits), base_(text.data()), p_(text.data()), end_(text.data() + text.size()) {}

    // The document offset of the next byte.
    std::uint64_t position() const { return start_ + static_cast<std::uint64_t>(p_ - base_); }
    // True when the next byte is there (refilling the chunk when it is used up).
    bool more() { return p_ != end_ || refill(); }
    // The next byte (more() must be true).
    char peek() const { return *p_; }
    char take() { return *p_++; }
    // The next byte, or a stop at the end of the input (`what` says what was expected).
    char take_or_stop(const char* what) {
        if (!more()) end_of_input(what);
        return take();
    }
    // The stretch of bytes from the next one to the chunk's end (empty at the chunk's end).
    const char* begin() const { return p_; }
    const char* end() const { return end_; }
    void skip_to(const char* p) { p_ = p; }

    // Keeps the bytes from the next one on, until release() or rewind(), however many refills come.
    void keep_from_here() {
        keep_ = static_cast<std::size_t>(p_ - base_);
        keeping_ = true;
    }
    // The bytes kept so far (to the next byte).
    std::string_view kept() const { return {base_ + keep_, static_cast<std::size_t>(p_ - (base_ + keep_))}; }
    void release() { keeping_ = false; }
    // Back to the first byte kept, to read them again.
    void rewind() {
        p_ = base_ + keep_;
        keeping_ = false;
    }

    // At the end of the document's value: refused when the source holds more than the limit.
    void finish() const {
        if (cut_) end_of_input("");
    }
    // Throws the stop at the end of the input: the document's limit where it was cut there.
    [[noreturn]] void end_of_input(const char* what) const {
        if (cut_) {
            throw Stop{limits_.max_bytes, "more than the limit of " + std::to_string(limits_.max_bytes) +
                                              " bytes of JSON"};
        }
        throw Stop{position(), std::string("syntax error: unexpected end of input; expected ") + what};
    }

private:
    // The next bytes after the kept ones (if any), moved to the chunk's start.
    bool refill() {
        if (cut_ || !source_) return false;
        const std::size_t from = keeping_ ? keep_ : static_cast<std::size_t>(end_ - base_);
        const std::size_t retained = static_cast<std::size_t>(end_ - base_) - from;
        start_ += from;
        if (retained != 0) std::memmove(chunk_.data(), chunk_.data() + from, retained);
        keep_ = 0;
        read_size_ = std::clamp(read_size_ * 2, kFirstChunk, kLastChunk);
        chunk_.resize(retained + read_size_);
        std::size_t n = (*source_)(std::span(chunk_).subspan(retained));
        const std::uint64_t fresh = start_ + retained;  // the document offset of the first byte read now
        if (fresh + n > limits_.max_bytes) {
            n = static_cast<std::size_t>(limits_.max_bytes - std::min(fresh, limits_.max_bytes));
            cut_ = true;
        }
        base_ = chunk_.data();
        p_ = base_ + retained;
        end_ = p_ + n;
        return n != 0;
    }

    const JsonSource* source_;
    const JsonLimits& limits_;
    std::vector<char> chunk_;
    std::size_t read_size_ = 0;
    std::uint64_t start_ = 0;  // the document offset of base_[0]
    const char* base_ = nullptr;  // the chunk (or the text read in place)
    const char* p_ = nullptr;
    const char* end_ = nullptr;
    std::size_t keep_ = 0;  // the first byte kept, from base_, while keeping_
    bool keeping_ = false;
    bool cut_ = false;  // the source holds more than the document's limit
};

// Builds one document (the kept one, or a streamed element) within its budget.
class DomBuilder {
public:
    explicit DomBuilder(const JsonBudget& budget) : budget_(budget) {}

    void start(json& root) {
        root_ = &root;
        stack_.clear();
        placed_ = false;
        values_ = text_ = 0;
    }
    // Adds `value` where the document is (into the open container, under the last key); an
    // object or array added with `open` takes what follows until close(). False when over budget.
    bool add(json&& value, std::size_t text, bool open) {
        if (!spend(text)) return false;
        json* at = place(std::move(value));
        if (open) stack_.push_back(at);
        return true;
    }
    bool key(std::string&& key) {
        if (!spend(key.size())) return false;
        key_ = std::move(key);
        return true;
    }
    void close() { stack_.pop_back(); }
    // Spends the budget of a value or key (of `text` bytes) that is not kept. False when over budget.
    bool count(std::size_t text) { return spend(text); }
    bool closed() const { return stack_.empty(); }
    std::string overflow(const char* what) const {
        return values_ > budget_.values
                   ? std::string(what) + " holds more than the limit of " + std::to_string(budget_.values) + " values"
                   : std::string(what) + " holds more than the limit of " + std::to_string(budget_.text_bytes) +
                         " bytes of text";
    }

private:
    bool spend(std::size_t text) {
        text_ += text;
        return ++values_ <= budget_.values && text_ <= budget_.text_bytes;
    }
    json* place(json&& value) {
        if (!placed_) {
            placed_ = true;
            *root_ = std::move(value);
            return root_;
        }
        json& parent = *stack_.back();
        if (parent.is_array()) {
            auto& array = parent.get_ref<json::array_t&>();
            array.push_back(std::move(value));
            return &array.back();
        }
        json& slot = parent.get_ref<json::object_t&>()[std::move(key_)];
        slot = std::move(value);  // a repeated key: the last one wins
        return &slot;
    }

    const JsonBudget& budget_;
    json* root_ = nullptr;
    std::vector<json*> stack_;
    std::string key_;
    bool placed_ = false;
    std::uint64_t values_ = 0, text_ = 0;
};

// Whether the streamed elements are prepared (JsonStreaming::prepare) before the sink (`prepared`) sees them.
bool prepares(const JsonStreaming& s) { return s.prepare && s.prepared; }

// How deep a streamed array's elements lie: in the root object (1), in the array (2).
constexpr std::size_t kElementDepth = 2;

// Whether no limit could refuse the element `text` (one the cutter delimited, so at most ElementCut::kMostDepth
// deep): it is shorter than a string may be and than its budget, and holds no run of kMaxJsonTokenBytes bytes
// that could be one number or literal (outside the structure's marks, quotes and white space).
bool no_limit_refuses(std::string_view text, const JsonLimits& limits) {
    if (text.size() >= limits.max_string_bytes || text.size() > limits.element.text_bytes ||
        text.size() > limits.element.values) {
        return false;
    }
    if (text.size() < kMaxJsonTokenBytes) return true;
    std::size_t run = 0;
    for (const char c : text) {
        const bool mark = c == ',' || c == ':' || c == '[' || c == ']' || c == '{' || c == '}' || c == '"' ||
                          c == ' ' || c == '\t' || c == '\n' || c == '\r';
        run = mark ? 0 : run + 1;
        if (run >= kMaxJsonTokenBytes) return false;
    }
    return true;
}

// nlohmann's SAX interface: the kept document, streamed elements, the depth limit. Of a streamed element
// parsed on its own (`element`): the element is the document, within the element's budget, as deep as
// in its document.
class BoundedHandler {
public:
    BoundedHandler(const JsonLimits& limits, const JsonStreaming* streaming, const Input& input, json& result,
                   bool element = false)
        : limits_(limits), streaming_(streaming), input_(input), kept_(element ? limits.element : limits.kept),
          element_(limits.element), depth_(element ? kElementDepth : 0), of_element_(element) {
        kept_.start(result);
    }

    // Whether the next value is an element of a streamed array that threads may parse (JsonStreaming::threads).
    bool at_parallel_element() const {
        return streaming_ && streaming_->threads > 1 && streamed() && depth_ == stream_depth_ &&
               diverting_depth_ == 0 && (!streaming_->diverted || streaming_->diverted->drops_everything());
    }
    // The streamed array's key, and the index of the element the sink sees next.
    const std::string& stream_key() const { return stream_key_; }
    std::size_t next_index() const { return index_; }
    // Hands the sink an element of the streamed array parsed on its own (what JsonStreaming::prepare made of it,
    // where it prepares); false when the sink stops.
    bool deliver_parsed(json&& element, std::any&& prepared) {
        const std::size_t index = index_++;
        const bool more = prepares(*streaming_) ? streaming_->prepared(stream_key_, index, std::move(prepared))
                                                : streaming_->sink(stream_key_, index, std::move(element));
        if (!more) stopped_ = true;
        return more;
    }

    bool null() { return value(nullptr, 0); }
    bool boolean(bool v) { return value(v, 0); }
    bool number_integer(json::number_integer_t v) { return value(v, 0); }
    bool number_unsigned(json::number_unsigned_t v) { return value(v, 0); }
    bool number_float(json::number_float_t v) { return value(v, 0); }
    bool string(std::string& s) {
        const std::size_t n = s.size();
        return value(std::move(s), n);
    }
    bool start_object(std::size_t) { return open(json::object()); }
    bool start_array(std::size_t) { return open(json::array()); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(std::string& k) {
        if (diverting_depth_ != 0) return streaming_->diverted->key(k), true;
        divert_next_ = streaming_ && streaming_->diverted && contains(streaming_->diverted_keys, k);
        if (depth_ == 1) root_key_ = k;
        DomBuilder& builder = streamed() ? element_ : kept_;
        if (divert_next_ && streaming_->diverted->drops_everything()) return counted(builder, k.size());  // (not kept)
        return builder.key(std::move(k)) || over_budget(builder);
    }
    const std::optional<Stop>& failure() const { return failure_; }
    // Whether the next scalar goes to a receiver of diverted values that drops it.
    bool drops_next_scalar() const {
        return (diverting_depth_ != 0 || divert_next_) && streaming_->diverted->drops_scalars();
    }
    bool stopped_by_sink() const { return stopped_; }
    // Whether the next value goes whole to a receiver of diverted values that keeps nothing of it: then
    // the parser reads it past (as JSON, within the depth and string limits) and tells skip_value().
    bool skips_next_value() const {
        return diverting_depth_ == 0 && divert_next_ && streaming_->diverted->drops_everything();
    }
    // The value skipped: its ordinal is left where it would have been.
    bool skip_value() { return divert(); }

private:
    bool streamed() const { return stream_depth_ != 0; }

    bool open(json&& container) {
        if (++depth_ > limits_.max_depth) return fail(depth_cause(limits_));
        if (diverting_depth_ != 0 || divert_next_) {
            if (diverting_depth_ == 0 && !divert()) return false;
            streaming_->diverted->open(container.is_object());
            if (diverting_depth_ == 0) diverting_depth_ = depth_;
            return true;
        }
        if (streamed()) {
            if (depth_ == stream_depth_ + 1) element_.start(element_value_);
            return add(element_, std::move(container), 0, true);
        }
        if (depth_ == 2 && container.is_array() && root_is_object_ && streams(root_key_)) {
            stream_depth_ = depth_;
            stream_key_ = root_key_;
            index_ = 0;
            return add(kept_, json::array(), 0, false);  // (left empty: it shows that the array was there)
        }
        if (depth_ == 1) root_is_object_ = container.is_object();
        return add(kept_, std::move(container), 0, true);
    }

    bool close() {
        if (diverting_depth_ != 0) {
            streaming_->diverted->close();
            if (depth_-- == diverting_depth_) diverting_depth_ = 0;
            return true;
        }
        --depth_;
        if (!streamed()) return kept_.close(), true;
        if (depth_ + 1 == stream_depth_) return stream_depth_ = 0, true;  // the streamed array ends
        element_.close();
        return depth_ == stream_depth_ ? deliver() : true;
    }

    bool value(json&& v, std::size_t text) {
        if (diverting_depth_ != 0) return streaming_->diverted->scalar(v), true;
        if (divert_next_) return divert() && (streaming_->diverted->scalar(v), true);
        if (!streamed()) return add(kept_, std::move(v), text, false);
        if (depth_ == stream_depth_) element_.start(element_value_);
        if (!add(element_, std::move(v), text, false)) return false;
        return depth_ == stream_depth_ ? deliver() : true;
    }

    // Leaves the ordinal of the value diverted next where it would have been (the key is the last
    // one read: of the element being streamed, if any, else of the document).
    bool divert() {
        divert_next_ = false;
        DomBuilder& builder = streamed() ? element_ : kept_;
        if (streaming_->diverted->drops_everything()) return ++diverted_, counted(builder, 0);
        return add(builder, json(diverted_++), 0, false);
    }

    // A key (of `text` bytes) or ordinal of a value whose receiver drops everything: counted against the budget,
    // not kept.
    bool counted(DomBuilder& builder, std::size_t text) { return builder.count(text) || over_budget(builder); }

    bool add(DomBuilder& builder, json&& v, std::size_t text, bool open) {
        return builder.add(std::move(v), text, open) || over_budget(builder);
    }

    bool over_budget(const DomBuilder& builder) {
        const bool element = &builder == &element_ || of_element_;
        return fail(builder.overflow(element ? "a streamed element" : "the document"));
    }

    static bool contains(const std::vector<std::string>& keys, const std::string& key) {
        return std::find(keys.begin(), keys.end(), key) != keys.end();
    }
    bool streams(const std::string& key) const { return streaming_ && contains(streaming_->keys, key); }

    bool deliver() {
        json element = std::move(element_value_);
        element_value_ = json();
        std::any prepared;
        if (prepares(*streaming_)) prepared = streaming_->prepare(stream_key_, index_, std::move(element));
        return deliver_parsed(std::move(element), std::move(prepared));
    }

    bool fail(const std::string& cause) {
        const std::uint64_t at = input_.position();
        failure_ = Stop{at > 0 ? at - 1 : 0, cause};
        return false;
    }

    const JsonLimits& limits_;
    const JsonStreaming* streaming_;
    const Input& input_;
    DomBuilder kept_, element_;
    json element_value_;
    std::size_t depth_, stream_depth_ = 0, index_ = 0;
    std::size_t diverting_depth_ = 0, diverted_ = 0;  // the depth of the diverted object or array being read
    bool of_element_;  // the document is a streamed element parsed on its own
    bool root_is_object_ = false, stopped_ = false, divert_next_ = false;
    std::string root_key_, stream_key_;
    std::optional<Stop> failure_;
};

// 1 for a whole number as JSON writes it, 2 for one with a fraction (no exponent), 3 for one with an exponent,
// 0 for no number.
std::size_t number_shape(std::string_view w) {
    std::size_t i = w[0] == '-' ? 1 : 0;
    const auto digits = [&] {
        const std::size_t from = i;
        while (i < w.size() && w[i] >= '0' && w[i] <= '9') ++i;
        return i - from;
    };
    if (i == w.size()) return 0;
    if (w[i] == '0') {
        ++i;
    } else if (digits() == 0) {
        return 0;
    }
    std::size_t shape = 1;
    if (i < w.size() && w[i] == '.') {
        ++i, shape = 2;
        if (digits() == 0) return 0;
    }
    if (i < w.size() && (w[i] == 'e' || w[i] == 'E')) {
        ++i, shape = 3;
        if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
        if (digits() == 0) return 0;
    }
    return i == w.size() ? shape : 0;
}

// Where the object or array just opened before `p` ends (past its closing bracket), when [p, end) holds it
// whole and it is JSON of the plainest kind: strings of printable ASCII without escapes, of at most
// `max_string` bytes, numbers without an exponent of under 300 characters, true, false and null, nested at
// most `max_depth` deep (it counting 1, and at most 64). nullptr otherwise: then it is read the slow way,
// which tells what is wrong with it, if anything, and where. What a value read past costs where it is plain.
const char* plain_value_end(const char* p, const char* end, bool object, std::size_t max_depth,
                            std::size_t max_string) {
    enum State { kKeyOrClose, kValueOrClose, kKey, kValue, kAfter };
    std::uint64_t objects = object ? 1 : 0;  // bit k: the container k deep (0: the first) is an object
    std::size_t depth = 1;
    State state = object ? kKeyOrClose : kValueOrClose;
    const auto plain_string = [&] {  // at its opening quote
        const char* from = ++p;
        p = first_mark<Mark::kPlainStringEnd>(p, end);
        if (p == end || *p != '"' || static_cast<std::size_t>(p - from) > max_string) return false;
        return ++p, true;
    };
    const auto plain_word = [&] {  // (one that ends at the chunk's end may go on in the next one)
        const char* from = p;
        while (p != end && is_word_byte(*p)) ++p;
        const std::string_view w(from, static_cast<std::size_t>(p - from));
        if (p == end || w.empty()) return false;
        if (w == "true" || w == "false" || w == "null") return true;
        const std::size_t shape = number_shape(w);
        return w.size() < 300 && shape != 0 && shape != 3;
    };
    while (true) {
        while (p != end && is_space(*p)) ++p;
        if (p == end) return nullptr;
        const char c = *p;
        const bool in_object = (objects >> (depth - 1)) & 1;
        if (state == kKeyOrClose || state == kValueOrClose) {
            state = state == kKeyOrClose ? kKey : kValue;
            if (c != (in_object ? '}' : ']')) continue;
            ++p;
            if (--depth == 0) return p;
            state = kAfter;
        } else if (state == kKey) {
            if (c != '"' || !plain_string()) return nullptr;
            while (p != end && is_space(*p)) ++p;
            if (p == end || *p != ':') return nullptr;
            ++p, state = kValue;
        } else if (state == kValue && (c == '{' || c == '[')) {
            if (depth + 1 > max_depth || depth == 64) return nullptr;
            objects = (objects & ~(std::uint64_t{1} << depth)) | (std::uint64_t{c == '{'} << depth);
            ++depth, ++p;
            state = c == '{' ? kKeyOrClose : kValueOrClose;
        } else if (state == kValue) {
            if (!(c == '"' ? plain_string() : plain_word())) return nullptr;
            state = kAfter;
        } else if (c == ',') {
            ++p, state = in_object ? kKey : kValue;
        } else if (c == (in_object ? '}' : ']')) {
            ++p;
            if (--depth == 0) return p;
        } else {
            return nullptr;
        }
    }
}

// The largest streamed element that threads parse (JsonStreaming::threads): a larger one is read on the reading
// thread, the usual way, not held whole.
constexpr std::size_t kMaxParallelElementBytes = 4u << 20;
// The bytes of elements that make a batch for a thread.
constexpr std::size_t kParallelBatchBytes = 256u << 10;

// A streamed element parsed on its own, from its text at document offset `at`: its value, or where and why it
// is not JSON or passes a limit (as if read in its document).
std::variant<json, Stop> parse_element(std::string_view text, std::uint64_t at, const JsonLimits& limits,
                                       const JsonStreaming& streaming);

// Streamed elements parsed by threads of their own: the reading thread cuts them apart (add), threads parse
// them a batch at a time (and prepare them: JsonStreaming::prepare), and the reading thread hands them to the
// sink in their order (as their batches are parsed, and at drain). At most four batches a thread are held.
class ParallelElements {
public:
    ParallelElements(const JsonLimits& limits, const JsonStreaming& streaming)
        : limits_(limits), streaming_(streaming),
          element_streaming_{{}, {}, streaming.diverted_keys, streaming.diverted, 1, {}, {}, {}},
          from_text_(prepares(streaming) && streaming.prepare_text &&
                     (!streaming.diverted || streaming.diverted->drops_everything()) &&
                     limits.max_depth >= kElementDepth + ElementCut::kMostDepth) {}
    ~ParallelElements() {
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        work_.notify_all();
        for (auto& t : workers_) t.join();
    }
    ParallelElements(const ParallelElements&) = delete;
    ParallelElements& operator=(const ParallelElements&) = delete;

    // Adds the element `text` found at document offset `at` (copied); hands a full batch to the threads, and
    // the oldest batch's elements to the sink when more than four batches a thread are held.
    void add(std::uint64_t at, std::string_view text, BoundedHandler& h) {
        if (!filling_) {
            filling_ = std::make_shared<Batch>();
            filling_->key = h.stream_key();
            filling_->first_index = h.next_index() + pending_;
        }
        filling_->elements.push_back({at, filling_->text.size(), text.size()});
        filling_->text.append(text);
        ++pending_;
        if (filling_->text.size() < kParallelBatchBytes) return;
        submit();
        if (batches_.size() > 4 * streaming_.threads) deliver_oldest(h);
    }

    // Hands every element added to the sink, in order; throws Halt where the sink stops, and the Stop of the first
    // element that is not JSON or passes a limit (after those before it), or what preparing one threw.
    void drain(BoundedHandler& h) {
        if (filling_) submit();
        while (!batches_.empty()) deliver_oldest(h);
    }

private:
    struct Element {
        std::uint64_t at;  // in the document
        std::size_t from, size;  // in the batch's text
    };
    struct Parsed {
        json value;  // (null where it was prepared)
        std::any prepared;
    };
    struct Batch {
        std::string key;
        std::size_t first_index = 0;  // its first element's in the array
        std::string text;
        std::vector<Element> elements;
        std::vector<Parsed> parsed;  // in order, up to the first that is not JSON or could not be prepared
        std::optional<Stop> stop;  // why that one is not JSON
        std::exception_ptr error;  // what preparing that one threw
        bool done = false;
    };

    void submit() {
        {
            std::lock_guard lock(mutex_);
            waiting_.push_back(filling_);
            if (workers_.size() < streaming_.threads) workers_.emplace_back([this] { work(); });
        }
        work_.notify_one();
        batches_.push_back(std::move(filling_));
    }

    void work() {
        std::unique_lock lock(mutex_);
        while (true) {
            work_.wait(lock, [&] { return stopping_ || !waiting_.empty(); });
            if (stopping_) return;
            const std::shared_ptr<Batch> batch = std::move(waiting_.front());
            waiting_.pop_front();
            lock.unlock();
            parse(*batch);
            lock.lock();
            batch->done = true;
            done_.notify_all();
        }
    }

    void parse(Batch& b) const {
        b.parsed.reserve(b.elements.size());
        for (std::size_t i = 0; i < b.elements.size(); ++i) {
            const Element& e = b.elements[i];
            const std::string_view text = std::string_view(b.text).substr(e.from, e.size);
            if (from_text_ && no_limit_refuses(text, limits_)) {
                try {
                    if (auto prepared = streaming_.prepare_text(b.key, b.first_index + i, text); prepared.has_value()) {
                        b.parsed.push_back({json(), std::move(prepared)});
                        continue;
                    }
                } catch (...) {
                    return void(b.error = std::current_exception());
                }
            }
            auto value = parse_element(text, e.at, limits_, element_streaming_);
            if (auto* stop = std::get_if<Stop>(&value)) return void(b.stop = std::move(*stop));
            if (!prepares(streaming_)) {
                b.parsed.push_back({std::move(std::get<json>(value)), {}});
                continue;
            }
            try {
                auto prepared = streaming_.prepare(b.key, b.first_index + i, std::move(std::get<json>(value)));
                b.parsed.push_back({json(), std::move(prepared)});
            } catch (...) {
                return void(b.error = std::current_exception());
            }
        }
        std::string().swap(b.text);  // (what is left is handed on)
    }

    void deliver_oldest(BoundedHandler& h) {
        const std::shared_ptr<Batch> batch = std::move(batches_.front());
        batches_.pop_front();
        {
            std::unique_lock lock(mutex_);
            done_.wait(lock, [&] { return batch->done; });
        }
        pending_ -= batch->elements.size();
        for (std::size_t i = 0; i <= batch->parsed.size() && i < batch->elements.size(); ++i) {
            const Element& e = batch->elements[i];
            try {
                if (i == batch->parsed.size()) {
                    if (batch->stop) throw *batch->stop;
                    std::rethrow_exception(batch->error);
                }
                Parsed& p = batch->parsed[i];
                if (!h.deliver_parsed(std::move(p.value), std::move(p.prepared))) throw Halt{};
            } catch (const Error& error) {  // (the sink's: where the element ends, as when it is read the usual way)
                if (!error.file().empty() || error.offset()) throw;
                throw Error("", e.at + e.size, error.cause());
            }
        }
    }

    const JsonLimits& limits_;
    const JsonStreaming& streaming_;
    const JsonStreaming element_streaming_;  // the diverted values alone, for each element parsed on its own
    const bool from_text_;  // elements may be prepared from their text (JsonStreaming::prepare_text)
    std::shared_ptr<Batch> filling_;
    std::deque<std::shared_ptr<Batch>> batches_;  // handed to the threads, not yet to the sink, in order
    std::size_t pending_ = 0;  // elements added, not yet handed to the sink
    std::mutex mutex_;
    std::condition_variable work_, done_;
    std::deque<std::shared_ptr<Batch>> waiting_;  // for a thread
    std::vector<std::thread> workers_;
    bool stopping_ = false;
};

// Whether `b` is a UTF-8 continuation byte within [lo, hi] (0x80..0xBF unless the lead byte narrows it).
bool continues(unsigned char b, unsigned char lo = 0x80, unsigned char hi = 0xBF) { return b >= lo && b <= hi; }

// The JSON text of the input as events to the handler (nlohmann's SAX interface), as nlohmann's parser
// reads it (RFC 8259: strings of well-formed UTF-8 with their escapes and surrogate pairs, numbers as
// whole numbers where they fit 64 bits, else doubles, a double's overflow refused, a UTF-8 byte order
// mark allowed, nothing but white space after the value), without recursion and a chunk at a time: a
// string or a number's bytes are measured as they go by, and refused past their limit.
class Parser {
public:
    // `parallel`: where threads parse a streamed array's elements (null: this thread does); `base_depth`: how deep
    // the text lies in its document (a streamed element parsed on its own: kElementDepth).
    Parser(Input& in, BoundedHandler& handler, const JsonLimits& limits, ParallelElements* parallel = nullptr,
           std::size_t base_depth = 0)
        : in_(in), h_(handler), limits_(limits), parallel_(parallel), base_depth_(base_depth) {}

    // Reads the document; throws Stop where it is not JSON or passes a limit the reader keeps, Halt
    // where the handler refused an event.
    void run() {
        skip_bom();
        bool value_next = true;
        while (true) {
            const bool in_parallel = value_next && parallel_ && !skipping() && h_.at_parallel_element();
            if (in_parallel && parallel_elements()) value_next = false;  // (what follows the last is read here)
            if (value_next && !value()) {
                if (!object()) {
                    value_next = true;  // the first element of an array just opened
                    continue;
                }
                key();
                continue;
            }
            if (open_.empty()) break;
            value_next = after_value();
        }
        skip_space();
        if (in_.more()) fail("unexpected '" + std::string(1, in_.peek()) + "'; expected end of input");
        in_.finish();
    }

private:
    bool object() const { return open_.back(); }
    // How deep the innermost object or array open lies in the document.
    std::size_t depth() const { return base_depth_ + open_.size(); }

    // At an element of a streamed array that threads parse: cuts the elements and their commas apart for
    // them, each handed to the sink in order. True when it stopped after an element (what follows it, the
    // array's end or not, is read the usual way), false when before one: an element that cannot be cut
    // apart this way (too large to hold, or not delimited: read the usual way, which says what is wrong).
    bool parallel_elements() {
        while (true) {
            skip_space();
            if (!in_.more()) return parallel_->drain(h_), false;
            in_.keep_from_here();
            const std::uint64_t at = in_.position();
            if (!element_past()) {
                in_.rewind();
                return parallel_->drain(h_), false;
            }
            parallel_->add(at, in_.kept(), h_);
            in_.release();
            skip_space();
            if (!in_.more() || in_.peek() != ',') return parallel_->drain(h_), true;
            in_.take();
        }
    }

    // Past the element at the next byte (an object, array, string, number or literal), its bytes kept (the
    // input keeping them); false when they pass kMaxParallelElementBytes, or it cannot be delimited by its
    // quotes and brackets (a bracket closing the wrong kind, more than 64 deep, the input's end, no value).
    bool element_past() {
        const char first = in_.peek();
        if (first != '{' && first != '[' && first != '"') {
            if (!is_word_byte(first)) return false;
            return bytes_past([](const char* p, const char* end) {
                while (p != end && is_word_byte(*p)) ++p;
                return std::pair{p, p != end};
            }, true);
        }
        ElementCut cut;
        const bool delimited = bytes_past([&](const char* p, const char* end) {
            while (p != end) {
                bool ended = false;
                p = cut.blocks(p, end, ended);
                if (ended) return std::pair{p, true};
                if (p == end) break;
                if (cut.escaped) {
                    cut.escaped = false, ++p;
                } else if (cut.in_string) {
                    p = first_mark<Mark::kStringBodyEnd>(p, end);
                    if (p == end) break;
                    cut.escaped = *p == '\\', cut.in_string = *p++ != '"';
                } else {
                    p = first_mark<Mark::kBracketOrQuote>(p, end);
                    if (p == end) break;
                    const char c = *p++;
                    if (c == '"') {
                        cut.in_string = true;
                    } else if (cut.bracket(c)) {
                        return std::pair{p, true};
                    }
                }
                if (cut.depth == 0 && !cut.in_string) return std::pair{p, true};  // (a string element, closed)
            }
            return std::pair{p, false};
        }, false);
        return delimited && !cut.wrong;
    }

    // Moves past bytes while `scan(begin, end)` (where it stopped, and whether the element ends there) says so,
    // across chunks. At the input's end: `end_ok` (a number or literal ends there), else false; also false past
    // kMaxParallelElementBytes.
    template <typename Scan>
    bool bytes_past(Scan&& scan, bool end_ok) {
        while (in_.more()) {
            const auto [p, ended] = scan(in_.begin(), in_.end());
            in_.skip_to(p);
            if (ended) return true;
            if (in_.kept().size() > kMaxParallelElementBytes) return false;
        }
        return end_ok;
    }

    // A value: a scalar read whole (true), or an object or array opened (false) whose first member,
    // element or end comes next. An object or array opened and closed at once counts as read whole.
    bool value() {
        skip_space();
        if (!in_.more()) in_.end_of_input("a value");
        const char c = in_.peek();
        if (c == '"') {
            in_.take();
            const bool dropped = skipping() || h_.drops_next_scalar();
            std::string& text = string(in_.position() - 1, !dropped);
            if (!skipping()) check(dropped ? h_.null() : h_.string(text));
            return true;
        }
        if (c != '{' && c != '[') return word(), true;
        in_.take();
        open_.push_back(c == '{');
        if (open_container(c == '{')) return true;
        skip_space();
        if (!in_.more() || in_.peek() != (c == '{' ? '}' : ']')) return false;
        in_.take();
        close();
        return true;
    }

    // After a value in an open object or array: a comma (true: a value comes next, after its key in an
    // object) or the close (false).
    bool after_value() {
        skip_space();
        const char c = in_.take_or_stop(object() ? "',' or '}'" : "',' or ']'");
        if (c == ',') {
            if (object()) key();
            return true;
        }
        if (c != (object() ? '}' : ']')) {
            back_fail(std::string("unexpected '") + c + "'; expected " + (object() ? "',' or '}'" : "',' or ']'"));
        }
        close();
        return false;
    }

    // An object or array just opened (pushed on open_): to the handler, or read past where it (or the
    // value it lies in) is skipped. True when it was read whole (a plain value skipped at once).
    bool open_container(bool object) {
        if (!skipping() && !h_.skips_next_value()) {
            check(object ? h_.start_object(std::size_t(-1)) : h_.start_array(std::size_t(-1)));
            return false;
        }
        if (depth() > limits_.max_depth) throw Stop{in_.position() - 1, depth_cause(limits_)};
        if (skipping()) return false;
        check(h_.skip_value());
        const char* end = plain_value_end(in_.begin(), in_.end(), object, limits_.max_depth + 1 - depth(),
                                          limits_.max_string_bytes);
        if (end) {
            in_.skip_to(end);
            open_.pop_back();
            return true;
        }
        skip_from_ = open_.size();
        return false;
    }

    void close() {
        if (!skipping()) check(open_.back() ? h_.end_object() : h_.end_array());
        open_.pop_back();
        if (open_.size() < skip_from_) skip_from_ = 0;
    }

    // Whether the parser is inside a value it reads past (no events, no text kept).
    bool skipping() const { return skip_from_ != 0; }

    // A member's key and its colon.
    void key() {
        skip_space();
        const std::uint64_t at = in_.position();
        if (in_.take_or_stop("a string (an object's key)") != '"') {
            throw Stop{at, "syntax error: expected a string (an object's key)"};
        }
        std::string& key = string(at, !skipping());
        if (!skipping()) check(h_.key(key));
        skip_space();
        const std::uint64_t colon = in_.position();
        if (in_.take_or_stop("':'") != ':') throw Stop{colon, "syntax error: expected ':' after an object's key"};
    }

    void skip_space() {
        while (in_.more()) {
            const char* p = in_.begin();
            while (p != in_.end() && is_space(*p)) ++p;
            const bool done = p != in_.end();
            in_.skip_to(p);
            if (done) return;
        }
    }

    void skip_bom() {
        if (!in_.more() || static_cast<unsigned char>(in_.peek()) != 0xEF) return;
        in_.take();
        for (const unsigned char b : {0xBB, 0xBF}) {
            if (static_cast<unsigned char>(in_.take_or_stop("a byte order mark")) != b) {
                throw Stop{0, "syntax error: an ill-formed byte order mark (0xEF 0xBB 0xBF)"};
            }
        }
    }

    // The string whose opening quote, at `start`, was just taken, decoded (unless `keep` is false: then
    // what it holds is checked and not kept); its bytes as written measured against the string limit.
    std::string& string(std::uint64_t start, bool keep) {
        text_.clear();
        std::uint64_t written = 0;  // bytes between the quotes so far
        while (true) {
            if (!in_.more()) in_.end_of_input("'\"' (a string's end)");
            const char* p = in_.begin();
            const std::uint64_t room = limits_.max_string_bytes - written;
            const char* end = in_.end() - p > static_cast<std::ptrdiff_t>(room) ? p + room : in_.end();
            const char* q = first_mark<Mark::kPlainStringEnd>(p, end);
            if (keep) text_.append(p, q);
            written += static_cast<std::uint64_t>(q - p);
            in_.skip_to(q);
            if (q == in_.end()) continue;
            if (*q == '"') {
                in_.take();
                return text_;
            }
            const std::uint64_t before = in_.position();
            special(start);
            written += in_.position() - before;
            if (written > limits_.max_string_bytes) refuse_string(start, written);
        }
    }

    // At a string's byte that is not plain ASCII: an escape, a control character, a UTF-8 sequence, or
    // the byte that passes the string's limit.
    void special(std::uint64_t start) {
        const auto c = static_cast<unsigned char>(in_.peek());
        if (c >= 0x20 && c < 0x80 && c != '\\') {  // (past the limit: the fast loop stopped at it)
            in_.take();
            refuse_string(start, limits_.max_string_bytes + 1);
        }
        if (c == '\\') return escape();
        if (c < 0x20) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "%04X", static_cast<unsigned>(c));
            fail(std::string("invalid string: control character U+") + hex + " must be escaped");
        }
        utf8();
    }

    void escape() {
        in_.take();
        const char c = in_.take_or_stop("an escape");
        switch (c) {
            case '"': case '\\': case '/': text_ += c; return;
            case 'b': text_ += '\b'; return;
            case 'f': text_ += '\f'; return;
            case 'n': text_ += '\n'; return;
            case 'r': text_ += '\r'; return;
            case 't': text_ += '\t'; return;
            case 'u': return append_utf8(text_, code_point());
            default: back_fail("invalid string: forbidden character after backslash");
        }
    }

    // The code point of a \u escape whose 'u' was just taken, with the low surrogate that must follow a high one.
    std::uint32_t code_point() {
        const std::uint32_t first = hex4();
        if (first >= 0xDC00 && first <= 0xDFFF) {
            back_fail("invalid string: surrogate U+DC00..U+DFFF must follow U+D800..U+DBFF");
        }
        if (first < 0xD800 || first > 0xDBFF) return first;
        const bool escaped = in_.take_or_stop("a low surrogate") == '\\' && in_.take_or_stop("a low surrogate") == 'u';
        const std::uint32_t second = escaped ? hex4() : 0;
        if (second < 0xDC00 || second > 0xDFFF) {
            back_fail("invalid string: surrogate U+D800..U+DBFF must be followed by U+DC00..U+DFFF");
        }
        return 0x10000 + ((first - 0xD800) << 10) + (second - 0xDC00);
    }

    std::uint32_t hex4() {
        std::uint32_t code = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = in_.take_or_stop("four hexadecimal digits");
            const int digit = c >= '0' && c <= '9' ? c - '0'
                              : c >= 'a' && c <= 'f' ? c - 'a' + 10
                              : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
            if (digit < 0) back_fail("invalid string: '\\u' must be followed by 4 hex digits");
            code = code * 16 + static_cast<std::uint32_t>(digit);
        }
        return code;
    }

    // A UTF-8 sequence, checked as RFC 3629 (and nlohmann) have it, appended as it is.
    void utf8() {
        const auto lead = static_cast<unsigned char>(in_.take());
        int follow = 0;
        unsigned char lo = 0x80, hi = 0xBF;
        if (lead >= 0xC2 && lead <= 0xDF) {
            follow = 1;
        } else if (lead >= 0xE0 && lead <= 0xEF) {
            follow = 2, lo = lead == 0xE0 ? 0xA0 : 0x80, hi = lead == 0xED ? 0x9F : 0xBF;
        } else if (lead >= 0xF0 && lead <= 0xF4) {
            follow = 3, lo = lead == 0xF0 ? 0x90 : 0x80, hi = lead == 0xF4 ? 0x8F : 0xBF;
        } else {
            back_fail("invalid string: ill-formed UTF-8 byte");
        }
        text_ += static_cast<char>(lead);
        for (int k = 0; k < follow; ++k, lo = 0x80, hi = 0xBF) {
            const auto b = static_cast<unsigned char>(in_.take_or_stop("a UTF-8 continuation byte"));
            if (!continues(b, lo, hi)) back_fail("invalid string: ill-formed UTF-8 byte");
            text_ += static_cast<char>(b);
        }
    }

    // The string at `start` is past its limit: refused naming its length as written, measured to its end
    // (or to the end of the input) without keeping it.
    [[noreturn]] void refuse_string(std::uint64_t start, std::uint64_t written) {
        bool ended = false, escaped = false;
        while (!ended && in_.more()) {
            const char* p = in_.begin();
            for (; p != in_.end(); ++p) {
                if (!escaped && *p == '"') {
                    ended = true;
                    break;
                }
                escaped = !escaped && *p == '\\';
                ++written;
            }
            in_.skip_to(p);
        }
        throw Stop{start, std::string("a string of ") + (ended ? "" : "at least ") + std::to_string(written) +
                              " bytes, more than the limit of " + std::to_string(limits_.max_string_bytes)};
    }

    // A number or literal: its bytes up to the next structural character, space or quote (looked at where they
    // lie when the chunk holds them whole, else copied).
    void word() {
        const std::uint64_t start = in_.position();
        word_.clear();
        std::string_view w;
        while (in_.more()) {
            const char* p = in_.begin();
            const char* q = p;
            while (q != in_.end() && is_word_byte(*q)) ++q;
            if (word_.size() + static_cast<std::size_t>(q - p) > kMaxJsonTokenBytes) {
                throw Stop{start, "a number or literal of more than " + std::to_string(kMaxJsonTokenBytes) +
                                      " characters"};
            }
            in_.skip_to(q);
            if (q != in_.end() && word_.empty()) {
                w = std::string_view(p, static_cast<std::size_t>(q - p));
                break;
            }
            word_.append(p, q);
            w = word_;
            if (q != in_.end()) break;
        }
        if (w.empty()) {
            if (!in_.more()) in_.end_of_input("a value");
            throw Stop{start, std::string("syntax error: unexpected '") + in_.peek() + "'; expected a value"};
        }
        const char first = w[0];  // (a number starts with a digit or '-': one byte tells it from a literal)
        if (first != '-' && (first < '0' || first > '9')) return literal(start, w);
        number(start, w);
    }

    // true, false or null.
    void literal(std::uint64_t start, std::string_view w) {
        if (w == "true" || w == "false") return skipping() ? void() : check(h_.boolean(w == "true"));
        if (w == "null") return skipping() ? void() : check(h_.null());
        invalid_literal(start, w);
    }

    [[noreturn]] void invalid_literal(std::uint64_t start, std::string_view w) {
        throw Stop{start, "syntax error: invalid literal '" + display_excerpt(w) + "'"};
    }

    void number(std::uint64_t start, std::string_view w) {
        const std::size_t shape = number_shape(w);
        if (shape == 0) invalid_literal(start, w);
        const char* first = w.data();
        const char* last = first + w.size();
        const bool dropped = skipping() || h_.drops_next_scalar();
        // (a number dropped is not converted where it cannot overflow: no exponent, under 300 digits)
        if (dropped && w.size() < 300 && shape != 3) return drop();
        if (shape == 1 && w[0] != '-') {
            std::uint64_t v = 0;
            if (std::from_chars(first, last, v).ec == std::errc()) {
                return dropped ? drop() : check(h_.number_unsigned(v));
            }
        } else if (shape == 1) {
            std::int64_t v = 0;
            if (std::from_chars(first, last, v).ec == std::errc()) {
                return dropped ? drop() : check(h_.number_integer(v));
            }
        }
        double v = 0;  // (from_chars refuses an underflow: strtod gives its nearest double)
        if (std::from_chars(first, last, v).ec != std::errc()) v = std::strtod(std::string(w).c_str(), nullptr);
        if (!std::isfinite(v)) throw Stop{start, "number overflow parsing '" + display_excerpt(w) + "'"};
        dropped ? drop() : check(h_.number_float(v));
    }

    // A scalar read and dropped: nothing where the value it lies in is skipped, else null to the handler.
    void drop() {
        if (!skipping()) check(h_.null());
    }


    void check(bool accepted) {
        if (!accepted) throw Halt{};
    }
    // Refuses the text at the next byte.
    [[noreturn]] void fail(const std::string& what) { throw Stop{in_.position(), "syntax error: " + what}; }
    // Refuses the text at the byte just taken.
    [[noreturn]] void back_fail(const std::string& what) { throw Stop{in_.position() - 1, "syntax error: " + what}; }

    Input& in_;
    BoundedHandler& h_;
    const JsonLimits& limits_;
    ParallelElements* parallel_;
    std::size_t base_depth_;
    std::vector<bool> open_;  // the objects (true) and arrays open, outermost first
    std::size_t skip_from_ = 0;  // open_.size() when the outermost object or array read past opened (0: none)
    std::string text_, word_;
};

std::variant<json, Stop> parse_element(std::string_view text, std::uint64_t at, const JsonLimits& limits,
                                       const JsonStreaming& streaming) {
    json value;
    Input input(text, limits);
    BoundedHandler handler(limits, &streaming, input, value, true);
    try {
        Parser(input, handler, limits, nullptr, kElementDepth).run();
        return value;
    } catch (const Halt&) {
        Stop stop = handler.failure().value_or(Stop{0, "refused"});  // (no sink: only a limit halts it)
        stop.offset += at;
        return stop;
    } catch (Stop& stop) {
        stop.offset += at;
        return std::move(stop);
    }
}

Error field_error(std::string_view key, const std::string& what) {
    return Error("\"" + display_excerpt(key) + "\" " + what);
}

Error wrong_kind(std::string_view key, const json& value, const char* expected) {
    return field_error(key, "is " + json_kind(value) + ", not " + expected);
}

}  // namespace

nlohmann::json read_json(const JsonSource& source, const std::string& name, const JsonLimits& limits,
                         const JsonStreaming* streaming) {
    json result;
    Input input(source, limits);
    BoundedHandler handler(limits, streaming, input, result);
    std::optional<ParallelElements> parallel;
    if (streaming && streaming->threads > 1 && !streaming->keys.empty()) parallel.emplace(limits, *streaming);
    try {
        Parser(input, handler, limits, parallel ? &*parallel : nullptr).run();
    } catch (const Halt&) {
        const auto& f = handler.failure();
        if (handler.stopped_by_sink() || !f) return result;
        throw Error(name, f->offset, f->cause);
    } catch (const Stop& stop) {
        throw Error(name, stop.offset, stop.cause.starts_with("syntax error") || stop.cause.starts_with("number")
                                           ? "not JSON (" + display_excerpt(stop.cause) + ")"
                                           : stop.cause);
    } catch (const Error& e) {  // from the source or a receiver: about this document unless it names another
        if (e.file().empty()) throw Error(name, e.offset() ? e.offset() : input.position(), e.cause());
        throw;
    }
    return result;
}

nlohmann::json parse_json(std::string_view text, const std::string& name, const JsonLimits& limits,
                          const JsonStreaming* streaming) {
    return read_json(text_json_source(text), name, limits, streaming);
}

JsonSource text_json_source(std::string_view text) {
    return [text, at = std::size_t{0}](std::span<char> out) mutable {
        const std::size_t n = std::min(out.size(), text.size() - at);
        std::copy_n(text.data() + at, n, out.data());
        at += n;
        return n;
    };
}

JsonSource istream_json_source(std::istream& in) {
    return [&in](std::span<char> out) {
        in.read(out.data(), static_cast<std::streamsize>(out.size()));
        if (in.bad()) throw Error("reading failed");
        return static_cast<std::size_t>(in.gcount());
    };
}

std::string json_kind(const nlohmann::json& value) {
    if (value.is_null()) return "null";
    if (value.is_number()) return "a number";
    const std::string name = value.type_name();
    return (value.is_object() || value.is_array() ? "an " : "a ") + name;
}

std::string json_excerpt(const nlohmann::json& value) {
    return display_excerpt(value.dump(-1, ' ', false, json::error_handler_t::replace));
}

const nlohmann::json* json_field(const nlohmann::json& object, std::string_view key) {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    return it == object.end() || it->is_null() ? nullptr : &*it;
}

std::optional<std::string> json_optional_string(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (!v) return std::nullopt;
    if (!v->is_string()) throw wrong_kind(key, *v, "a string");
    return v->get_ref<const std::string&>();
}

std::optional<double> json_optional_number(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (!v) return std::nullopt;
    if (!v->is_number()) throw wrong_kind(key, *v, "a number");
    return v->get<double>();
}

std::optional<bool> json_optional_bool(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (!v) return std::nullopt;
    if (!v->is_boolean()) throw wrong_kind(key, *v, "true or false");
    return v->get<bool>();
}

std::optional<std::uint64_t> json_optional_count(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (!v) return std::nullopt;
    if (v->is_number_unsigned()) return v->get<std::uint64_t>();
    if (v->is_number_integer() && v->get<std::int64_t>() >= 0) {
        return static_cast<std::uint64_t>(v->get<std::int64_t>());
    }
    throw field_error(key, "is " + (v->is_number() ? json_excerpt(*v) : json_kind(*v)) +
                               ", not a count (a whole number, 0 or more)");
}

const nlohmann::json* json_optional_array(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (v && !v->is_array()) throw wrong_kind(key, *v, "an array");
    return v;
}

const nlohmann::json* json_optional_object(const nlohmann::json& object, std::string_view key) {
    const json* v = json_field(object, key);
    if (v && !v->is_object()) throw wrong_kind(key, *v, "an object");
    return v;
}

namespace {
template <typename T>
T required(T value, std::string_view key) {
    if (!value) throw field_error(key, "is missing");
    return value;
}
}  // namespace

std::string json_string(const nlohmann::json& object, std::string_view key) {
    return *required(json_optional_string(object, key), key);
}

double json_number(const nlohmann::json& object, std::string_view key) {
    return *required(json_optional_number(object, key), key);
}

const nlohmann::json& json_array(const nlohmann::json& object, std::string_view key) {
    return *required(json_optional_array(object, key), key);
}

const nlohmann::json& json_object(const nlohmann::json& object, std::string_view key) {
    return *required(json_optional_object(object, key), key);
}

double json_finite(const nlohmann::json& value, std::string_view what) {
    if (!value.is_number()) throw Error(std::string(what) + " is " + json_kind(value) + ", not a number");
    const double v = value.get<double>();
    if (!std::isfinite(v)) throw Error(std::string(what) + " is not a finite number");
    return v;
}

}  // namespace lidarscout
