// convert_tile: plan the output header and records, then stream the records batch by batch
// into a LAS body or into LAZ chunks encoded in parallel.
#include "dataset/tile_writer.hpp"

#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "io/output_file.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"
#include "laz/chunk_encoder.hpp"
#include "laz/chunk_table_writer.hpp"
#include "laz/laszip_vlr_writer.hpp"

namespace lidarscout::dataset {
namespace {

// Everything about the output that is known before the first point is written.
struct OutputPlan {
    las::Header header;
    std::vector<std::uint8_t> header_trailing;  // user bytes after the standard header
    std::vector<las::Vlr> vlrs;
    std::vector<las::Vlr> evlrs;
    std::optional<las::LaszipVlr> laz;
    std::vector<std::string> notes;
};

bool is_copc_record(const las::Vlr& v) { return v.user_id == "copc"; }

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
        throw Error(in.path, std::nullopt, "waveform data packets stored inside the file cannot be carried over");
    }
}

void plan_records(OutputPlan& plan, const io::File& file, const Tile& in, const ConvertOptions& opt) {
    for (const auto& v : in.vlrs) {
        if (v.is("laszip encoded", 22204)) continue;
        if (is_copc_record(v)) {
            plan.notes.push_back("COPC info VLR dropped: the output is not a COPC file");
            continue;
        }
        plan.vlrs.push_back(v);
    }
    for (const auto& v : in.evlrs) {
        if (is_copc_record(v)) {
            plan.notes.push_back("COPC hierarchy EVLR dropped");
            continue;
        }
        las::Vlr e = v;
        e.data = las::vlr_payload(file, v);
        plan.evlrs.push_back(std::move(e));
    }
    if (opt.compress) {
        plan.laz = laz::make_laszip_vlr(plan.header.point_format, plan.header.record_length,
                                        opt.variable_chunks ? las::LaszipVlr::kVariableChunkSize : opt.chunk_size);
        las::Vlr v;
        v.user_id = "laszip encoded";
        v.record_id = 22204;
        v.description = "lidarscout LAZ";
        v.data = laz::serialize_laszip_vlr(*plan.laz);
        plan.vlrs.push_back(std::move(v));
    }
}

OutputPlan plan_output(const io::File& file, const Tile& in, const ConvertOptions& opt) {
    OutputPlan plan;
    plan.header = in.header;
    const auto standard = las::standard_header_size(in.header.version_major, in.header.version_minor);
    if (in.header.header_size > standard) plan.header_trailing = file.read_vector(standard, in.header.header_size - standard, "header");
    plan_format(plan, in, opt);
    plan_records(plan, file, in, opt);
    auto& h = plan.header;
    h.compressed = opt.compress;
    h.number_of_vlrs = static_cast<std::uint32_t>(plan.vlrs.size());
    h.number_of_evlrs = static_cast<std::uint32_t>(plan.evlrs.size());
    std::uint64_t offset = h.header_size;
    for (const auto& v : plan.vlrs) offset += 54 + v.data.size();
    if (offset > 0xFFFFFFFFu) throw Error(in.path, std::nullopt, "VLRs too large for a LAS header");
    h.offset_to_point_data = static_cast<std::uint32_t>(offset);
    las::set_point_count(h, in.header.point_count);
    if (plan.evlrs.empty()) h.evlr_offset = 0;
    return plan;
}

void write_head(io::AtomicOutputFile& out, const OutputPlan& plan) {
    out.write(las::serialize_header(plan.header, plan.header_trailing));
    for (const auto& v : plan.vlrs) out.write(las::serialize_vlr(v));
}

// Appends the EVLRs and patches the EVLR offset in the header.
void write_tail(io::AtomicOutputFile& out, OutputPlan& plan) {
    if (plan.evlrs.empty()) return;
    plan.header.evlr_offset = out.size();
    for (const auto& v : plan.evlrs) out.write(las::serialize_vlr(v));
    out.write_at(0, las::serialize_header(plan.header, plan.header_trailing));
}

// Converts a batch of input records to the output format (a copy when nothing changes).
std::span<const std::uint8_t> to_output_format(std::span<const std::uint8_t> records, const Tile& in, const OutputPlan& plan,
                                              std::vector<std::uint8_t>& buf) {
    if (in.header.point_format == plan.header.point_format && in.header.record_length == plan.header.record_length) {
        return records;
    }
    const std::size_t n = records.size() / in.header.record_length;
    buf.resize(n * plan.header.record_length);
    las::convert_records(records, las::point_format_info(in.header.point_format), in.header.record_length, buf,
                         las::point_format_info(plan.header.point_format), plan.header.record_length, in.header);
    return buf;
}

// Cuts records into chunks, encodes whole chunks in parallel and writes them in order.
class ChunkWriter {
public:
    ChunkWriter(io::AtomicOutputFile& out, const las::LaszipVlr& laz, std::size_t record_length, std::uint32_t chunk_size,
                ThreadPool& pool)
        : out_(out), laz_(laz), record_(record_length), chunk_size_(chunk_size), pool_(pool) {}

    void add(std::span<const std::uint8_t> records) {
        pending_.insert(pending_.end(), records.begin(), records.end());
        const std::size_t full = pending_.size() / (record_ * chunk_size_);
        if (full > 0) flush_chunks(full * chunk_size_);
    }
    void finish() {
        if (!pending_.empty()) flush_chunks(pending_.size() / record_);
    }
    const std::vector<laz::Chunk>& chunks() const { return chunks_; }

private:
    void flush_chunks(std::size_t points) {
        const std::size_t count = (points + chunk_size_ - 1) / chunk_size_;
        std::vector<std::vector<std::uint8_t>> encoded(count);
        pool_.for_each(count, [&](std::size_t k) {
            const std::size_t first = k * chunk_size_;
            const std::size_t n = std::min<std::size_t>(chunk_size_, points - first);
            laz::encode_chunk(laz_, std::span(pending_).subspan(first * record_, n * record_), n, encoded[k]);
        });
        for (std::size_t k = 0; k < count; ++k) {
            const std::size_t n = std::min<std::size_t>(chunk_size_, points - k * chunk_size_);
            chunks_.push_back({next_point_, n, out_.size(), encoded[k].size()});
            next_point_ += n;
            out_.write(encoded[k]);
        }
        pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(points * record_));
    }

    io::AtomicOutputFile& out_;
    const las::LaszipVlr& laz_;
    std::size_t record_;
    std::uint32_t chunk_size_;
    ThreadPool& pool_;
    std::vector<std::uint8_t> pending_;
    std::vector<laz::Chunk> chunks_;
    std::uint64_t next_point_ = 0;
};

}  // namespace

ConvertResult convert_tile(const std::string& in_path, const std::string& out_path, const ConvertOptions& opt,
                           ThreadPool& pool, const ConvertProgressFn& progress) {
    if (opt.chunk_size == 0) throw Error("chunk size must be positive");
    auto file = io::File::open(in_path);
    const Tile in = read_tile(file);
    OutputPlan plan = plan_output(file, in, opt);
    io::AtomicOutputFile out(out_path, in_path);
    write_head(out, plan);

    ConvertResult result;
    result.notes = plan.notes;
    std::vector<std::uint8_t> converted;
    const std::uint64_t batch = std::max<std::uint64_t>(1u << 20, std::uint64_t{opt.chunk_size} * pool.size() * 2);
    if (plan.laz) {
        const std::uint64_t table_pointer_at = out.size();
        out.write(std::vector<std::uint8_t>(8, 0));
        ChunkWriter chunks(out, *plan.laz, plan.header.record_length, opt.chunk_size, pool);
        for_each_record_batch(file, in, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
            chunks.add(to_output_format(records, in, plan, converted));
            if (progress) progress(first + records.size() / in.header.record_length);
        }, laz::fields::kAll, batch);
        chunks.finish();
        const std::int64_t table_at = static_cast<std::int64_t>(out.size());
        out.write(laz::encode_chunk_table(chunks.chunks(), plan.laz->variable_chunks()));
        std::uint8_t pointer[8];
        std::memcpy(pointer, &table_at, 8);
        out.write_at(table_pointer_at, pointer);
        result.chunks = chunks.chunks().size();
    } else {
        for_each_record_batch(file, in, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
            out.write(to_output_format(records, in, plan, converted));
            if (progress) progress(first + records.size() / in.header.record_length);
        }, laz::fields::kAll, batch);
    }
    write_tail(out, plan);
    result.points = in.header.point_count;
    result.bytes_written = out.size();
    out.commit();
    return result;
}

}  // namespace lidarscout::dataset
