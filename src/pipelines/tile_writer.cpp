// convert_tile: plan the output header and records, then stream the records batch by batch
// through a LasWriter (LAS body, or LAZ chunks encoded in parallel).
#include "pipelines/tile_writer.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "laz/laz.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "geo/projection.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"
#include "pipelines/output_records.hpp"

namespace lidarscout::pipelines {

using dataset::for_each_record_batch;
using dataset::read_tile;
using dataset::Tile;
using laz::LasWriter;
using laz::LasWriterOptions;
using laz::LasWriterResult;

namespace {

// Everything about the output that is known before the first point is written.
struct OutputPlan {
    las::Header header;
    std::vector<std::uint8_t> header_trailing;  // user bytes after the standard header
    std::vector<las::Vlr> vlrs;                 // without the LASzip VLR (the writer adds its own)
    std::vector<las::Vlr> evlrs;
    std::vector<std::string> notes;
    std::vector<std::string> warnings;
};

void plan_format(OutputPlan& plan, const Tile& in, const ConvertOptions& opt) {
    auto& h = plan.header;
    const auto& in_fmt = las::point_format_info(in.header.point_format);
    const std::uint8_t format = opt.point_format.value_or(in.header.point_format);
    const auto& out_fmt = las::point_format_info(format);
    const std::uint16_t extra = static_cast<std::uint16_t>(in.header.record_length - in_fmt.size);
    h.point_format = format;
    h.record_length = static_cast<std::uint16_t>(out_fmt.size + extra);
    if (out_fmt.extended && !h.at_least(1, 4)) {
        h.version_minor = 4;
        h.header_size = las::standard_header_size(1, 4);
        plan.header_trailing.clear();
        plan.notes.push_back("header upgraded to LAS 1.4 for point format " + std::to_string(format));
    }
    if ((out_fmt.wave_offset >= 0 || in_fmt.wave_offset >= 0) && (in.header.global_encoding & 2)) {
        throw Error(in.path(), std::nullopt, "waveform data packets stored inside the file cannot be carried over");
    }
}

void plan_records(OutputPlan& plan, const io::File& file, const Tile& in) {
    for (const auto& v : in.vlrs()) {
        if (v.is("laszip encoded", 22204)) continue;
        if (is_copc_record(v)) {
            plan.notes.push_back("COPC info VLR dropped: the output is not a COPC file");
            continue;
        }
        plan.vlrs.push_back(v);
    }
    for (const auto& v : in.evlrs()) {
        if (is_copc_record(v)) {
            plan.notes.push_back("COPC hierarchy EVLR dropped");
            continue;
        }
        las::Vlr e = v;
        e.data = las::vlr_payload(file, v);
        plan.evlrs.push_back(std::move(e));
    }
}

// The CRS stated once, in the form the output's point format expects (pipelines/output_records.hpp):
// GeoTIFF keys become WKT for point formats 6-10 (LAS 1.4 requires it); a CRS PROJ cannot write as WKT
// is refused unless forced (then the keys stay, with a warning).
void plan_crs(OutputPlan& plan, const Tile& in, const ConvertOptions& opt) {
    auto& h = plan.header;
    std::string forced;
    const std::vector<std::string> notes =
        keep_crs_or_keys(h, plan.vlrs, plan.evlrs, in.crs(), "convert", in.path(), opt.force, forced);
    if (!forced.empty()) {
        plan.warnings.push_back(forced);
        return;
    }
    plan.notes.insert(plan.notes.end(), notes.begin(), notes.end());
    const bool rewritten = in.crs().source == "geotiff" && (h.global_encoding & 0x10);
    const std::string fallback = geo::vertical_fallback_message(in.crs());
    if (rewritten && !fallback.empty()) plan.warnings.push_back(fallback + "; the WKT names the horizontal CRS alone");
}

OutputPlan plan_output(const io::File& file, const Tile& in, const ConvertOptions& opt) {
    OutputPlan plan;
    plan.header = in.header;
    const auto standard = las::standard_header_size(in.header.version_major, in.header.version_minor);
    if (in.header.header_size > standard) {
        plan.header_trailing = file.read_vector(standard, in.header.header_size - standard, "header");
    }
    plan_format(plan, in, opt);
    plan_records(plan, file, in);
    plan_crs(plan, in, opt);
    return plan;
}

// Converts a batch of input records to the output format (a copy when nothing changes),
// counting what the format cannot hold.
std::span<const std::uint8_t> to_output_format(std::span<const std::uint8_t> records, const Tile& in,
                                               const OutputPlan& plan, std::vector<std::uint8_t>& buf,
                                               las::FormatLosses& losses) {
    if (in.header.point_format == plan.header.point_format && in.header.record_length == plan.header.record_length) {
        return records;
    }
    const std::size_t n = records.size() / in.header.record_length;
    buf.resize(n * plan.header.record_length);
    las::convert_records(records, las::point_format_info(in.header.point_format), in.header.record_length, buf,
                         las::point_format_info(plan.header.point_format), plan.header.record_length, in.header,
                         &losses);
    return buf;
}

// Refuses the conversion when values were lost, unless forced (then a warning).
void check_losses(const las::FormatLosses& losses, const OutputPlan& plan, const std::string& in_path, bool force,
                  ConvertResult& result) {
    if (losses.total() == 0) return;
    const std::string what = "point format " + std::to_string(plan.header.point_format) + " cannot hold " +
                             losses.describe();
    if (!force) throw Error(in_path, std::nullopt, what + "; nothing written (--force writes them so)");
    result.warnings.push_back(what);
}

// Points per slice of a batch given to the writer: the progress moves after each (a batch of
// one-point chunks would otherwise be encoded in one silent step).
constexpr std::uint64_t kSlicePoints = 65'536;

}  // namespace

bool wants_laz(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".laz") return true;
    if (ext == ".las") return false;
    throw Error(path, std::nullopt, "output must end in .las or .laz");
}

ConvertResult convert_tile(const std::string& in_path, const std::string& out_path, const ConvertOptions& opt,
                           ThreadPool& pool, const ConvertProgressFn& progress) {
    if (opt.chunk_size == 0) throw Error("chunk size must be positive");
    auto file = io::File::open(in_path);
    const Tile in = read_tile(file);
    OutputPlan plan = plan_output(file, in, opt);
    const LasWriterOptions write{opt.compress, opt.chunk_size, opt.variable_chunks};
    LasWriter writer(out_path, plan.header, plan.vlrs, write, pool, plan.header_trailing, in_path);

    std::vector<std::uint8_t> converted;
    las::FormatLosses losses;
    const std::uint64_t batch = std::max<std::uint64_t>(1u << 20, std::uint64_t{opt.chunk_size} * pool.size() * 2);
    const std::size_t record = in.header.record_length;
    const std::size_t slice = std::max<std::uint64_t>(kSlicePoints, opt.chunk_size) * record;
    for_each_record_batch(file, in, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
        for (std::size_t at = 0; at < records.size(); at += slice) {
            const auto part = records.subspan(at, std::min(slice, records.size() - at));
            writer.add(to_output_format(part, in, plan, converted, losses));
            if (progress) progress(first + (at + part.size()) / record);
        }
    }, las::fields::kAll, batch);
    if (writer.points() != in.header.point_count) {
        throw Error(in_path, std::nullopt, "internal: the records read do not match the header's point count");
    }
    ConvertResult result;
    check_losses(losses, plan, in_path, opt.force, result);
    const LasWriterResult written = writer.finish(plan.evlrs);
    result.notes = plan.notes;
    result.warnings.insert(result.warnings.end(), plan.warnings.begin(), plan.warnings.end());
    result.points = written.points;
    result.bytes_written = written.bytes_written;
    result.chunks = written.chunks;
    return result;
}

}  // namespace lidarscout::pipelines
