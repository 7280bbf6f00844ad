// write_training_data: one streaming pass per dataset (all texel sizes at once), then per
// usable patch the nearest and linear inputs and the ground truth, appended as fixed-size
// records; the JSON metadata goes last and the preamble is patched at the end.
#include "pipelines/training_data.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/random.hpp"
#include "dataset/dataset.hpp"
#include "io/output_file.hpp"
#include "recon/methods.hpp"
#include "pipelines/survey_samples.hpp"

namespace lidarscout::pipelines {
namespace {

// IEEE 754 binary16 from binary32, rounding to nearest even; NaN stays NaN.
std::uint16_t to_half(float f) {
    std::uint32_t x;
    std::memcpy(&x, &f, 4);
    const std::uint16_t sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
    const std::uint32_t abs = x & 0x7FFFFFFFu;
    if (abs > 0x7F800000u) return sign | 0x7E00u;                   // NaN
    if (abs >= 0x477FF000u) return sign | 0x7C00u;                  // overflow (>= 65520) -> inf
    if (abs < 0x38800000u) {                                        // subnormal half (or zero)
        const float scaled = std::fabs(f) * 16777216.0f;            // 2^24: units of the smallest subnormal
        return sign | static_cast<std::uint16_t>(std::nearbyint(scaled));
    }
    const std::uint32_t rounded = abs + 0x0FFFu + ((abs >> 13) & 1u);  // round to nearest even
    return sign | static_cast<std::uint16_t>((rounded - 0x38000000u) >> 13);
}

std::uint8_t to_byte(float v) {
    if (std::isnan(v)) return 0;
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// Field sizes of one record for a spec (see the header for the layout).
struct RecordLayout {
    int w = 96, p = 64;
    std::size_t height_in() const { return 2u * w * w * 2; }
    std::size_t rgb_in() const { return 6u * w * w; }
    std::size_t height_gt() const { return std::size_t(p) * p * 2; }
    std::size_t rgb_gt() const { return 3u * p * p; }
    std::size_t mask() const { return std::size_t(p) * p; }
    std::size_t size() const { return height_in() + rgb_in() + height_gt() + rgb_gt() + mask() + 2; }
    nlohmann::json fields() const {
        return nlohmann::json::array({{"height_in", "<f2", {2, w, w}},
                                      {"rgb_in", "u1", {6, w, w}},
                                      {"height_gt", "<f2", {p, p}},
                                      {"rgb_gt", "u1", {3, p, p}},
                                      {"mask", "u1", {p, p}},
                                      {"has_rgb", "u1", nlohmann::json::array()},
                                      {"split", "u1", nlohmann::json::array()}});
    }
};

class RecordWriter {
public:
    explicit RecordWriter(std::vector<std::uint8_t>& out) : out_(out) {}
    void halves(std::span<const float> v) {
        for (float f : v) put16(to_half(f));
    }
    void bytes(std::span<const float> v) {
        for (float f : v) out_.push_back(to_byte(f));
    }
    void byte(std::uint8_t b) { out_.push_back(b); }

private:
    void put16(std::uint16_t h) {
        out_.push_back(static_cast<std::uint8_t>(h & 0xFF));
        out_.push_back(static_cast<std::uint8_t>(h >> 8));
    }
    std::vector<std::uint8_t>& out_;
};

const std::string& nearest_tile(const dataset::Dataset& ds, double x, double y) {
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        const double d = ds.tiles[i].bounds_m.distance_xy(x, y);
        if (d < best_d) best_d = d, best = i;
    }
    return ds.tiles[best].tile.path();
}

struct Writer {
    io::AtomicOutputFile& out;
    nlohmann::json samples = nlohmann::json::array();
    TrainingDataSummary summary;
    std::vector<std::uint8_t> record;
};

void write_record(Writer& w, const PatchPoints& pp, const std::vector<Reconstruction>& rec, const GroundTruth& truth,
                  std::size_t index, bool has_rgb, int split) {
    const int p = pp.spec.patch_texels;
    w.record.clear();
    RecordWriter r(w.record);
    r.halves(rec[0].height.values);
    r.halves(rec[1].height.values);
    r.bytes(rec[0].rgb.values);
    r.bytes(rec[1].rgb.values);
    Image gt_h = truth.height_m(index);
    for (auto& v : gt_h.values) v = std::isnan(v) ? v : static_cast<float>(pp.normalise(v));
    r.halves(gt_h.values);
    r.bytes(truth.rgb(index).values);
    for (float v : gt_h.values) r.byte(std::isnan(v) ? 0 : 1);
    r.byte(has_rgb ? 1 : 0);
    r.byte(static_cast<std::uint8_t>(split));
    if (w.record.size() != RecordLayout{pp.size(), p}.size()) {
        throw Error("training data: record size mismatch (internal error)");
    }
    w.out.write(w.record);
}

void write_dataset(Writer& w, const NamedDataset& nd, const TrainingDataOptions& o, ThreadPool& pool,
                   const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    const dataset::Dataset& ds = *nd.dataset;
    std::vector<SampleRequest> requests;
    for (double texel : o.texels_m) {
        PatchSpec spec;
        spec.texel_m = texel;
        for (const Lattice& l : offset_lattices(lattice_for(ds, spec), o.offsets)) {
            requests.push_back(
                {l, o.stride.value_or(auto_stride(ds, spec)), candidate_patches(ds, l, 2 * o.patches + 10, o.seed)});
        }
    }
    const SurveySamples samples = sample_survey(ds, requests, pool, progress);
    const RegionSplit split(o.split, nd.name);
    const Method methods[] = {Method::Nearest, Method::Linear};
    for (std::size_t r = 0; r < requests.size(); ++r) {
        const auto& s = samples.samples[r];
        const PatchSpec& spec = s.lattice.spec;
        const double texels = double(spec.patch_texels) * spec.patch_texels;
        std::size_t used = 0;
        for (std::size_t i = 0; i < requests[r].patches.size() && used < o.patches; ++i) {
            const PatchPoints pp =
                make_patch_points(*s.chunk_points, requests[r].patches[i], {spec, o.min_points, samples.has_rgb});
            if (pp.status != PatchStatus::Ok || s.truth->covered_texels(i) < o.min_coverage * texels) continue;
            const double cx = pp.window_min_x + spec.radius_m(), cy = pp.window_min_y + spec.radius_m();
            const Split which = split.of_window(cx, cy, pp.window_min_x, pp.window_min_y,
                                                pp.window_min_x + spec.window_m(), pp.window_min_y + spec.window_m());
            if (which == Split::Border) {
                ++w.summary.dropped_at_split_border;
                continue;
            }
            write_record(w, pp, reconstruct(pp, methods), *s.truth, i, samples.has_rgb, static_cast<int>(which));
            w.samples.push_back({{"dataset", nd.name},
                                 {"tile", nearest_tile(ds, cx, cy)},
                                 {"centre_x", cx},
                                 {"centre_y", cy},
                                 {"texel_m", spec.texel_m},
                                 {"centre_z", pp.centre_z},
                                 {"radius_m", spec.radius_m()},
                                 {"stride", s.stride},
                                 {"split", static_cast<int>(which)}});
            ++(which == Split::Validation ? w.summary.validation : w.summary.train);
            ++used;
        }
    }
}

std::vector<std::uint8_t> preamble(std::uint64_t records_offset, std::uint64_t record_size, std::uint64_t count,
                                   std::uint64_t meta_offset, std::uint64_t meta_length) {
    std::vector<std::uint8_t> out(48);
    std::memcpy(out.data(), kTrainingMagic, 8);
    const std::uint64_t v[5] = {records_offset, record_size, count, meta_offset, meta_length};
    for (int i = 0; i < 5; ++i) {
        for (int b = 0; b < 8; ++b) out[8 + 8 * i + b] = static_cast<std::uint8_t>(v[i] >> (8 * b));
    }
    return out;
}

}  // namespace

TrainingDataSummary write_training_data(
    const std::vector<NamedDataset>& datasets, const TrainingDataOptions& o, const std::string& out_path,
    ThreadPool& pool, const std::function<void(std::size_t, std::uint64_t, std::uint64_t)>& progress) {
    if (o.texels_m.empty()) throw Error("training data: no texel size given");
    o.split.validate();
    if (o.offsets < 1) throw Error("training data: offsets must be at least 1");
    io::AtomicOutputFile out(out_path);
    constexpr std::uint64_t kRecordsOffset = 64;
    out.write(std::vector<std::uint8_t>(kRecordsOffset, 0));
    Writer w{out, nlohmann::json::array(), {}, {}};
    for (std::size_t d = 0; d < datasets.size(); ++d) {
        write_dataset(w, datasets[d], o, pool, [&](std::uint64_t done, std::uint64_t total) {
            if (progress) progress(d, done, total);
        });
    }
    if (w.samples.empty()) {
        throw Error::in_stage("training data", "no sample in " + std::to_string(datasets.size()) +
                                                   " dataset(s) (" + std::to_string(w.summary.dropped_at_split_border) +
                                                   " dropped at split borders; patches need enough chunk points and "
                                                   "ground truth at each --texel); nothing written");
    }
    const RecordLayout layout;  // the default 96 / 64 texels (PatchSpec defaults)
    const nlohmann::json meta = {
        {"format", "lidarscout-train"},
        {"version", 1},
        {"fields", layout.fields()},
        {"samples", w.samples},
        {"normalisation", "h' = (z - centre_z) / radius_m; colours 0..255; see src/recon/patch_space.hpp"}};
    const std::string text = meta.dump();
    const std::uint64_t meta_offset = out.size();
    out.write(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    const std::uint64_t count = w.samples.size();
    out.write_at(0, preamble(kRecordsOffset, layout.size(), count, meta_offset, text.size()));
    w.summary.samples = count;
    w.summary.bytes = out.size();
    out.commit();
    return w.summary;
}

}  // namespace lidarscout::pipelines
