// liblidarscout_cuda_raster.so: the C entry points of the CUDA rasterizer (raster_abi.h). Per
// frame it uploads what the host prepared (colour tables, patches with their heights and
// colours, point batches and the point jobs, one per chunk of points) into a device arena,
// runs the heightmap kernels, the point kernels per layer and the resolve, and downloads the
// image. Buffers grow and are kept from frame to frame, and so are point batches and patches
// that come with a key (ResidentData); those without one are uploaded with every frame.
#include <cuda_runtime.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <initializer_list>
#include <memory>
#include <unordered_map>
#include <vector>

#include "render/cuda/raster_abi.h"
#include "render/cuda/raster_kernels.hpp"

namespace lidarscout::render::cuda {
namespace {

constexpr std::size_t kAlign = 256;
constexpr std::size_t kSmallCopy = 1 << 20;        // smaller segments go through the pinned staging
constexpr unsigned int kQueueCapacity = 1 << 18;  // large triangles per frame (more: drawn in place)
constexpr int kQueueBlocks = 1024;

void check(cudaError_t status, const char* what) {
    if (status != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(status));
}

std::size_t aligned(std::size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

cudaError_t device_alloc(void** p, std::size_t n) { return cudaMalloc(p, n); }
cudaError_t device_free(void* p) { return cudaFree(p); }
cudaError_t pinned_alloc(void** p, std::size_t n) { return cudaMallocHost(p, n); }
cudaError_t pinned_free(void* p) { return cudaFreeHost(p); }

// Memory from one CUDA allocator that only grows: device memory, or pinned host memory for
// the many small uploads of a frame.
template <cudaError_t (*Alloc)(void**, std::size_t), cudaError_t (*Release)(void*)>
struct GrowingBuffer {
    char* ptr = nullptr;
    std::size_t bytes = 0;
    void reserve(std::size_t n) {
        if (n <= bytes) return;
        const std::size_t want = std::max(n, bytes + bytes / 2);
        if (ptr) Release(ptr);
        ptr = nullptr, bytes = 0;
        void* p = nullptr;
        check(Alloc(&p, want), Alloc == device_alloc ? "cudaMalloc" : "cudaMallocHost");
        ptr = static_cast<char*>(p);
        bytes = want;
    }
    template <typename T>
    T* at(std::size_t offset = 0) const { return reinterpret_cast<T*>(ptr + offset); }
    ~GrowingBuffer() { if (ptr) Release(ptr); }
};
using DeviceBuffer = GrowingBuffer<device_alloc, device_free>;
using PinnedBuffer = GrowingBuffer<pinned_alloc, pinned_free>;

// A frame's uploads laid out in one device arena: small segments first (copied together
// through the pinned staging buffer), large ones after (copied straight from their memory).
// layout() fixes the offsets, so that tables holding offsets can be filled in before copy().
class Upload {
public:
    std::size_t add(const void* data, std::size_t bytes, bool small_region) {
        segments_.push_back({data, bytes, small_region, 0});
        return segments_.size() - 1;
    }
    // A host table (copied at copy() time, so it may still be changed after layout()).
    template <typename T>
    std::size_t add(const std::vector<T>& v) { return add(v.data(), v.size() * sizeof(T), true); }

    void layout() {
        small_ = 0;
        for (auto& s : segments_) {
            if (s.small_region) s.offset = small_, small_ += aligned(s.bytes);
        }
        total_ = small_;
        for (auto& s : segments_) {
            if (!s.small_region) s.offset = total_, total_ += aligned(s.bytes);
        }
    }
    std::size_t offset(std::size_t segment) const { return segments_[segment].offset; }
    std::size_t total() const { return total_; }

    // The arena must hold total() bytes (reserved before device addresses were taken from it).
    void copy(const DeviceBuffer& arena, PinnedBuffer& staging, cudaStream_t stream) const {
        staging.reserve(std::max(small_, kAlign));
        for (const auto& s : segments_) {
            if (s.small_region && s.bytes) std::memcpy(staging.ptr + s.offset, s.data, s.bytes);
        }
        if (small_) check(cudaMemcpyAsync(arena.ptr, staging.ptr, small_, cudaMemcpyHostToDevice, stream), "upload");
        for (const auto& s : segments_) {
            if (s.small_region || !s.bytes) continue;
            check(cudaMemcpyAsync(arena.at<char>(s.offset), s.data, s.bytes, cudaMemcpyHostToDevice, stream),
                  "upload");
        }
    }

private:
    struct Segment {
        const void* data;
        std::size_t bytes;
        bool small_region;
        std::size_t offset;
    };
    std::vector<Segment> segments_;
    std::size_t small_ = 0, total_ = 0;
};

// Point batches and patches kept in device memory from frame to frame under the key the host
// gave them (LsrBatch::key, LsrPatch::key: the same key always names the same data). The least
// recently drawn go first when new data would pass the budget; what the current frame uses
// stays.
class ResidentData {
public:
    struct Part {
        const void* data;
        std::size_t bytes;
    };

    void set_budget(std::size_t bytes) { budget_ = bytes; }
    void begin_frame() { ++frame_; }

    // The device copy of `parts` laid end to end (each 256-byte aligned), uploaded on `stream`
    // when it is not there yet; null when it cannot be kept (the caller then uploads the parts
    // with the frame).
    const char* get(std::uint64_t key, std::initializer_list<Part> parts, cudaStream_t stream) {
        std::size_t bytes = 0;
        for (const Part& p : parts) bytes += aligned(p.bytes);
        if (auto it = entries_.find(key); it != entries_.end()) {
            if (it->second.bytes == bytes) {
                it->second.last_frame = frame_;
                return it->second.data;
            }
            release(it);  // not the data this key named before: the host broke the key's promise
        }
        if (bytes == 0 || !make_room(bytes)) return nullptr;
        void* p = nullptr;
        if (cudaMalloc(&p, bytes) != cudaSuccess) {
            (void)cudaGetLastError();  // out of memory is not sticky: upload with the frame instead
            return nullptr;
        }
        char* at = static_cast<char*>(p);
        for (const Part& part : parts) {
            if (part.bytes) check(cudaMemcpyAsync(at, part.data, part.bytes, cudaMemcpyHostToDevice, stream), "upload");
            at += aligned(part.bytes);
        }
        entries_[key] = {static_cast<const char*>(p), bytes, frame_};
        bytes_ += bytes;
        return static_cast<const char*>(p);
    }

    ~ResidentData() {
        for (auto& [key, e] : entries_) cudaFree(const_cast<char*>(e.data));
    }

private:
    struct Entry {
        const char* data;
        std::size_t bytes;
        std::uint64_t last_frame;
    };
    using Iterator = std::unordered_map<std::uint64_t, Entry>::iterator;

    void release(Iterator it) {
        // Earlier frames are complete (each ends with a stream synchronisation), so no kernel
        // still reads it; cudaFree waits for the device anyway.
        cudaFree(const_cast<char*>(it->second.data));
        bytes_ -= it->second.bytes;
        entries_.erase(it);
    }

    bool make_room(std::size_t bytes) {
        while (bytes_ + bytes > budget_) {
            auto oldest = entries_.end();
            for (auto it = entries_.begin(); it != entries_.end(); ++it) {
                if (it->second.last_frame < frame_ &&
                    (oldest == entries_.end() || it->second.last_frame < oldest->second.last_frame)) {
                    oldest = it;
                }
            }
            if (oldest == entries_.end()) return false;
            release(oldest);
        }
        return true;
    }

    std::unordered_map<std::uint64_t, Entry> entries_;
    std::size_t bytes_ = 0, budget_ = 0;
    std::uint64_t frame_ = 0;
};

struct Context {
    int device = 0;
    std::string name;
    cudaStream_t stream = nullptr;
    DeviceBuffer fb, image, log_depth, counters, arena, info, work, grid, drawn, queue, outline;
    PinnedBuffer staging;
    ResidentData resident;

    ~Context() {
        if (stream) cudaStreamDestroy(stream);
    }
};

// The host-side tables of a frame (patch descriptions, per layer the batches and the point
// jobs, one per chunk of points), given device addresses once the upload is laid out (or
// at once for data kept on the GPU).
struct HostFrame {
    std::vector<DevicePatch> patches;
    std::vector<std::vector<DeviceBatch>> batches;  // per layer
    std::vector<std::vector<PointJob>> jobs;        // per layer, batch-relative until placed
};

HostFrame describe(const LsrFrame& f) {
    HostFrame h;
    for (std::uint32_t i = 0; i < f.heightmaps.patch_count; ++i) {
        const LsrPatch& p = f.heightmaps.patches[i];
        h.patches.push_back({p.origin_x, p.origin_y, p.texel_m, p.size, nullptr, nullptr, p.colours != nullptr,
                             p.tint});
    }
    const std::uint64_t chunk = std::max<std::uint32_t>(1, f.chunk_points);
    for (std::uint32_t l = 0; l < f.layer_count; ++l) {
        const LsrPointLayer& layer = f.layers[l];
        auto& batches = h.batches.emplace_back();
        auto& jobs = h.jobs.emplace_back();
        for (std::uint32_t b = 0; b < layer.batch_count; ++b) {
            const LsrBatch& batch = layer.batches[b];
            batches.push_back({batch.screen, batch.elevation_offset, nullptr, batch.size_scale});
            for (std::uint64_t begin = 0; begin < batch.count; begin += chunk) {
                jobs.push_back({b, begin, std::min(batch.count, begin + chunk)});
            }
        }
    }
    return h;
}

// Segment indices of a frame's uploads.
struct FrameSegments {
    std::size_t ramp = 0, intensity = 0, classes = 0, patches = 0;
    std::vector<std::size_t> heights, colours;     // per patch (kNotUploaded: resident)
    std::vector<std::size_t> points;               // per batch, all layers in order (kNotUploaded: resident)
    std::vector<std::size_t> batches, jobs;        // per layer
};

constexpr std::size_t kNotUploaded = ~std::size_t{0};

// Batches with a key come from (or go to) the resident copies; the others join the upload.
FrameSegments add_segments(const LsrFrame& f, HostFrame& h, Upload& up, ResidentData& resident,
                           cudaStream_t stream) {
    FrameSegments s;
    const LsrColours& c = f.colours;
    s.ramp = up.add(c.ramp, c.ramp ? 1024 * 4 : 0, true);
    s.intensity = up.add(c.intensity, c.intensity ? 65536 * 4 : 0, true);
    s.classes = up.add(c.classes, c.classes ? 256 * 4 : 0, true);
    s.patches = up.add(h.patches);
    for (std::uint32_t i = 0; i < f.heightmaps.patch_count; ++i) {
        const LsrPatch& p = f.heightmaps.patches[i];
        const std::size_t bytes = static_cast<std::size_t>(p.size) * p.size * 4;
        if (p.key != 0) {
            if (const char* kept =
                    resident.get(p.key, {{p.heights, bytes}, {p.colours, p.colours ? bytes : 0}}, stream)) {
                h.patches[i].heights = reinterpret_cast<const float*>(kept);
                h.patches[i].colours = reinterpret_cast<const std::uint32_t*>(kept + aligned(bytes));
                s.heights.push_back(kNotUploaded);
                s.colours.push_back(kNotUploaded);
                continue;
            }
        }
        s.heights.push_back(up.add(p.heights, bytes, bytes < kSmallCopy));
        s.colours.push_back(up.add(p.colours, p.colours ? bytes : 0, bytes < kSmallCopy));
    }
    for (std::uint32_t l = 0; l < f.layer_count; ++l) {
        for (std::uint32_t b = 0; b < f.layers[l].batch_count; ++b) {
            const LsrBatch& batch = f.layers[l].batches[b];
            const std::size_t bytes = batch.count * sizeof(LsrPoint);
            if (batch.key != 0) {
                if (const char* kept = resident.get(batch.key, {{batch.points, bytes}}, stream)) {
                    h.batches[l][b].points = reinterpret_cast<const LsrPoint*>(kept);
                    s.points.push_back(kNotUploaded);
                    continue;
                }
            }
            s.points.push_back(up.add(batch.points, bytes, bytes < kSmallCopy));
        }
        s.batches.push_back(up.add(h.batches[l]));
        s.jobs.push_back(up.add(h.jobs[l]));
    }
    return s;
}

// The device addresses of what this frame uploads (resident data already has its own).
void place(const FrameSegments& s, const Upload& up, const DeviceBuffer& arena, HostFrame& h) {
    for (std::size_t i = 0; i < h.patches.size(); ++i) {
        if (s.heights[i] == kNotUploaded) continue;
        h.patches[i].heights = arena.at<float>(up.offset(s.heights[i]));
        h.patches[i].colours = arena.at<std::uint32_t>(up.offset(s.colours[i]));
    }
    std::size_t k = 0;
    for (auto& layer : h.batches) {
        for (auto& b : layer) {
            const std::size_t segment = s.points[k++];
            if (segment != kNotUploaded) b.points = arena.at<LsrPoint>(up.offset(segment));
        }
    }
}

DeviceColours device_colours(const LsrFrame& f, const DeviceBuffer& arena, const Upload& up,
                             const FrameSegments& s) {
    return DeviceColours{f.colours.mode,
                         arena.at<std::uint32_t>(up.offset(s.ramp)),
                         f.colours.ramp_scale,
                         f.colours.heightmap_offset,
                         arena.at<std::uint32_t>(up.offset(s.intensity)),
                         arena.at<std::uint32_t>(up.offset(s.classes)),
                         f.colours.filter};
}

HeightmapFrame heightmap_frame(const LsrFrame& f, const DeviceBuffer& arena, const Upload& up,
                               const FrameSegments& s) {
    const LsrHeightmapPass& p = f.heightmaps;
    HeightmapFrame h{};
    h.patches = arena.at<DevicePatch>(up.offset(s.patches));
    h.screen = p.screen;
    h.camera_x = p.camera_x, h.camera_y = p.camera_y, h.camera_z = p.camera_z;
    h.focal_px = p.focal_px, h.near_m = p.near_m;
    h.depth_scale = p.depth_scale, h.lod_quad_px = p.lod_quad_px, h.skirt_quads = p.skirt_quads;
    h.ambient = p.ambient, h.level_gain = p.level_gain, h.fixed_step = p.fixed_step;
    for (int k = 0; k < 3; ++k) h.sun[k] = p.sun[k], h.tint_rgb[k] = p.tint_rgb[k];
    h.tint_strength = p.tint_strength;
    return h;
}

// The visible patches and where their grids and block flags go (from the first kernel's
// per-patch decisions, read back).
std::vector<PatchWork> plan_patches(const std::vector<PatchInfo>& info, std::uint64_t& grid, std::uint64_t& drawn) {
    std::vector<PatchWork> work;
    grid = 0, drawn = 0;
    for (std::uint32_t i = 0; i < info.size(); ++i) {
        if (!info[i].visible) continue;
        work.push_back({i, grid, drawn});
        grid += static_cast<std::uint64_t>(info[i].blocks + 1) * (info[i].blocks + 1);
        drawn += static_cast<std::uint64_t>(info[i].blocks) * info[i].blocks;
    }
    return work;
}

void draw_heightmaps(Context& ctx, const LsrFrame& f, const Target& t, const DeviceColours& c,
                     const HeightmapFrame& hf) {
    const std::uint32_t n = f.heightmaps.patch_count;
    if (n == 0) return;
    ctx.info.reserve(n * sizeof(PatchInfo));
    launch_patch_info(hf, t, n, ctx.info.at<PatchInfo>(), ctx.stream);
    std::vector<PatchInfo> info(n);
    check(cudaMemcpyAsync(info.data(), ctx.info.ptr, n * sizeof(PatchInfo), cudaMemcpyDeviceToHost, ctx.stream),
          "patch info");
    check(cudaStreamSynchronize(ctx.stream), "heightmap pass");
    std::uint64_t grid = 0, drawn = 0;
    const std::vector<PatchWork> work = plan_patches(info, grid, drawn);
    if (work.empty()) return;
    ctx.work.reserve(work.size() * sizeof(PatchWork));
    ctx.grid.reserve(grid * sizeof(GridVertex));
    ctx.drawn.reserve(std::max<std::uint64_t>(drawn, 1));
    ctx.queue.reserve(kQueueCapacity * sizeof(QueuedTriangle));
    check(cudaMemcpyAsync(ctx.work.ptr, work.data(), work.size() * sizeof(PatchWork), cudaMemcpyHostToDevice,
                          ctx.stream),
          "patch work");
    const TriangleQueue queue{ctx.queue.at<QueuedTriangle>(), ctx.counters.at<unsigned int>(8), kQueueCapacity};
    const auto count = static_cast<std::uint32_t>(work.size());
    launch_patch_grids(hf, t, c, ctx.info.at<PatchInfo>(), ctx.work.at<PatchWork>(), count,
                       ctx.grid.at<GridVertex>(), ctx.drawn.at<unsigned char>(), ctx.stream);
    launch_patch_triangles(hf, t, c, ctx.info.at<PatchInfo>(), ctx.work.at<PatchWork>(), count,
                           ctx.grid.at<GridVertex>(), ctx.drawn.at<unsigned char>(), queue, ctx.stream);
    launch_queued_triangles(t, queue, kQueueBlocks, ctx.stream);
    if (f.heightmaps.fill_outline) {
        ctx.outline.reserve(static_cast<std::size_t>(t.width) * t.height * sizeof(Fragment));
        launch_fill_outline(t, ctx.outline.at<Fragment>(), ctx.stream);
    }
    // `work` is read by the kernels through ctx.work; the host copy may go once it is copied.
    check(cudaStreamSynchronize(ctx.stream), "heightmap pass");
}

void draw_points(Context& ctx, const LsrFrame& f, const Target& t, const DeviceColours& c, const HostFrame& h,
                 const Upload& up, const FrameSegments& s) {
    for (std::uint32_t l = 0; l < f.layer_count; ++l) {
        launch_points(t, c, ctx.arena.at<DeviceBatch>(up.offset(s.batches[l])),
                      ctx.arena.at<PointJob>(up.offset(s.jobs[l])), h.jobs[l].size(), f.layers[l].point_size,
                      f.layers[l].max_point_size,
                      ctx.stream);
    }
}

void resolve_and_download(Context& ctx, const LsrFrame& f, const Target& t, std::uint32_t* rgba,
                          std::uint64_t* drawn_pixels) {
    const std::size_t pixels = static_cast<std::size_t>(f.width) * f.height;
    if (f.resolve.edl_strength != 0.0f) ctx.log_depth.reserve(pixels * 4);
    launch_resolve(t, f.resolve, ctx.image.at<std::uint32_t>(), ctx.log_depth.at<float>(),
                   ctx.counters.at<unsigned long long>(), ctx.stream);
    check(cudaGetLastError(), "kernel launch");
    check(cudaMemcpyAsync(rgba, ctx.image.ptr, pixels * 4, cudaMemcpyDeviceToHost, ctx.stream), "download");
    unsigned long long drawn = 0;
    check(cudaMemcpyAsync(&drawn, ctx.counters.ptr, 8, cudaMemcpyDeviceToHost, ctx.stream), "download");
    check(cudaStreamSynchronize(ctx.stream), "frame");
    *drawn_pixels = drawn;
}

void draw_frame(Context& ctx, const LsrFrame& f, std::uint32_t* rgba, std::uint64_t* drawn_pixels) {
    const std::size_t pixels = static_cast<std::size_t>(f.width) * f.height;
    ctx.fb.reserve(pixels * sizeof(Fragment));
    ctx.image.reserve(pixels * 4);
    ctx.counters.reserve(16);
    check(cudaMemsetAsync(ctx.fb.ptr, 0xff, pixels * sizeof(Fragment), ctx.stream), "clear");
    check(cudaMemsetAsync(ctx.counters.ptr, 0, 16, ctx.stream), "clear");
    HostFrame h = describe(f);
    Upload up;
    ctx.resident.begin_frame();
    const FrameSegments s = add_segments(f, h, up, ctx.resident, ctx.stream);
    up.layout();
    ctx.arena.reserve(std::max(up.total(), kAlign));  // before place(): the arena may move
    place(s, up, ctx.arena, h);
    up.copy(ctx.arena, ctx.staging, ctx.stream);
    const Target t{ctx.fb.at<Fragment>(), f.width, f.height, f.near_m, f.far_m};
    const DeviceColours c = device_colours(f, ctx.arena, up, s);
    draw_heightmaps(ctx, f, t, c, heightmap_frame(f, ctx.arena, up, s));
    draw_points(ctx, f, t, c, h, up, s);
    resolve_and_download(ctx, f, t, rgba, drawn_pixels);
}

void set_error(char* error, std::size_t size, const std::string& text) {
    if (error && size) std::snprintf(error, size, "%s", text.c_str());
}

void* open_context(char* error, std::size_t error_size) {
    int count = 0;
    const cudaError_t status = cudaGetDeviceCount(&count);
    if (status != cudaSuccess) {
        set_error(error, error_size, std::string("no usable GPU (") + cudaGetErrorString(status) + ")");
        return nullptr;
    }
    if (count == 0) {
        set_error(error, error_size, "no GPU found");
        return nullptr;
    }
    try {
        auto ctx = std::make_unique<Context>();
        cudaDeviceProp prop{};
        check(cudaGetDeviceProperties(&prop, 0), "cudaGetDeviceProperties");
        check(cudaSetDevice(0), "cudaSetDevice");
        check(cudaStreamCreateWithFlags(&ctx->stream, cudaStreamNonBlocking), "cudaStreamCreate");
        std::size_t free_bytes = 0, total_bytes = 0;
        check(cudaMemGetInfo(&free_bytes, &total_bytes), "cudaMemGetInfo");
        ctx->resident.set_budget(free_bytes / 2);  // the rest for frame buffers and uploads
        ctx->name = prop.name;
        return ctx.release();
    } catch (const std::exception& e) {
        set_error(error, error_size, e.what());
        return nullptr;
    }
}

const char* context_device_name(void* context) { return static_cast<Context*>(context)->name.c_str(); }

int draw(void* context, const LsrFrame* frame, std::uint32_t* rgba, std::uint64_t* drawn_pixels, char* error,
         std::size_t error_size) {
    try {
        auto* ctx = static_cast<Context*>(context);
        check(cudaSetDevice(ctx->device), "cudaSetDevice");
        draw_frame(*ctx, *frame, rgba, drawn_pixels);
        return 0;
    } catch (const std::exception& e) {
        set_error(error, error_size, e.what());
        return 1;
    }
}

void close_context(void* context) { delete static_cast<Context*>(context); }

const LidarscoutCudaRasterApi kApi = {LIDARSCOUT_CUDA_RASTER_ABI, open_context, context_device_name, draw,
                                      close_context};

}  // namespace
}  // namespace lidarscout::render::cuda

extern "C" __attribute__((visibility("default"))) const LidarscoutCudaRasterApi* lidarscout_cuda_raster_api(void) {
    return &lidarscout::render::cuda::kApi;
}
