// JSON documents read from a file or URL (through io::File) by the bounded reader
// (core/json_reader.hpp), chunk by chunk: what the dataset stage's JSON inputs (EPT metadata and
// hierarchies, STAC catalogs, replica manifests) and the viewer's sessions share.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "core/json_reader.hpp"
#include "io/file.hpp"

namespace lidarscout::dataset {

// A source reading `file` from its start, in the chunks asked (the file must outlive it).
JsonSource file_json_source(const io::File& file);

// The document in `file`, of at most limits.max_bytes (its size checked before reading), read
// within `limits`. Throws lidarscout::Error naming the file (too large, not JSON, a limit passed).
nlohmann::json read_json_file(const io::File& file, const JsonLimits& limits,
                              const JsonStreaming* streaming = nullptr);

// The same where the document must be a JSON object ("not a JSON object" otherwise).
nlohmann::json read_json_object(const io::File& file, const JsonLimits& limits,
                                const JsonStreaming* streaming = nullptr);
// A JSON object of at most `max_bytes`, within the reader's default depth and string limits, the
// values it holds bounded by its size only (EPT metadata and hierarchies).
nlohmann::json read_json_object(const io::File& file, std::uint64_t max_bytes);

// A remote document's first blocks asked for before its reader comes (the viewer's window opens meanwhile: a
// country's catalog was not asked for until that had taken a fifth of a second): the reader of the same URL
// takes them, read or in flight. Local paths: nothing. A failed early open is no error (the reader's own
// open says why).
void prefetch_json_document(const std::string& url);
// Drops what prefetch_json_document asked for where no reader took it.
void forget_json_prefetch();

}  // namespace lidarscout::dataset
