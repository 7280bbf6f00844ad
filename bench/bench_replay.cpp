// Benchmark: how much of a LAZ decode is the arithmetic decoding itself. In two steps:
//   --record T: decodes FILE once on one thread and writes to T every stream its arithmetic
//     decoders start and every symbol, bit and raw field they decode (laz/decode_trace.hpp;
//     needs a build configured with -DLIDARSCOUT_LAZ_TRACE=ON);
//   --trace T: in a default build (no hooks in the decoder), times the full decode of FILE and
//     replays T alone: the same streams, calls and models in the same order (fresh models in
//     their start state, as at a chunk's start), without the item decoders that choose the
//     models and turn symbols into fields; the replay with two and with four streams stepped
//     in turn in one loop (what interleaving chunks could gain at best); and the replay with
//     every value known in advance (no search: the floor under any way of searching). Every
//     replayed value is checked against the recorded one before the timing.
// Usage: bench_replay FILE.laz --record T | --trace T [--runs N]
#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "io/output_file.hpp"
#include "laz/arithmetic_decoder.hpp"
#include "laz/laz.hpp"

using namespace lidarscout;

namespace {

enum class OpKind : std::uint32_t { Symbol, Bit, Raw, LikelySymbol };  // LikelySymbol: decode_likely_symbol

bool is_symbol(OpKind k) { return k == OpKind::Symbol || k == OpKind::LikelySymbol; }

// One recorded decoder call: the model (an index into the stream's own models) or the raw width.
struct Op {
    OpKind kind;
    std::uint32_t arg;  // model index, or raw bits
    std::uint32_t result;
};

// One arithmetic-coded stream (a chunk, or a layer of one) and the calls made on it.
struct RecordedStream {
    std::vector<std::uint8_t> bytes;
    std::vector<Op> ops;
    std::map<const void*, std::uint32_t> model_index;  // recorded model -> index
    std::vector<std::uint32_t> model_symbols;           // per index: alphabet size, 0 for a bit model
};

// Collects the streams and calls of every decoder, one thread at a time.
class Recorder final : public laz::DecodeTraceSink {
public:
    std::vector<RecordedStream> streams;

    void on_start(Stream stream) override {
        current_[key(stream)] = streams.size();
        streams.push_back({{stream.begin(), stream.end()}, {}, {}, {}});
    }
    void on_symbol(Stream stream, laz::SymbolModel& model, std::uint32_t symbol, bool likely) override {
        auto& s = streams[current_.at(key(stream))];
        const OpKind kind = likely ? OpKind::LikelySymbol : OpKind::Symbol;
        s.ops.push_back({kind, index_of(s, &model, model.symbols()), symbol});
    }
    void on_bit(Stream stream, laz::BitModel& model, std::uint32_t bit) override {
        auto& s = streams[current_.at(key(stream))];
        s.ops.push_back({OpKind::Bit, index_of(s, &model, 0), bit});
    }
    void on_raw(Stream stream, std::uint32_t bits, std::uint32_t value) override {
        streams[current_.at(key(stream))].ops.push_back({OpKind::Raw, bits, value});
    }

private:
    static std::uint32_t index_of(RecordedStream& s, const void* model, std::uint32_t symbols) {
        const auto [it, added] = s.model_index.try_emplace(model, static_cast<std::uint32_t>(s.model_symbols.size()));
        if (added) s.model_symbols.push_back(symbols);
        return it->second;
    }
    static std::pair<const void*, std::size_t> key(Stream s) { return {s.data(), s.size()}; }
    std::map<std::pair<const void*, std::size_t>, std::size_t> current_;  // a stream's latest start
};

// ---- The trace file: little-endian u32 words. The recorded file's point count (low word first)
// and a stream count, then per stream: its byte count and
// bytes (padded to 4), its model count and each model's alphabet (0: bit model), its call count
// and per call (kind << 30 | model index or raw bits, result).
class TraceWriter {
public:
    explicit TraceWriter(io::AtomicOutputFile& out) : out_(out) {}
    void word(std::uint32_t v) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        buffer_.insert(buffer_.end(), p, p + 4);
        flush_if_full();
    }
    void bytes(std::span<const std::uint8_t> b) {
        word(static_cast<std::uint32_t>(b.size()));
        buffer_.insert(buffer_.end(), b.begin(), b.end());
        buffer_.resize((buffer_.size() + 3) / 4 * 4, 0);
        flush_if_full();
    }
    void flush() { out_.write(buffer_); buffer_.clear(); }

private:
    void flush_if_full() {
        if (buffer_.size() > (1u << 20)) flush();
    }
    io::AtomicOutputFile& out_;
    std::vector<std::uint8_t> buffer_;
};

void write_trace(const std::vector<RecordedStream>& streams, std::uint64_t points, const std::string& path,
                 const std::string& input) {
    io::AtomicOutputFile out(path, input);
    TraceWriter w(out);
    w.word(static_cast<std::uint32_t>(points));
    w.word(static_cast<std::uint32_t>(points >> 32));
    w.word(static_cast<std::uint32_t>(streams.size()));
    for (const RecordedStream& s : streams) {
        w.bytes(s.bytes);
        w.word(static_cast<std::uint32_t>(s.model_symbols.size()));
        for (std::uint32_t m : s.model_symbols) w.word(m);
        w.word(static_cast<std::uint32_t>(s.ops.size()));
        for (const Op& op : s.ops) {
            w.word(static_cast<std::uint32_t>(op.kind) << 30 | op.arg);
            w.word(op.result);
        }
    }
    w.flush();
    out.commit();
}

class TraceReader {
public:
    explicit TraceReader(const std::string& path) : file_(io::File::open(path)), data_(file_.size()) {
        if (file_.read_at(0, data_) != data_.size()) throw Error(path, 0, "short read");
    }
    std::uint32_t word() {
        if (at_ + 4 > data_.size()) throw Error(file_.path(), at_, "trace ends early");
        std::uint32_t v;
        std::memcpy(&v, data_.data() + at_, 4);
        at_ += 4;
        return v;
    }
    std::vector<std::uint8_t> bytes() {
        const std::size_t n = word();
        if (at_ + n > data_.size()) throw Error(file_.path(), at_, "trace ends early");
        std::vector<std::uint8_t> b(data_.begin() + static_cast<std::ptrdiff_t>(at_),
                                    data_.begin() + static_cast<std::ptrdiff_t>(at_ + n));
        at_ += (n + 3) / 4 * 4;
        return b;
    }

private:
    io::File file_;
    std::vector<std::uint8_t> data_;
    std::size_t at_ = 0;
};

// The trace's streams; refuses one recorded from a file of another point count than `points`.
std::vector<RecordedStream> read_trace(const std::string& path, std::uint64_t points) {
    TraceReader r(path);
    std::uint64_t recorded = r.word();
    recorded |= std::uint64_t{r.word()} << 32;
    if (recorded != points) {
        throw Error(path, 0, "recorded from a file of " + std::to_string(recorded) + " points, not this one's " +
                                 std::to_string(points));
    }
    std::vector<RecordedStream> streams(r.word());
    for (RecordedStream& s : streams) {
        s.bytes = r.bytes();
        s.model_symbols.resize(r.word());
        for (std::uint32_t& m : s.model_symbols) {
            m = r.word();
            if (m == 1 || m > laz::kMaxSymbols) throw Error(path, 0, "bad model size in the trace");
        }
        s.ops.resize(r.word());
        for (Op& op : s.ops) {
            const std::uint32_t head = r.word();
            op = {static_cast<OpKind>(head >> 30), head & 0x3FFFFFFFu, r.word()};
            if (op.kind != OpKind::Raw && op.arg >= s.model_symbols.size()) throw Error(path, 0, "bad model index");
            if (is_symbol(op.kind) != (op.kind != OpKind::Raw && s.model_symbols[op.arg] != 0)) {
                throw Error(path, 0, "a call does not match its model's kind");
            }
            if (op.kind == OpKind::Raw && (op.arg < 1 || op.arg > 19)) throw Error(path, 0, "bad raw width");
            const std::uint64_t values = is_symbol(op.kind) ? s.model_symbols[op.arg]
                                         : op.kind == OpKind::Bit  ? 2u
                                                                   : std::uint64_t{1} << op.arg;
            if (op.result >= values) throw Error(path, 0, "a recorded value outside its alphabet");
        }
    }
    return streams;
}

// A stream's models for replaying, in their start state.
struct ReplayModels {
    std::vector<laz::SymbolModel> symbol_models;
    std::vector<laz::BitModel> bit_models;
    std::vector<std::uint32_t> slot;  // model index -> index into its vector

    explicit ReplayModels(const RecordedStream& s) {
        for (std::uint32_t symbols : s.model_symbols) {
            if (symbols == 0) {
                slot.push_back(static_cast<std::uint32_t>(bit_models.size()));
                bit_models.emplace_back();
            } else {
                slot.push_back(static_cast<std::uint32_t>(symbol_models.size()));
                symbol_models.emplace_back(symbols);
            }
        }
    }
    void reset() {
        for (auto& m : symbol_models) m.reset();
        for (auto& m : bit_models) m.reset();
    }
};

// The recorded ops with their models resolved, ready to run back to back.
struct ReplayOp {
    OpKind kind;
    std::uint32_t bits;
    void* model;
    std::uint32_t result;
};

std::vector<ReplayOp> resolve(const RecordedStream& s, ReplayModels& models) {
    std::vector<ReplayOp> out;
    out.reserve(s.ops.size());
    for (const Op& op : s.ops) {
        void* model = nullptr;
        if (is_symbol(op.kind)) model = &models.symbol_models[models.slot[op.arg]];
        if (op.kind == OpKind::Bit) model = &models.bit_models[models.slot[op.arg]];
        out.push_back({op.kind, op.kind == OpKind::Raw ? op.arg : 0u, model, op.result});
    }
    return out;
}

// The call with its value known in advance: no search (the floor under any way of searching).
inline void take_op(laz::ArithmeticDecoder& dec, const ReplayOp& op) {
    if (is_symbol(op.kind)) [[likely]] {
        dec.take_known_symbol(*static_cast<laz::SymbolModel*>(op.model), op.result);
    } else if (op.kind == OpKind::Bit) {
        dec.take_known_bit(*static_cast<laz::BitModel*>(op.model), op.result);
    } else {
        dec.take_known_raw(op.bits, op.result);
    }
}

inline std::uint32_t replay_op(laz::ArithmeticDecoder& dec, const ReplayOp& op) {
    if (op.kind == OpKind::Symbol) [[likely]] return dec.decode_symbol(*static_cast<laz::SymbolModel*>(op.model));
    if (op.kind == OpKind::LikelySymbol) return dec.decode_likely_symbol(*static_cast<laz::SymbolModel*>(op.model));
    if (op.kind == OpKind::Bit) return dec.decode_bit(*static_cast<laz::BitModel*>(op.model));
    return dec.read_bits(op.bits);
}

struct Replay {
    std::vector<RecordedStream> streams;
    std::vector<std::unique_ptr<ReplayModels>> models;
    std::vector<std::vector<ReplayOp>> ops;

    void reset() {
        for (auto& m : models) m->reset();
    }

    // Every stream once, in order, each value against the recorded one (untimed).
    void check() {
        for (std::size_t i = 0; i < ops.size(); ++i) {
            laz::ArithmeticDecoder dec(streams[i].bytes);
            for (const ReplayOp& op : ops[i]) {
                if (replay_op(dec, op) != op.result) throw Error("replay of stream " + std::to_string(i) + " differs");
            }
        }
    }

    // Every stream once, each value taken as known; returns the bytes consumed (to keep the work).
    std::uint64_t run_known() {
        std::uint64_t consumed = 0;
        for (std::size_t i = 0; i < ops.size(); ++i) {
            laz::ArithmeticDecoder dec(streams[i].bytes);
            for (const ReplayOp& op : ops[i]) take_op(dec, op);
            consumed += dec.bytes_consumed();
        }
        return consumed;
    }

    // Streams two or four at a time, one call of each in turn (what interleaving chunks could
    // gain): the decoders are named locals, so that the compiler can keep their state in registers.
    std::uint64_t run_one(laz::ArithmeticDecoder& dec, std::size_t stream, std::size_t from) {
        std::uint64_t sum = 0;
        for (std::size_t k = from; k < ops[stream].size(); ++k) sum += replay_op(dec, ops[stream][k]);
        return sum;
    }
    std::uint64_t run_paired() {
        std::uint64_t sum = 0;
        std::size_t i = 0;
        for (; i + 2 <= ops.size(); i += 2) {
            laz::ArithmeticDecoder a(streams[i].bytes), b(streams[i + 1].bytes);
            const auto &oa = ops[i], &ob = ops[i + 1];
            const std::size_t both = std::min(oa.size(), ob.size());
            for (std::size_t k = 0; k < both; ++k) sum += replay_op(a, oa[k]) + replay_op(b, ob[k]);
            sum += run_one(a, i, both) + run_one(b, i + 1, both);
        }
        return sum + run_rest(i);
    }
    std::uint64_t run_four() {
        std::uint64_t sum = 0;
        std::size_t i = 0;
        for (; i + 4 <= ops.size(); i += 4) {
            laz::ArithmeticDecoder a(streams[i].bytes), b(streams[i + 1].bytes);
            laz::ArithmeticDecoder c(streams[i + 2].bytes), d(streams[i + 3].bytes);
            const auto &oa = ops[i], &ob = ops[i + 1], &oc = ops[i + 2], &od = ops[i + 3];
            const std::size_t all = std::min({oa.size(), ob.size(), oc.size(), od.size()});
            for (std::size_t k = 0; k < all; ++k) {
                sum += replay_op(a, oa[k]) + replay_op(b, ob[k]) + replay_op(c, oc[k]) + replay_op(d, od[k]);
            }
            sum += run_one(a, i, all) + run_one(b, i + 1, all) + run_one(c, i + 2, all) + run_one(d, i + 3, all);
        }
        return sum + run_rest(i);
    }
    // The streams from `first` on, one by one (from 0: the plain replay).
    std::uint64_t run_rest(std::size_t first) {
        std::uint64_t sum = 0;
        for (std::size_t i = first; i < ops.size(); ++i) {
            laz::ArithmeticDecoder dec(streams[i].bytes);
            sum += run_one(dec, i, 0);
        }
        return sum;
    }
};

// Wall-clock seconds of one call of fn.
template <class Fn>
double seconds_of(Fn&& fn) {
    const auto t0 = bench::Clock::now();
    fn();
    return bench::seconds_since(t0);
}

// The decoder of FILE on one thread, the reference for the replay.
struct FileDecode {
    io::File file;
    dataset::Tile tile;
    laz::LazLayout layout;
    std::vector<std::uint8_t> records;
    ThreadPool pool{1};

    explicit FileDecode(const std::string& path)
        : file(io::File::open(path)), tile(dataset::read_tile(file)),
          layout(make_layout(path, tile)), records(tile.header.point_count * tile.header.record_length) {}
    static laz::LazLayout make_layout(const std::string& path, const dataset::Tile& tile) {
        if (!tile.laz()) throw Error(path, 0, "not a LAZ file");
        const las::LaszipVlr& vlr = *tile.laz();
        return {tile.header, vlr, laz::decode_units(tile.header, vlr, *tile.chunks(), tile.file_size())};
    }
    void decode() {
        laz::decode_units_parallel(file, layout, 0, layout.units.size(), records, las::fields::kAll, pool);
    }
};

void record(const std::string& path, const std::string& trace) {
    if (!laz::kDecodeTraceBuilt) throw Error("--record needs a build configured with -DLIDARSCOUT_LAZ_TRACE=ON");
    FileDecode f(path);
    Recorder recorder;
    laz::decode_trace_sink = &recorder;
    f.decode();
    laz::decode_trace_sink = nullptr;
    write_trace(recorder.streams, f.tile.header.point_count, trace, path);
    fmt::print("{}: {} streams recorded to {}\n", path, recorder.streams.size(), trace);
}

void replay(const std::string& path, const std::string& trace, int runs) {
    if (laz::kDecodeTraceBuilt) {
        throw Error("--trace times the decoder: use a build without -DLIDARSCOUT_LAZ_TRACE (its hooks slow it)");
    }
    FileDecode f(path);
    f.decode();  // warm-up
    std::vector<double> full_runs;
    for (int r = 0; r < runs; ++r) full_runs.push_back(seconds_of([&] { f.decode(); }));
    const double full = bench::median(full_runs);
    Replay replay{read_trace(trace, f.tile.header.point_count), {}, {}};
    std::size_t symbols = 0, bits = 0, raws = 0;
    for (const RecordedStream& s : replay.streams) {
        replay.models.push_back(std::make_unique<ReplayModels>(s));
        replay.ops.push_back(resolve(s, *replay.models.back()));
        for (const Op& op : s.ops) {
            symbols += is_symbol(op.kind);
            bits += op.kind == OpKind::Bit;
            raws += op.kind == OpKind::Raw;
        }
    }
    replay.reset();
    replay.check();
    std::vector<double> alone, paired, four, known;
    volatile std::uint64_t sink = 0;  // keeps the replays' results alive
    for (int r = 0; r < runs; ++r) {  // the forms alternate, each from the start state
        replay.reset();
        alone.push_back(seconds_of([&] { sink = sink + replay.run_rest(0); }));
        replay.reset();
        paired.push_back(seconds_of([&] { sink = sink + replay.run_paired(); }));
        replay.reset();
        four.push_back(seconds_of([&] { sink = sink + replay.run_four(); }));
        replay.reset();
        known.push_back(seconds_of([&] { sink = sink + replay.run_known(); }));
    }
    const double n = static_cast<double>(f.tile.header.point_count);
    const double per = 1e9 / n;
    fmt::print("{}: {} points, format {}, {} streams; per point {:.2f} symbols, {:.2f} bits, {:.2f} raw fields\n",
               path, f.tile.header.point_count, f.tile.header.point_format, replay.streams.size(), symbols / n,
               bits / n, raws / n);
    fmt::print("  full decode, one thread:              {:7.1f} ns/point\n", full * per);
    fmt::print("  arithmetic decoding alone (replay):   {:7.1f} ns/point ({:.0f} % of the full decode)\n",
               bench::median(alone) * per, 100 * bench::median(alone) / full);
    fmt::print("  the same, two streams interleaved:    {:7.1f} ns/point\n", bench::median(paired) * per);
    fmt::print("  the same, four streams interleaved:   {:7.1f} ns/point\n", bench::median(four) * per);
    fmt::print("  the same, every value known (no search): {:5.1f} ns/point\n", bench::median(known) * per);
}

constexpr const char* kUsage = "FILE.laz --record TRACE | --trace TRACE [--runs N]";

int run(int argc, char** argv) {
    int runs = 5;
    std::string file, record_to, trace;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--record") == 0 && i + 1 < argc) record_to = argv[++i];
        else if (std::strcmp(argv[i], "--trace") == 0 && i + 1 < argc) trace = argv[++i];
        else if (file.empty()) file = argv[i];
        else throw Error(std::string("unexpected argument ") + argv[i] + "; see --help");
    }
    if (file.empty() || record_to.empty() == trace.empty()) {
        fmt::print(stderr, "usage: bench_replay {}\n", kUsage);
        return 2;
    }
    if (!record_to.empty()) record(file, record_to);
    else replay(file, trace, runs);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_replay", kUsage, argc, argv, run);
}
