// Reference frames: the visible tiles decoded piece by piece into one framebuffer; their cache
// files (a small header, then the pixels).
#include "viewer/reference_frame.hpp"

#include <atomic>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "io/output_file.hpp"
#include "render/framebuffer.hpp"
#include "render/point_pass.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::uint64_t kPiecePoints = 1u << 18;
constexpr char kMagic[8] = {'L', 'S', 'R', 'E', 'F', '0', '0', '1'};

std::vector<std::uint32_t> visible_tiles(const dataset::Dataset& ds, const render::Camera& camera) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        if (screen_fraction(camera, ds.bounds(i)) > 0) out.push_back(i);
    }
    return out;
}

// Draws every point of `tile` into `fb`, piece by piece as they are decoded.
void draw_tile(const dataset::Dataset& ds, const dataset::DatasetTile& tile, bool grey, render::Framebuffer& fb,
               const render::Camera& camera, const render::PointPassSettings& settings, ThreadPool& pool,
               const std::function<void(std::uint64_t)>& drawn) {
    const PointOrder any = [](double, double, double) { return 0.0; };
    decode_tile_pieces(tile, ds.las_stride, pool, any, kPiecePoints, ~0ull, [&](PointSet&& piece) {
        if (grey) paint_uncoloured(std::span(&piece, 1));
        const render::PointBatch batch = piece.batch();
        render::draw_points(fb, camera, std::span(&batch, 1), settings, pool);
        drawn(piece.points.size());
    });
}

std::string path_of(const std::filesystem::path& dir, const std::string& key) {
    return (dir / (key + ".ref")).string();
}

}  // namespace

render::RgbaImage stream_reference_frame(const dataset::Dataset& ds, const render::Camera& camera,
                                         std::span<const render::HeightmapPatch> heightmaps, const SceneStyle& style,
                                         ThreadPool& pool, const ReferenceProgress& progress) {
    render::Framebuffer fb(camera.width, camera.height);
    if (!heightmaps.empty()) {
        render::HeightmapPassSettings hs = style.heightmaps;
        hs.colour = style.colour;
        render::draw_heightmaps(fb, camera, heightmaps, hs, pool);
    }
    render::PointPassSettings ps;
    ps.colour = style.colour;
    ps.point_size = style.point_size;
    ps.adaptive_size = style.adaptive_point_size;
    const auto tiles = visible_tiles(ds, camera);
    std::uint64_t total = 0;
    for (const auto t : tiles) total += ds.tiles[t].tile.header.point_count;
    std::atomic<std::uint64_t> done{0};
    const auto drawn = [&](std::uint64_t n) {
        const std::uint64_t now = done.fetch_add(n) + n;
        if (progress) progress(now, total);
    };
    const bool grey = !survey_has_rgb(ds);
    for (const auto t : tiles) draw_tile(ds, ds.tiles[t], grey, fb, camera, ps, pool, drawn);
    return render::resolve(fb, style.resolve, pool);
}

std::string reference_key(const dataset::Dataset& ds, const render::Camera& camera, const SceneStyle& style,
                          const std::string& extra) {
    std::ostringstream text;
    text.precision(17);
    // v2: heightmaps lit to their colour on level ground, outline filled; v3: adaptive point sizes
    text << "reference v3\n" << extra << '\n';
    for (const auto& t : ds.tiles) {  // a replica's shifted copies differ by their place only
        text << t.tile.path() << ' ' << t.tile.file_size() << ' ' << t.tile.header.point_count << ' '
             << t.bounds_m.min_x << ' ' << t.bounds_m.min_y << '\n';
    }
    const auto& c = camera;
    text << "camera " << c.x << ' ' << c.y << ' ' << c.z << ' ' << c.yaw_deg << ' ' << c.pitch_deg << ' ' << c.fov_deg
         << ' ' << c.width << ' ' << c.height << ' ' << c.near_m << ' ' << c.far_m << '\n';
    const auto& k = style.colour;
    text << "style " << static_cast<int>(k.mode) << ' ' << k.z_min << ' ' << k.z_max << ' ' << style.point_size << ' '
         << style.adaptive_point_size << ' ' << style.resolve.background << ' ' << style.resolve.edl_strength << ' '
         << style.resolve.edl_radius_px << '\n';
    const auto& h = style.heightmaps;
    text << "heightmaps " << h.lod_quad_px << ' ' << h.fixed_step << ' ' << h.skirt_quads << ' ' << h.ambient << ' '
         << h.sun[0] << ' ' << h.sun[1] << ' ' << h.sun[2] << ' ' << h.fill_outline << '\n';
    const std::string all = text.str();
    Sha256 sha;
    sha.update(std::span(reinterpret_cast<const std::uint8_t*>(all.data()), all.size()));
    return sha.hex_digest().substr(0, 32);
}

std::optional<render::RgbaImage> load_reference(const std::filesystem::path& dir, const std::string& key) {
    std::ifstream in(path_of(dir, key), std::ios::binary);
    char magic[sizeof(kMagic)] = {};
    std::int32_t size[2] = {};
    if (!in.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) return std::nullopt;
    if (!in.read(reinterpret_cast<char*>(size), sizeof(size)) || size[0] <= 0 || size[1] <= 0) return std::nullopt;
    render::RgbaImage image;
    image.width = size[0], image.height = size[1];
    image.pixels.resize(static_cast<std::size_t>(size[0]) * static_cast<std::size_t>(size[1]));
    const auto bytes = static_cast<std::streamsize>(image.pixels.size() * sizeof(std::uint32_t));
    if (!in.read(reinterpret_cast<char*>(image.pixels.data()), bytes) || in.peek() != EOF) return std::nullopt;
    return image;
}

void store_reference(const std::filesystem::path& dir, const std::string& key, const render::RgbaImage& image) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error(dir.string(), std::nullopt, "cannot create the reference cache folder: " + ec.message());
    io::AtomicOutputFile out(path_of(dir, key));
    const std::int32_t size[2] = {image.width, image.height};
    out.write(std::span(reinterpret_cast<const std::uint8_t*>(kMagic), sizeof(kMagic)));
    out.write(std::span(reinterpret_cast<const std::uint8_t*>(size), sizeof(size)));
    out.write(std::span(reinterpret_cast<const std::uint8_t*>(image.pixels.data()),
                        image.pixels.size() * sizeof(std::uint32_t)));
    out.commit();
}

}  // namespace lidarscout::viewer
