// The one way JSON from a user or a server is read (STAC catalogs, EPT metadata, sessions, GeoJSON
// polygons, replica manifests): parsed chunk by chunk from a source (a parser of our own that reads
// JSON as nlohmann's does, into nlohmann::json values), with every bound applied while the bytes go
// by, so that no document costs more than its limits allow: the bytes of the document, how deep
// arrays and objects nest, the length of one string or key (a longer one is refused naming its
// length, never its text), of one number, and how many values and bytes of text the returned
// document may hold. Each refusal is one lidarscout::Error naming the document, the byte offset and
// the limit. Arrays under chosen keys of the root object can be streamed: each element is handed
// over as its own small document, bounded on its own and dropped after use, so that a catalog of a
// million items costs one item at a time (or a few per thread, where threads parse the elements). The values of
// chosen keys, at any depth, can be diverted: handed over event by event and never built (GeoJSON
// coordinates kept as rings, an item's footprint not kept at all).
//
// The fields of what was read are taken through typed accessors (json_string, json_number, ...):
// a field of the wrong kind is an Error naming the field and the kind expected, never a
// nlohmann exception. Text from a document put in a message goes through json_excerpt or
// display_excerpt (core/text.hpp), cut to a couple of hundred characters.
#pragma once

#include <any>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace lidarscout {

// What a document (or one streamed element of it) may hold once read.
struct JsonBudget {
    std::uint64_t values = 1'000'000;       // values and keys
    std::uint64_t text_bytes = 64ull << 20;  // bytes of strings and keys
};

struct JsonLimits {
    std::uint64_t max_bytes = 64ull << 20;      // the document
    std::size_t max_depth = 256;                // arrays and objects inside each other
    std::size_t max_string_bytes = 1u << 20;    // one string or key, as written (escapes included)
    JsonBudget kept;                            // the document returned (streamed arrays left out)
    JsonBudget element;                         // each streamed element
};

// The longest number or literal (true, 1.5e3, ...) accepted, in characters.
inline constexpr std::size_t kMaxJsonTokenBytes = 4096;

// Fills `out` with the document's next bytes and returns how many (0 at its end); throws Error.
using JsonSource = std::function<std::size_t(std::span<char> out)>;

// Receives one element of a streamed array: the array's key, the element's index in it and the
// element. Returns false to stop reading (the rest of the document is then not read).
using JsonElementSink = std::function<bool(const std::string& key, std::size_t index, nlohmann::json&& element)>;

// Makes an element into what the reader keeps of it (JsonStreaming::prepare), on the thread that parsed it.
using JsonElementPrepare =
    std::function<std::any(const std::string& key, std::size_t index, nlohmann::json&& element)>;
// Makes an element into what the reader keeps of it straight from its JSON text (JsonStreaming::prepare_text);
// an empty std::any where it does not, the element then parsed and prepared as usual.
using JsonTextPrepare = std::function<std::any(const std::string& key, std::size_t index, std::string_view text)>;
// Receives what JsonElementPrepare made of an element, in order. Returns false to stop reading.
using JsonPreparedSink = std::function<bool(const std::string& key, std::size_t index, std::any&& prepared)>;

// Receives, event by event, a value the document does not hold (a diverted value, below), so that
// its caller keeps it its own way (GeoJSON coordinates as rings, a few bytes a vertex rather than
// a document's hundreds), or not at all (a catalog item's footprint and schemas: no document is
// built for them). An event may throw lidarscout::Error to refuse the document.
class JsonValueEvents {
public:
    virtual ~JsonValueEvents() = default;
    virtual void scalar(const nlohmann::json& value) = 0;  // a number, string, true, false or null
    virtual void open(bool object) = 0;                    // an object or an array starts
    virtual void key(const std::string& key) = 0;          // the key of the next value (in an object)
    virtual void close() = 0;                              // the innermost open object or array ends
    // True when scalars are not looked at: each is then handed over as null (a number not converted, a
    // string not kept; both still read and checked as JSON).
    virtual bool drops_scalars() const { return false; }
    // True when nothing is looked at (no event has an effect): each value diverted here is then read past,
    // checked as JSON within the limits but never tokenized into events.
    virtual bool drops_everything() const { return false; }
};

struct JsonStreaming {
    std::vector<std::string> keys;  // keys of the root object whose arrays are streamed
    JsonElementSink sink;
    // The values of members named one of `diverted_keys`, at any depth (in streamed elements too;
    // this comes before streaming), go to `diverted` instead, the document holding in their place
    // their ordinal (0, 1, ...). They pass the depth, string and size limits, not the document's
    // budget: their receiver bounds them. Where the receiver drops everything (JsonValueDropper) neither their
    // key nor their ordinal is kept (both still counted against the budget, as if they were).
    std::vector<std::string> diverted_keys;
    JsonValueEvents* diverted = nullptr;
    // Threads that parse a streamed array's elements (the reading thread cutting them apart and handing
    // them to the sink, in order, as they are parsed); 1 parses them on the reading thread. Whatever the
    // number, the sink sees the same elements in the same order, and a document that is not JSON or passes
    // a limit is the same Error at the same offset, the elements before it delivered. Used only where
    // the diverted values are dropped (JsonValueDropper) or there are none: a receiver of events sees them in
    // order, on the reading thread.
    unsigned threads = 1;
    // Instead of `sink`, where both are set: each element made into what the caller keeps (`prepare`, on the
    // thread that parsed it, so safe to call from several threads at once; the element is destroyed there,
    // which is most of what a document costs), then that handed to `prepared` on the reading thread, in order.
    JsonElementPrepare prepare;
    JsonPreparedSink prepared;
    // Tried before `prepare`, on the same thread, for each element no limit could refuse (shorter than a string
    // may be, no token near the longest accepted, the diverted values dropped): what the reader keeps made
    // straight from the element's text (a fast reader of a common shape of element), or an empty std::any, the
    // element then parsed and prepared as usual. It must accept only text that is JSON, and make of it what
    // `prepare` makes of the parsed element.
    JsonTextPrepare prepare_text;
};

// A receiver of diverted values that keeps nothing: for values a caller does not use.
class JsonValueDropper final : public JsonValueEvents {
public:
    void scalar(const nlohmann::json&) override {}
    void open(bool) override {}
    void key(const std::string&) override {}
    void close() override {}
    bool drops_scalars() const override { return true; }
    bool drops_everything() const override { return true; }
};

// The document read from `source`; `name` (a path or URL as shown) names it in errors. A streamed
// array is left in the result as an empty array (so that its presence shows); a streamed key whose
// value is not an array is kept as it is. When the sink stops the reading, what was read so far
// is returned. (`streaming` may name no keys, to divert values only.) Throws
// lidarscout::Error(name, byte offset, cause) for text that is not JSON or passes a limit, and
// the Errors of the source, the sink and the diverted values' receiver (named the same way).
nlohmann::json read_json(const JsonSource& source, const std::string& name, const JsonLimits& limits,
                         const JsonStreaming* streaming = nullptr);
// The same of text in memory.
nlohmann::json parse_json(std::string_view text, const std::string& name, const JsonLimits& limits,
                          const JsonStreaming* streaming = nullptr);
// A source reading `in` (a local file, opened by the caller) in chunks.
JsonSource istream_json_source(std::istream& in);
// A source reading `text` (which must outlive it).
JsonSource text_json_source(std::string_view text);

// ---- typed access (each throws lidarscout::Error without a file; the caller adds where)

// "a string", "an object", "a number", ...: the kind of `value`, for messages.
std::string json_kind(const nlohmann::json& value);
// `value` as compact JSON text, cut for a message (display_excerpt).
std::string json_excerpt(const nlohmann::json& value);

// The field `key` of `object`, null when the field is absent or null (or `object` is no object).
const nlohmann::json* json_field(const nlohmann::json& object, std::string_view key);

// Absent (or null) fields give nullopt / nullptr; a field of another kind throws Error naming the
// field and the kind expected ("\"rel\" is a number, not a string").
std::optional<std::string> json_optional_string(const nlohmann::json& object, std::string_view key);
std::optional<double> json_optional_number(const nlohmann::json& object, std::string_view key);
std::optional<bool> json_optional_bool(const nlohmann::json& object, std::string_view key);
// A whole number >= 0 (written without a fraction or exponent).
std::optional<std::uint64_t> json_optional_count(const nlohmann::json& object, std::string_view key);
const nlohmann::json* json_optional_array(const nlohmann::json& object, std::string_view key);
const nlohmann::json* json_optional_object(const nlohmann::json& object, std::string_view key);

// The same where the field must be there ("\"href\" is missing").
std::string json_string(const nlohmann::json& object, std::string_view key);
double json_number(const nlohmann::json& object, std::string_view key);
const nlohmann::json& json_array(const nlohmann::json& object, std::string_view key);
const nlohmann::json& json_object(const nlohmann::json& object, std::string_view key);

// A value that must be a finite number, `what` naming it in the error ("a vertex's x").
double json_finite(const nlohmann::json& value, std::string_view what);

}  // namespace lidarscout
