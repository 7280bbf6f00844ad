// core/json_reader: documents read within their limits, each refusal one Error naming the document,
// the offset and the limit, never the text: nesting 100k deep, strings and numbers past their
// limit (a long string named by its length, and never held whole), documents past their size or
// their budget of values; arrays streamed element by element with what they hold at once
// bounded by one element; fields read by kind, a wrong kind named.
#include "core/json_reader.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <tuple>

#include <algorithm>
#include <any>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "allocation_counter.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/text.hpp"

namespace lidarscout {
namespace {

using nlohmann::json;

// The Error reading `text` within `limits` ("" when it reads).
Error refusal(const std::string& text, const JsonLimits& limits = {}, const JsonStreaming* streaming = nullptr) {
    try {
        parse_json(text, "doc.json", limits, streaming);
    } catch (const Error& e) {
        return e;
    }
    return Error("");
}

bool has(const Error& e, const std::string& what) { return std::string(e.what()).find(what) != std::string::npos; }

TEST(JsonReader, ReadsADocument) {
    const json j = parse_json(R"({"a": [1, -2, 2.5, "x", true, null, {"b": {}}], "c": "\u00e9"})", "doc.json", {});
    EXPECT_EQ(j.at("a").size(), 7u);
    EXPECT_EQ(j.at("a")[1], -2);
    EXPECT_EQ(j.at("a")[6].at("b"), json::object());
    EXPECT_EQ(j.at("c"), "\xC3\xA9");
    EXPECT_EQ(parse_json(" 7 ", "n", {}), 7);
}

TEST(JsonReader, NestingAHundredThousandDeepIsOneError) {
    for (const std::string open : {"[", "{\"a\":"}) {
        std::string deep;
        for (int i = 0; i < 100'000; ++i) deep += open;
        const Error e = refusal(deep);
        EXPECT_EQ(e.file(), "doc.json");
        EXPECT_TRUE(has(e, "nested more than the limit of 256 deep")) << e.what();
        ASSERT_TRUE(e.offset());
        EXPECT_LT(*e.offset(), 257 * open.size()) << "refused where it passes the limit, not at the end";
    }
    std::string at_limit(256, '['), past(257, '[');
    at_limit += std::string(256, ']'), past += std::string(257, ']');
    EXPECT_NO_THROW(parse_json(at_limit, "doc.json", {}));
    EXPECT_TRUE(has(refusal(past), "nested more than"));
}

TEST(JsonReader, AStringPastItsLimitIsNamedByItsLengthNeverCopied) {
    const std::string big(32u << 20, 'x');
    const std::string text = "{\"id\": \"" + big + "\", \"n\": 1}";
    const test::AllocationCounter counter;
    const Error e = refusal(text);
    EXPECT_TRUE(has(e, "a string of 33554432 bytes, more than the limit of 1048576")) << e.what();
    EXPECT_EQ(e.offset(), 7u);
    EXPECT_LT(std::string(e.what()).size(), 200u) << "the string itself is not in the message";
    EXPECT_LT(counter.peak_bytes(), 16u << 20) << "a 32 MiB string is refused holding at most a few MiB of it";
    // A string never closed is named by what there is of it; a key is a string too.
    EXPECT_TRUE(has(refusal("[\"" + std::string(3u << 20, 'y')), "a string of at least 3145728 bytes"));
    EXPECT_TRUE(has(refusal("{\"" + std::string(2u << 20, 'k') + "\": 1}"), "a string of 2097152 bytes"));
    // Escapes count as written; a string at the limit reads.
    JsonLimits small;
    small.max_string_bytes = 8;
    EXPECT_NO_THROW(parse_json(R"(["12345678", "\\\"\\\""])", "d", small));
    EXPECT_TRUE(has(refusal(R"(["123456789"])", small), "a string of 9 bytes"));
}

TEST(JsonReader, NumbersAndLiteralsHaveALimitToo) {
    const std::string digits(100'000, '7');
    const Error e = refusal("[1, " + digits + "]");
    EXPECT_TRUE(has(e, "a number or literal of more than 4096 characters")) << e.what();
    EXPECT_EQ(e.offset(), 4u);
    EXPECT_TRUE(has(refusal("[" + std::string(5000, 't') + "]"), "more than 4096 characters"));
    EXPECT_TRUE(has(refusal("[1e400]"), "not JSON")) << "a number out of range";
}

TEST(JsonReader, DocumentsPastTheirSizeOrBudgetAreRefused) {
    JsonLimits limits;
    limits.max_bytes = 100;
    const Error big = refusal("[" + std::string(200, ' ') + "1]", limits);
    EXPECT_TRUE(has(big, "more than the limit of 100 bytes of JSON")) << big.what();
    EXPECT_NO_THROW(parse_json("[" + std::string(90, ' ') + "1]", "d", limits));
    limits = {};
    limits.kept.values = 1000;
    std::string many = "[";
    for (int i = 0; i < 2000; ++i) many += "0,";
    many += "0]";
    EXPECT_TRUE(has(refusal(many, limits), "the document holds more than the limit of 1000 values"));
    limits = {};
    limits.kept.text_bytes = 1000;
    std::string words = "[";
    for (int i = 0; i < 200; ++i) words += "\"abcdefghij\",";
    words += "\"\"]";
    EXPECT_TRUE(has(refusal(words, limits), "more than the limit of 1000 bytes of text"));
}

TEST(JsonReader, WhatIsNotJsonIsNamedWhereItBreaks) {
    const Error e = refusal(R"({"a": 1,, "b": 2})");
    EXPECT_TRUE(has(e, "not JSON (")) << e.what();
    EXPECT_EQ(e.offset(), 8u);
    EXPECT_TRUE(has(refusal(R"({"a": 1} trailing)"), "not JSON"));
    EXPECT_TRUE(has(refusal(R"({"a": [1, 2)"), "not JSON"));
    EXPECT_TRUE(has(refusal(""), "not JSON"));
    EXPECT_TRUE(has(refusal("[\"\xFF\"]"), "not JSON")) << "ill-formed UTF-8";
    // The parser's own message quotes the last token: cut, whatever its length.
    const Error token = refusal("[1 \"" + std::string(500'000, 'z') + "\"]");
    EXPECT_LT(std::string(token.what()).size(), 400u);
}

// The reader reads JSON as nlohmann's parser does: what it takes, what it refuses and the values (kinds
// of numbers included), on edge cases of the grammar, escapes, surrogate pairs, UTF-8 and numbers, each
// also read a byte at a time (every token then crosses a chunk's edge).
TEST(JsonReader, ReadsAsNlohmannsParserDoes) {
    const std::vector<std::string> cases = {
        "0", "-0", "1", "-1", "18446744073709551615", "18446744073709551616", "-9223372036854775808",
        "-9223372036854775809", "1.5", "-1.5e3", "1E+2", "1e-400", "1e400", "-1e400", "0.1e1", "01", "1.", ".5",
        "-", "+1", "1e", "1e+", "0x10", "1.7976931348623157e308", "2.2250738585072014e-308", "4.9e-324",
        "123456789012345678901234567890", "0.30000000000000004", "true", "false", "null", "tru", "nul", "True",
        R"("")", R"("a\"b\\c\/d\b\f\n\r\t")", R"("\u0041\u00e9\u20AC")", R"("\ud83d\ude00")", R"("\ud83d")",
        R"("\ude00")", R"("\ud83dx")", R"("\ud83d\u0041")", R"("\u00")", R"("\u00G0")", R"("\x")", "\"\x01\"",
        "\"\x7f\"", "\"\xC3\xA9\"", "\"\xC3\"", "\"\xC0\x80\"", "\"\xE0\x80\x80\"", "\"\xED\xA0\x80\"",
        "\"\xEF\xBF\xBF\"", "\"\xF0\x9F\x98\x80\"", "\"\xF4\x90\x80\x80\"", "\"\xF5\x80\x80\x80\"", "\"\x80\"",
        "\xEF\xBB\xBF{}", "\xEF\xBB{}", "[]", "{}", "[1,]", "[,1]", "{\"a\":1,}", "{\"a\" 1}", "{1:2}", "[1 2]",
        "{\"a\":1}x", "[1]]", " \t\r\n[ 1 , { \"b\" : [ ] } ] \n", "", " ", "[", "{\"a\"", "{\"a\":", "\"abc",
        "[1,2,3", R"({"a":{"b":{"c":[1,{"d":null}]}},"a":2})", "[-0.0, 1E5, 1e-5, -12.5e+2]", "nan", "[Infinity]",
        "\"tab\there\"", "[\"\\u0000\"]", "{\"\":\"\"}", "/* no */ 1", "1 // no",
    };
    for (const std::string& text : cases) {
        std::optional<json> expected;
        try {
            expected = json::parse(text);
        } catch (const json::exception&) {
        }
        for (const std::size_t chunk : {std::size_t{0}, std::size_t{1}}) {
            const JsonSource bytes = [&, at = std::size_t{0}](std::span<char> out) mutable {
                const std::size_t n = std::min({chunk ? chunk : out.size(), out.size(), text.size() - at});
                std::copy_n(text.data() + at, n, out.data());
                return at += n, n;
            };
            std::optional<json> got;
            try {
                got = read_json(bytes, "doc.json", {});
            } catch (const Error& e) {
                EXPECT_TRUE(has(e, "not JSON (")) << e.what();
            }
            ASSERT_EQ(got.has_value(), expected.has_value()) << "'" << text << "' chunk " << chunk;
            if (!got) continue;
            EXPECT_EQ(got->dump(), expected->dump()) << text;
            EXPECT_EQ(got->type(), expected->type()) << text;
            if (got->is_array()) {
                for (std::size_t k = 0; k < got->size(); ++k) {
                    EXPECT_EQ((*got)[k].type(), (*expected)[k].type()) << text;
                }
            }
        }
    }
}

// A FeatureCollection-like document of `n` features, each ~`pad` bytes.
std::string collection(int n, std::size_t pad) {
    std::string text = R"({"type": "FeatureCollection", "features": [)";
    for (int i = 0; i < n; ++i) {
        text += (i ? "," : "") + std::string(R"({"id": "f)") + std::to_string(i) + R"(", "pad": ")" +
                std::string(pad, 'p') + R"(", "v": [1, 2, 3]})";
    }
    return text + R"(], "links": [{"rel": "next", "href": "x"}, 5], "stac_version": "1.0.0"})";
}

TEST(JsonReader, StreamedArraysAreHandedOverAnElementAtATime) {
    std::vector<std::string> ids;
    std::vector<json> links;
    const JsonStreaming streaming{{"features", "links"}, [&](const std::string& key, std::size_t i, json&& e) {
                                      if (key == "features") {
                                          EXPECT_EQ(i, ids.size());
                                          ids.push_back(e.at("id").get<std::string>());
                                      } else {
                                          links.push_back(std::move(e));
                                      }
                                      return true;
                                  }};
    const json rest = parse_json(collection(3, 4), "c.json", {}, &streaming);
    EXPECT_EQ(ids, (std::vector<std::string>{"f0", "f1", "f2"}));
    ASSERT_EQ(links.size(), 2u);
    EXPECT_EQ(links[1], 5);
    EXPECT_EQ(rest.at("type"), "FeatureCollection");
    EXPECT_EQ(rest.at("features"), json::array()) << "a streamed array stays, empty";
    EXPECT_EQ(rest.at("stac_version"), "1.0.0");
    // Only the root's keys stream; a streamed key that is no array is kept as it is.
    const json nested = parse_json(R"({"a": {"features": [1, 2]}, "features": 5})", "d", {}, &streaming);
    EXPECT_EQ(nested.at("a").at("features").size(), 2u);
    EXPECT_EQ(nested.at("features"), 5);
    EXPECT_EQ(ids.size(), 3u);
}

TEST(JsonReader, AStreamedArrayHoldsOneElementAtATime) {
    const std::string text = collection(20'000, 1000);  // ~20 MB
    std::size_t seen = 0;
    const JsonStreaming streaming{{"features"}, [&](const std::string&, std::size_t, json&&) { return ++seen, true; }};
    const test::AllocationCounter counter;
    parse_json(text, "c.json", {}, &streaming);
    EXPECT_EQ(seen, 20'000u);
    EXPECT_LT(counter.peak_bytes(), text.size() / 8) << "held at once: the chunk and one feature, not the document";
    // Each element has its own budget; the sink can stop the reading.
    JsonLimits limits;
    limits.element.values = 5;
    const Error e = refusal(text, limits, &streaming);
    EXPECT_TRUE(has(e, "a streamed element holds more than the limit of 5 values")) << e.what();
    std::size_t taken = 0;
    const JsonStreaming two{{"features"}, [&](const std::string&, std::size_t, json&&) { return ++taken < 2; }};
    const json rest = parse_json(text, "c.json", {}, &two);
    EXPECT_EQ(taken, 2u);
    EXPECT_EQ(rest.at("type"), "FeatureCollection");
}

// Records the events of diverted values as text.
class Recorder final : public JsonValueEvents {
public:
    std::string text;
    void scalar(const json& v) override { text += v.dump() + " "; }
    void open(bool object) override { text += object ? "{ " : "[ "; }
    void key(const std::string& k) override { text += k + ": "; }
    void close() override { text += "; "; }
};

TEST(JsonReader, DivertedValuesGoToTheirReceiverAndLeaveTheirOrdinal) {
    Recorder recorder;
    const JsonStreaming streaming{{"features"},
                                  [&](const std::string&, std::size_t, json&& e) {
                                      EXPECT_EQ(e.at("geometry").at("coordinates"), 2) << "its ordinal";
                                      return true;
                                  },
                                  {"coordinates"}, &recorder};
    const json j = parse_json(R"({"coordinates": [[1, 2], {"a": true}], "b": {"coordinates": null},
                                  "features": [{"geometry": {"coordinates": [3]}}], "c": [{"coordinates": "x"}]})",
                              "d", {}, &streaming);
    EXPECT_EQ(recorder.text, R"([ [ 1 2 ; { a: true ; ; null [ 3 ; "x" )");
    EXPECT_EQ(j.at("coordinates"), 0);
    EXPECT_EQ(j.at("b").at("coordinates"), 1);
    EXPECT_EQ(j.at("c")[0].at("coordinates"), 3);
    // Diverted values keep the depth limit; a receiver's Error names the document and where.
    EXPECT_TRUE(has(refusal(R"({"coordinates": )" + std::string(300, '[') + std::string(300, ']') + "}", {},
                            &streaming),
                    "nested more than"));
    class Refusing final : public JsonValueEvents {
        void scalar(const json&) override { throw Error("no numbers here"); }
        void open(bool) override {}
        void key(const std::string&) override {}
        void close() override {}
    } refusing;
    const JsonStreaming refused{{}, {}, {"coordinates"}, &refusing};
    const Error e = refusal(R"({"coordinates": [7]})", {}, &refused);
    EXPECT_EQ(e.file(), "doc.json");
    EXPECT_EQ(e.cause(), "no numbers here");
    EXPECT_TRUE(e.offset());
}

// Drops scalars but counts the events of diverted values: what the reader did with every value a catalog
// reads past before values dropped whole were skipped (and what it still does for any other receiver).
class EventCounter final : public JsonValueEvents {
public:
    std::size_t events = 0;
    void scalar(const json&) override { ++events; }
    void open(bool) override { ++events; }
    void key(const std::string&) override { ++events; }
    void close() override { ++events; }
    bool drops_scalars() const override { return true; }
};

// `doc` without its members named `key`, at any depth.
void erase_members(json& doc, const std::string& key) {
    if (doc.is_object()) doc.erase(key);
    if (doc.is_structured()) {
        for (auto& v : doc) erase_members(v, key);
    }
}

// What reading `text` gives: the document as JSON text (the diverted values' keys and ordinals left out), or
// the Error (offset and cause); the source hands over at most `piece` bytes a call (the chunks' edges fall
// inside strings, numbers and values read past).
std::string outcome(const std::string& text, JsonValueEvents& receiver, std::size_t piece) {
    const JsonStreaming streaming{{"features"}, [](const std::string&, std::size_t, json&&) { return true; },
                                  {"geometry", "skipped"}, &receiver};
    JsonLimits limits;
    limits.max_depth = 12;
    limits.max_string_bytes = 24;
    JsonSource source = [&text, piece, at = std::size_t{0}](std::span<char> out) mutable {
        const std::size_t n = std::min({out.size(), piece, text.size() - at});
        std::copy_n(text.data() + at, n, out.data());
        return at += n, n;
    };
    try {
        json doc = read_json(source, "d.json", limits, &streaming);
        for (const auto& key : streaming.diverted_keys) erase_members(doc, key);
        return doc.dump();
    } catch (const Error& e) {
        return "error at " + std::to_string(e.offset().value_or(~0ull)) + ": " + e.cause();
    }
}

// A value read past (its receiver keeps nothing) is checked as JSON as any value is: the same document, or the
// same Error at the same offset, as where its events go to a receiver, whatever the text and wherever the
// chunks end: braces and escaped quotes in strings, CRLF, deep nesting at and past the limit, long strings,
// bad UTF-8, numbers that overflow, truncated text.
TEST(JsonReader, AValueReadPastIsCheckedAsAValueHandedOver) {
    const std::vector<std::string> values = {
        R"({"a": "}{][", "b": [1, -2.5, 0, true, false, null, {}, []]})",
        R"({"q": "say \"}\" and \\", "u": "\u00e9\ud83d\ude00", "c": "\u0041"})",
        "{\r\n \"x\" :\t[ 1 ,\r\n 2 ] ,\"y\":{ }\r\n}",
        "[[[[[[[[[[[1]]]]]]]]]]]", "[[[[[[[[[[[[1]]]]]]]]]]]]", R"({"s": "0123456789012345678901234"})",
        R"(["0123456789012345678901234"])", "[\"caf\xC3\xA9\", \"\xC3\"]", "[\"\xF0\x9F\x98\x80\", \"\xED\xA0\x80\"]",
        "[\"tab\there\"]", "[1e999]", "[1e5, -0.5E-3, 12.]", "[01]", "[-]", "[1 2]", "{\"a\" 1}", "{\"a\": 1,}",
        "[1,]", "[tru]", "[true1]", "[nul, 2]", "{1: 2}", "[\"\\x\"]", "[\"\\ud800\"]", "[\"\\udc00\"]",
        R"({"coordinates": [[[-83.14, 37.66], [-83.12, 37.66]]], "type": "Polygon"})"};
    std::vector<std::string> documents;
    for (const auto& v : values) {
        documents.push_back(R"({"type": "FeatureCollection", "features": [{"id": "a", "geometry": )" + v +
                            R"(, "properties": {"skipped": )" + v + R"(, "n": 1}}], "skipped": )" + v + "}");
    }
    JsonValueDropper dropper;
    const JsonStreaming dropped{{}, {}, {"skipped"}, &dropper};
    EXPECT_EQ(parse_json(R"({"a": 1, "skipped": [2], "b": {"skipped": 3}})", "d", {}, &dropped),
              json::parse(R"({"a": 1, "b": {}})")) << "a value dropped leaves neither its key nor its ordinal";
    JsonLimits two;
    two.kept.values = 4;
    EXPECT_TRUE(has(refusal(R"({"a": 1, "skipped": [2]})", two, &dropped), "more than the limit of 4 values"))
        << "though they count against the budget";
    const std::string whole = documents[0];
    for (std::size_t cut = 0; cut < whole.size(); cut += 7) documents.push_back(whole.substr(0, cut));
    for (const auto& text : documents) {
        for (const std::size_t piece : {std::size_t{1}, std::size_t{5}, std::size_t{1} << 20}) {
            JsonValueDropper dropper;
            EventCounter counter;
            EXPECT_EQ(outcome(text, dropper, piece), outcome(text, counter, piece))
                << text << " in pieces of " << piece;
        }
    }
}

// Random choices for the documents below.
struct Random {
    explicit Random(std::uint64_t seed) : rng(seed) {}
    std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng.next() % n); }
    Rng rng;
};

// A streamed document's elements of every kind: objects and arrays nested, strings with escapes (quotes and
// brackets in them), UTF-8, numbers, literals, values read past ("skipped"), white space between.
std::string random_element(Random& rng, int depth) {
    static const std::vector<std::string> scalars = {
        "1",     "-2.5",  "0",    "1e3", "true", "false", "null", R"("a")", R"("q\"}]{[\\")", R"("\u00e9\ud83d\ude00")",
        "\"caf\xC3\xA9\"", R"("")", "12345678901234567890123"};
    const int kind = depth > 4 ? 0 : static_cast<int>(rng.below(4));
    if (kind == 0) return scalars[rng.below(scalars.size())];
    const std::string space = rng.below(3) == 0 ? " \r\n\t" : "";
    std::string out = kind == 1 ? "[" : "{";
    const std::size_t n = rng.below(5);
    for (std::size_t i = 0; i < n; ++i) {
        if (i) out += "," + space;
        const std::string key = rng.below(4) == 0 ? "skipped" : "k" + std::to_string(i);
        if (kind != 1) out += "\"" + key + "\":" + space;
        out += random_element(rng, depth + 1);
    }
    return out + space + (kind == 1 ? "]" : "}");
}

std::string random_document(Random& rng, std::size_t elements) {
    std::string doc = R"({"type": "FeatureCollection", "links": [{"rel": "self"}, 5], "features": [)";
    for (std::size_t i = 0; i < elements; ++i) doc += (i ? ", " : "") + random_element(rng, 0);
    return doc + R"(], "after": {"n": [1, 2]}})";
}

// What reading `text` with `threads` gives the sink (each element as key, index and JSON text, or what `prepare`
// made of it) and what it returns or throws; the sink stops after `stop_at` elements or throws at element
// `throw_at`; the source hands over at most `piece` bytes a call.
std::string streamed_outcome(const std::string& text, unsigned threads, const JsonLimits& limits, bool prepare,
                             std::size_t piece, std::size_t stop_at = ~std::size_t{0},
                             std::size_t throw_at = ~std::size_t{0}) {
    std::string seen;
    std::size_t count = 0;
    const auto take = [&](const std::string& key, std::size_t i, const std::string& what) {
        seen += key + "#" + std::to_string(i) + ":" + what + "\n";
        if (count == throw_at) throw Error("the sink refuses element " + std::to_string(i));
        return ++count < stop_at;
    };
    JsonValueDropper dropper;
    JsonStreaming streaming{{"features", "links"},
                            [&](const std::string& key, std::size_t i, json&& e) { return take(key, i, e.dump()); },
                            {"skipped"},
                            &dropper};
    streaming.threads = threads;
    if (prepare) {
        streaming.prepare = [](const std::string& key, std::size_t i, json&& e) -> std::any {
            return "prepared " + key + std::to_string(i) + " " + e.dump();
        };
        streaming.prepared = [&](const std::string& key, std::size_t i, std::any&& p) {
            return take(key, i, std::any_cast<std::string>(p));
        };
    }
    JsonSource source = [&text, piece, at = std::size_t{0}](std::span<char> out) mutable {
        const std::size_t n = std::min({out.size(), piece, text.size() - at});
        std::copy_n(text.data() + at, n, out.data());
        return at += n, n;
    };
    try {
        return seen + "returned " + read_json(source, "d.json", limits, &streaming).dump();
    } catch (const Error& e) {
        return seen + "error in " + e.file() + " at " + std::to_string(e.offset().value_or(~0ull)) + ": " + e.cause();
    }
}

// Elements parsed by threads (JsonStreaming::threads) reach the sink as those parsed by the reading thread: the
// same elements in the same order with the same indexes, the same document returned, the same Error at the same
// offset (the elements before it delivered), whatever the text: random documents, each also mutated (a byte
// changed, dropped or doubled: quotes, brackets, commas where they break it) and cut short, within limits that
// some elements pass (values, depth, string length, the document's bytes), a sink that stops or throws, chunks
// of one byte and of a megabyte.
TEST(JsonReader, ElementsParsedByThreadsAreThoseReadInOrder) {
    Random rng(54);
    const std::string marks = "\"{}[],: \\x1";
    std::vector<JsonLimits> limits(5);
    limits[1].element.values = 12;
    limits[2].max_depth = 5;
    limits[3].max_string_bytes = 6;
    std::size_t parallel_read = 0;
    for (int round = 0; round < 120; ++round) {
        const std::string whole = random_document(rng, 1 + rng.below(40));
        std::vector<std::string> texts = {whole, whole.substr(0, rng.below(whole.size()))};
        for (int m = 0; m < 4; ++m) {
            std::string t = whole;
            const std::size_t at = rng.below(t.size());
            const int how = static_cast<int>(rng.below(3));
            if (how == 0) t[at] = marks[rng.below(marks.size())];
            if (how == 1) t.erase(at, 1);
            if (how == 2) t.insert(at, 1, t[at]);
            texts.push_back(t);
        }
        for (const auto& text : texts) {
            JsonLimits l = limits[rng.below(limits.size())];
            if (rng.below(6) == 0) l.max_bytes = text.size() / 2 + 1;
            const bool prepare = rng.below(2) == 0;
            const std::size_t piece = rng.below(3) == 0 ? 1 : 1u << 20;
            const std::size_t stop = rng.below(4) == 0 ? rng.below(20) + 1 : ~std::size_t{0};
            const std::size_t fail = rng.below(5) == 0 ? rng.below(20) : ~std::size_t{0};
            const std::string serial = streamed_outcome(text, 1, l, prepare, piece, stop, fail);
            EXPECT_EQ(serial, streamed_outcome(text, 3, l, prepare, piece, stop, fail)) << text;
            parallel_read += serial.find("returned") != std::string::npos;
        }
    }
    EXPECT_GT(parallel_read, 100u) << "documents read whole, not only refused";
}

// A document of many elements is parsed on other threads than the reader's, in batches, in order; an element too
// large to hold for them (4 MB) is read on the reading thread, not held whole, and those after it go on to the
// threads.
TEST(JsonReader, LargeStreamedArraysAreParsedByThreads) {
    std::string big = "{\"pad\": [";
    for (int k = 0; k < 6; ++k) big += (k ? ",\"" : "\"") + std::string(900'000, 'x') + "\"";
    big += "]}";
    std::string text = R"({"features": [)";
    for (int i = 0; i < 20'000; ++i) text += (i ? "," : "") + std::string(R"({"id": )") + std::to_string(i) + "}";
    text += "," + big;
    for (int i = 0; i < 20'000; ++i) text += ",[" + std::to_string(i) + "]";
    text += "]}";
    std::mutex mutex;
    std::set<std::thread::id> threads;
    std::vector<std::size_t> order;
    JsonStreaming streaming{{"features"}, {}};
    streaming.threads = 2;
    streaming.prepare = [&](const std::string&, std::size_t i, json&& e) -> std::any {
        std::lock_guard lock(mutex);
        threads.insert(std::this_thread::get_id());
        return e.is_object() && e.contains("pad") ? std::size_t{999'999} : i;
    };
    streaming.prepared = [&](const std::string&, std::size_t i, std::any&& p) {
        const auto v = std::any_cast<std::size_t>(p);
        order.push_back(v == 999'999 ? i : v);
        return true;
    };
    JsonLimits limits;
    limits.element.text_bytes = 8u << 20;
    parse_json(text, "big.json", limits, &streaming);
    ASSERT_EQ(order.size(), 40'001u);
    for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i);
    EXPECT_GE(threads.size(), 2u) << "the threads and, for the large element, the reading thread";
    EXPECT_TRUE(threads.count(std::this_thread::get_id())) << "the large element is the reading thread's";
}

// A streamed element may be made into what is kept straight from its text (JsonStreaming::prepare_text), on the
// threads: only where no limit could refuse it (not a number past kMaxJsonTokenBytes digits, nor a string past
// max_string_bytes; none where the diverted values go to a receiver that looks at them), and
// where it declines (an empty std::any), the element is parsed and prepared as usual. Either way the sink sees
// the elements in order, and text that is not JSON is the same Error at the same offset.
TEST(JsonReader, AnElementMayBePreparedFromItsText) {
    std::string objects = R"({"features": [)";
    for (int i = 0; i < 3000; ++i) objects += (i ? "," : "") + std::string(R"({"id": )") + std::to_string(i) + "}";
    const std::string text = objects + ",[\"" + std::string(2000, 't') + "\", 0." + std::string(3000, '0') +
                             "1]" +  // (longer than a number may be, but no limit refuses it)
                             ",[" + std::string(kMaxJsonTokenBytes + 10, '7') + "]]}";  // (too long a number)
    const std::string long_string = objects + ",[\"" + std::string(9000, 's') + "\"]]}";  // (this test's 8 KiB)
    const auto run = [&](bool from_text, JsonValueEvents* diverted, const std::string& doc) {
        std::atomic<int> texts{0};
        std::vector<std::string> order;
        JsonStreaming streaming{{"features"}, {}, {"skipped"}, diverted};
        streaming.threads = 2;
        streaming.prepare = [](const std::string&, std::size_t, json&& e) -> std::any { return "parsed " + e.dump(); };
        if (from_text) {
            streaming.prepare_text = [&](const std::string&, std::size_t i, std::string_view t) -> std::any {
                ++texts;
                if (i % 2) return {};  // (the odd ones declined)
                return "text " + json::parse(t).dump();
            };
        }
        streaming.prepared = [&](const std::string&, std::size_t, std::any&& p) {
            order.push_back(std::any_cast<std::string>(p));
            return true;
        };
        JsonLimits limits;
        limits.max_string_bytes = 8192;
        std::string error;
        try {
            parse_json(doc, "d.json", limits, &streaming);
        } catch (const Error& e) {
            error = std::to_string(e.offset().value_or(0)) + " " + e.cause();
        }
        return std::tuple{texts.load(), order, error};
    };
    const auto [texts, order, error] = run(true, nullptr, text);
    EXPECT_EQ(texts, 3001) << "every element but the one a limit refuses";
    EXPECT_EQ(error, std::get<2>(run(false, nullptr, text)));
    EXPECT_NE(error.find("number"), std::string::npos) << error;  // (the number refused, where it is)
    ASSERT_EQ(order.size(), 3001u);
    for (std::size_t i = 0; i < 3000; ++i) {
        const std::string id = R"({"id":)" + std::to_string(i) + "}";
        ASSERT_EQ(order[i], (i % 2 ? "parsed " : "text ") + id);
    }
    EXPECT_EQ(order[3000].rfind("text [", 0), 0u);
    const auto [string_texts, string_order, string_error] = run(true, nullptr, long_string);
    EXPECT_EQ(string_texts, 3000);
    EXPECT_EQ(string_error, std::get<2>(run(false, nullptr, long_string)));
    EXPECT_NE(string_error.find("string"), std::string::npos) << string_error;
    EventCounter counter;  // (looks at the diverted values: never from the text)
    EXPECT_EQ(std::get<0>(run(true, &counter, text)), 0);
    JsonValueDropper dropper;  // (drops them: from the text)
    EXPECT_EQ(std::get<0>(run(true, &dropper, text)), 3001);
}

TEST(JsonReader, AnErrorOfTheSourceOrSinkNamesTheDocument) {
    const JsonSource failing = [](std::span<char>) -> std::size_t { throw Error("read failed"); };
    try {
        read_json(failing, "remote.json", {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "remote.json");
    }
}

TEST(JsonReader, FieldsAreReadByTheirKind) {
    const json j = json::parse(R"({"s": "text", "n": 2.5, "c": 7, "neg": -1, "b": true, "a": [1], "o": {},
                                   "z": null, "rel": 5})");
    EXPECT_EQ(json_optional_string(j, "s"), "text");
    EXPECT_EQ(json_optional_string(j, "missing"), std::nullopt);
    EXPECT_EQ(json_optional_string(j, "z"), std::nullopt) << "null is absent";
    EXPECT_EQ(json_number(j, "c"), 7.0);
    EXPECT_EQ(json_optional_count(j, "c"), 7u);
    EXPECT_EQ(json_optional_bool(j, "b"), true);
    EXPECT_EQ(json_array(j, "a").size(), 1u);
    EXPECT_TRUE(json_object(j, "o").empty());
    const auto cause = [](auto&& read) {
        try {
            read();
        } catch (const Error& e) {
            return e.cause();
        }
        return std::string();
    };
    EXPECT_EQ(cause([&] { json_optional_string(j, "rel"); }), "\"rel\" is a number, not a string");
    EXPECT_EQ(cause([&] { json_number(j, "s"); }), "\"s\" is a string, not a number");
    EXPECT_EQ(cause([&] { json_array(j, "o"); }), "\"o\" is an object, not an array");
    EXPECT_EQ(cause([&] { json_object(j, "a"); }), "\"a\" is an array, not an object");
    EXPECT_EQ(cause([&] { json_string(j, "missing"); }), "\"missing\" is missing");
    EXPECT_EQ(cause([&] { json_optional_count(j, "neg"); }), "\"neg\" is -1, not a count (a whole number, 0 or more)");
    EXPECT_EQ(cause([&] { json_optional_count(j, "n"); }), "\"n\" is 2.5, not a count (a whole number, 0 or more)");
    EXPECT_EQ(cause([&] { json_finite(j.at("s"), "x"); }), "x is a string, not a number");
    EXPECT_EQ(json_field(json(5), "s"), nullptr) << "a value that is no object has no fields";
}

TEST(JsonReader, TextFromADocumentIsCutWherePrinted) {
    const std::string id(10'000, 'i');
    const std::string shown = display_excerpt(id);
    EXPECT_EQ(shown, std::string(200, 'i') + "... (10000 bytes)");
    EXPECT_EQ(display_excerpt("short"), "short");
    EXPECT_EQ(display_excerpt(std::string(199, 'a') + "\xC3\xA9" + "tail"), std::string(199, 'a') + "... (205 bytes)")
        << "cut before a character, not inside it";
    EXPECT_LT(json_excerpt(json{{"id", id}}).size(), 240u);
}

}  // namespace
}  // namespace lidarscout
