// LasWriter: header and VLRs first, records as they come (LAZ: whole chunks encoded in
// parallel, written in order, chunk table at the end), EVLRs, then the final header.
#include "laz/laz.hpp"

#include <algorithm>
#include <cstring>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "las/header_writer.hpp"
#include "laz/chunk_encoder.hpp"
#include "laz/chunk_table_writer.hpp"
#include "laz/laszip_vlr_writer.hpp"

namespace lidarscout::laz {

// Cuts records into chunks, encodes whole chunks in parallel and writes them in order.
class LasWriter::Chunks {
public:
    Chunks(io::AtomicOutputFile& out, const las::LaszipVlr& laz, std::size_t record_length, std::uint32_t chunk_size,
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

namespace {

las::Vlr laszip_record(const las::LaszipVlr& laz) {
    las::Vlr v;
    v.user_id = "laszip encoded";
    v.record_id = 22204;
    v.description = "lidarscout LAZ";
    v.data = laz::serialize_laszip_vlr(laz);
    return v;
}

// Sets the offsets and counts that follow from the VLRs; throws when they do not fit.
void place_vlrs(las::Header& h, const std::vector<las::Vlr>& vlrs, const std::string& path) {
    h.number_of_vlrs = static_cast<std::uint32_t>(vlrs.size());
    std::uint64_t offset = h.header_size;
    for (const auto& v : vlrs) offset += 54 + v.data.size();
    if (offset > 0xFFFFFFFFu) throw Error(path, std::nullopt, "VLRs too large for a LAS header");
    h.offset_to_point_data = static_cast<std::uint32_t>(offset);
}

}  // namespace

LasWriter::LasWriter(const std::string& path, las::Header header, std::vector<las::Vlr> vlrs,
                     const LasWriterOptions& options, ThreadPool& pool, std::vector<std::uint8_t> header_trailing,
                     const std::string& protect)
    : header_(std::move(header)),
      header_trailing_(std::move(header_trailing)),
      options_(options),
      out_(path, protect) {
    if (options.compress && options.chunk_size == 0) throw Error("chunk size must be positive");
    for (auto& v : vlrs) {
        if (!v.is("laszip encoded", 22204)) vlrs_.push_back(std::move(v));
    }
    header_.compressed = options.compress;
    if (options.compress) {
        laz_ = laz::make_laszip_vlr(header_.point_format, header_.record_length,
                                    options.variable_chunks ? las::LaszipVlr::kVariableChunkSize : options.chunk_size);
        vlrs_.push_back(laszip_record(laz_));
        chunks_ = std::make_unique<Chunks>(out_, laz_, header_.record_length, options.chunk_size, pool);
    }
    place_vlrs(header_, vlrs_, path);
    las::set_point_count(header_, 0);
    out_.write(las::serialize_header(header_, header_trailing_));
    for (const auto& v : vlrs_) out_.write(las::serialize_vlr(v));
    if (chunks_) {
        table_pointer_at_ = out_.size();
        out_.write(std::vector<std::uint8_t>(8, 0));  // where the chunk table will be
    }
}

LasWriter::~LasWriter() = default;

void LasWriter::add(std::span<const std::uint8_t> records) {
    if (records.size() % header_.record_length != 0) {
        throw Error(out_.target(), std::nullopt, "internal: a partial point record was given to the writer");
    }
    points_ += records.size() / header_.record_length;
    if (chunks_) chunks_->add(records);
    else out_.write(records);
}

LasWriterResult LasWriter::finish(const std::vector<las::Vlr>& evlrs) {
    if (finished_) throw Error(out_.target(), std::nullopt, "internal: the file was already finished");
    finished_ = true;
    LasWriterResult result;
    if (chunks_) {
        chunks_->finish();
        const std::int64_t table_at = static_cast<std::int64_t>(out_.size());
        out_.write(laz::encode_chunk_table(chunks_->chunks(), laz_.variable_chunks()));
        std::uint8_t pointer[8];
        std::memcpy(pointer, &table_at, 8);
        out_.write_at(table_pointer_at_, pointer);
        result.chunks = chunks_->chunks().size();
    }
    header_.number_of_evlrs = static_cast<std::uint32_t>(evlrs.size());
    header_.evlr_offset = evlrs.empty() ? 0 : out_.size();
    for (const auto& v : evlrs) out_.write(las::serialize_vlr(v));
    las::set_point_count(header_, points_);
    out_.write_at(0, las::serialize_header(header_, header_trailing_));
    result.points = points_;
    result.bytes_written = out_.size();
    out_.commit();
    return result;
}

}  // namespace lidarscout::laz
