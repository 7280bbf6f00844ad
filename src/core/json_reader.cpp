// The bounded JSON reader: a stream buffer that pulls chunks from the source and cuts the input
// where a string, a number or the document passes its limit, and a SAX handler that builds the
// kept document and the streamed elements, each within its budget, and stops at the depth limit.
#include "core/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <streambuf>
#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"

namespace lidarscout {
namespace {

using nlohmann::json;

constexpr std::size_t kFirstChunk = 64u << 10, kLastChunk = 1u << 20;  // the chunk grows to the last size

// Where and why reading stopped short of the document's end (a limit).
struct Stop {
    std::uint64_t offset = 0;
    std::string cause;
};

bool is_structural_or_space(char c) {
    switch (c) {
        case '[': case ']': case '{': case '}': case ':': case ',': case ' ': case '\t': case '\n': case '\r':
            return true;
        default:
            return false;
    }
}

// Tells strings apart from the rest as the bytes go by, to measure each string and number.
struct Lexeme {
    bool in_string = false, escaped = false;
    std::uint64_t start = 0;  // where the current string or token starts
    std::uint64_t length = 0;  // its bytes so far (a string's without its quotes)

    // Takes the byte at `offset`; returns false when a string or token passes its limit.
    bool take(char c, std::uint64_t offset, const JsonLimits& limits) {
        if (in_string) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                in_string = false;
                return true;
            }
            return ++length <= limits.max_string_bytes;
        }
        if (c == '"') {
            in_string = true, start = offset, length = 0;
        } else if (is_structural_or_space(c)) {
            length = 0;
        } else {
            if (length == 0) start = offset;
            return ++length <= kMaxJsonTokenBytes;
        }
        return true;
    }
};

// The source as a stream buffer for nlohmann's parser, cut where a limit is passed.
class BoundedBuffer : public std::streambuf {
public:
    BoundedBuffer(const JsonSource& source, const JsonLimits& limits) : source_(source), limits_(limits) {}

    const std::optional<Stop>& stop() const { return stop_; }
    // Bytes handed to the parser so far.
    std::uint64_t position() const { return start_ + static_cast<std::uint64_t>(gptr() - eback()); }

protected:
    int_type underflow() override {
        start_ += delivered_;
        delivered_ = 0;
        setg(nullptr, nullptr, nullptr);
        if (stop_) return traits_type::eof();
        chunk_.resize(std::clamp(chunk_.size() * 2, kFirstChunk, kLastChunk));
        std::size_t n = source_(chunk_);
        if (n == 0) return traits_type::eof();
        if (start_ + n > limits_.max_bytes) {
            n = static_cast<std::size_t>(limits_.max_bytes - std::min(start_, limits_.max_bytes));
            stop_ = Stop{limits_.max_bytes, "more than the limit of " + std::to_string(limits_.max_bytes) +
                                                " bytes of JSON"};
        }
        delivered_ = scan(n);
        setg(chunk_.data(), chunk_.data(), chunk_.data() + delivered_);
        return delivered_ == 0 ? traits_type::eof() : traits_type::to_int_type(chunk_[0]);
    }

private:
    // How many of the chunk's first `n` bytes pass; where one does not, stop_ says why.
    std::size_t scan(std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) {
            if (lexeme_.in_string && !lexeme_.escaped && (i = skip_plain(i, n)) == n) break;
            if (lexeme_.take(chunk_[i], start_ + i, limits_)) continue;
            if (lexeme_.in_string) {
                stop_ = Stop{lexeme_.start, string_refusal(i + 1, n)};
            } else {
                stop_ = Stop{lexeme_.start, "a number or literal of more than " +
                                                std::to_string(kMaxJsonTokenBytes) + " characters"};
            }
            return i;
        }
        return n;
    }

    // Past the bytes of a string from chunk byte `i` that are neither a quote nor a backslash, as long
    // as the string stays within its limit (the byte that passes it is left to Lexeme::take).
    std::size_t skip_plain(std::size_t i, std::size_t n) {
        const std::uint64_t used = std::min<std::uint64_t>(lexeme_.length, limits_.max_string_bytes);
        const auto end = static_cast<std::size_t>(std::min<std::uint64_t>(n, i + (limits_.max_string_bytes - used)));
        std::size_t j = i;
        while (j < end && chunk_[j] != '"' && chunk_[j] != '\\') ++j;
        lexeme_.length += j - i;
        return j;
    }

    // The refusal of the string passing its limit at chunk byte `from - 1`, naming its whole length
    // (read on to its end, bounded by the document's limit, without keeping it).
    std::string string_refusal(std::size_t from, std::size_t n) {
        bool ended = measure(std::span<const char>(chunk_.data() + from, n - from));
        std::uint64_t offset = start_ + n;
        std::vector<char> scratch(ended ? 0 : kFirstChunk);
        while (!ended && offset < limits_.max_bytes) {
            const std::size_t got = source_(scratch);
            if (got == 0) break;
            const auto allowed = static_cast<std::size_t>(std::min<std::uint64_t>(got, limits_.max_bytes - offset));
            offset += allowed;
            ended = measure(std::span<const char>(scratch.data(), allowed));
        }
        return std::string("a string of ") + (ended ? "" : "at least ") + std::to_string(lexeme_.length) +
               " bytes, more than the limit of " + std::to_string(limits_.max_string_bytes);
    }

    // Counts the string on through `bytes`; true when it ends there.
    bool measure(std::span<const char> bytes) {
        for (const char c : bytes) {
            lexeme_.take(c, 0, limits_);
            if (!lexeme_.in_string) return true;
        }
        return false;
    }

    const JsonSource& source_;
    const JsonLimits& limits_;
    std::vector<char> chunk_;
    std::uint64_t start_ = 0;      // the document offset of chunk_[0]
    std::size_t delivered_ = 0;    // bytes of chunk_ handed to the parser
    Lexeme lexeme_;
    std::optional<Stop> stop_;
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

// nlohmann's SAX interface: the kept document, streamed elements, the depth limit.
class BoundedHandler {
public:
    BoundedHandler(const JsonLimits& limits, const JsonStreaming* streaming, const BoundedBuffer& buffer,
                   json& result)
        : limits_(limits), streaming_(streaming), buffer_(buffer), kept_(limits.kept), element_(limits.element) {
        kept_.start(result);
    }

    bool null() { return value(nullptr, 0); }
    bool boolean(bool v) { return value(v, 0); }
    bool number_integer(json::number_integer_t v) { return value(v, 0); }
    bool number_unsigned(json::number_unsigned_t v) { return value(v, 0); }
    bool number_float(json::number_float_t v, const std::string&) { return value(v, 0); }
    bool string(std::string& s) {
        const std::size_t n = s.size();
        return value(std::move(s), n);
    }
    bool binary(json::binary_t&) { return fail("binary data"); }  // (never in JSON text)
    bool start_object(std::size_t) { return open(json::object()); }
    bool start_array(std::size_t) { return open(json::array()); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(std::string& k) {
        if (diverting_depth_ != 0) return streaming_->diverted->key(k), true;
        divert_next_ = streaming_ && streaming_->diverted && contains(streaming_->diverted_keys, k);
        if (depth_ == 1) root_key_ = k;
        DomBuilder& builder = streamed() ? element_ : kept_;
        return builder.key(std::move(k)) || over_budget(builder);
    }
    bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
        std::string what = e.what();
        if (const auto at = what.find("] "); what.starts_with("[json.exception") && at != std::string::npos) {
            what.erase(0, at + 2);
        }
        parse_error_ = Stop{position > 0 ? position - 1 : 0, "not JSON (" + display_excerpt(what) + ")"};
        return false;
    }

    const std::optional<Stop>& failure() const { return failure_; }
    const std::optional<Stop>& parse_failure() const { return parse_error_; }
    bool stopped_by_sink() const { return stopped_; }

private:
    bool streamed() const { return stream_depth_ != 0; }

    bool open(json&& container) {
        if (++depth_ > limits_.max_depth) {
            return fail("arrays and objects nested more than the limit of " + std::to_string(limits_.max_depth) +
                        " deep");
        }
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
        return add(streamed() ? element_ : kept_, json(diverted_++), 0, false);
    }

    bool add(DomBuilder& builder, json&& v, std::size_t text, bool open) {
        return builder.add(std::move(v), text, open) || over_budget(builder);
    }

    bool over_budget(const DomBuilder& builder) {
        return fail(&builder == &kept_ ? kept_.overflow("the document") : element_.overflow("a streamed element"));
    }

    static bool contains(const std::vector<std::string>& keys, const std::string& key) {
        return std::find(keys.begin(), keys.end(), key) != keys.end();
    }
    bool streams(const std::string& key) const { return streaming_ && contains(streaming_->keys, key); }

    bool deliver() {
        json element = std::move(element_value_);
        element_value_ = json();
        if (streaming_->sink(stream_key_, index_++, std::move(element))) return true;
        stopped_ = true;
        return false;
    }

    bool fail(const std::string& cause) {
        const std::uint64_t at = buffer_.position();
        failure_ = Stop{at > 0 ? at - 1 : 0, cause};
        return false;
    }

    const JsonLimits& limits_;
    const JsonStreaming* streaming_;
    const BoundedBuffer& buffer_;
    DomBuilder kept_, element_;
    json element_value_;
    std::size_t depth_ = 0, stream_depth_ = 0, index_ = 0;
    std::size_t diverting_depth_ = 0, diverted_ = 0;  // the depth of the diverted object or array being read
    bool root_is_object_ = false, stopped_ = false, divert_next_ = false;
    std::string root_key_, stream_key_;
    std::optional<Stop> failure_, parse_error_;
};

// A reader for nlohmann's stream adapter over the buffer (it uses the buffer directly).
class BufferStream : public std::istream {
public:
    explicit BufferStream(std::streambuf& buffer) : std::istream(&buffer) {}
};

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
    BoundedBuffer buffer(source, limits);
    BoundedHandler handler(limits, streaming, buffer, result);
    BufferStream stream(buffer);
    try {
        json::sax_parse(static_cast<std::istream&>(stream), &handler, json::input_format_t::json, true, false);
    } catch (const json::exception& e) {  // (the parser reports through the handler; this is a safety net)
        throw Error(name, buffer.position(), "not JSON (" + display_excerpt(e.what()) + ")");
    } catch (const Error& e) {  // from the source or a receiver: about this document unless it names another
        if (e.file().empty()) throw Error(name, e.offset() ? e.offset() : buffer.position(), e.cause());
        throw;
    }
    if (handler.stopped_by_sink()) return result;
    if (const auto& f = handler.failure()) throw Error(name, f->offset, f->cause);
    const auto& stop = buffer.stop();
    const auto& parse = handler.parse_failure();
    // The parser meets the end of the input where it was cut: the cut is the cause.
    if (stop && (!parse || parse->offset >= stop->offset)) throw Error(name, stop->offset, stop->cause);
    if (parse) throw Error(name, parse->offset, parse->cause);
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
