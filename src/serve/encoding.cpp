// Quantizing chunk points and heightmaps into the API's binary forms.
#include "serve/encoding.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"

namespace lidarscout::serve {
namespace {

template <typename T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts only (x86-64, aarch64)
    out.append(bytes, sizeof(T));
}

// value in [lo, hi] -> [0, steps - 1], rounded to the nearest step.
std::uint32_t quantize(double value, double lo, double hi, std::uint32_t steps) {
    const double t = hi > lo ? (value - lo) / (hi - lo) : 0.0;
    const double q = std::round(std::clamp(t, 0.0, 1.0) * (steps - 1));
    return static_cast<std::uint32_t>(q);
}

void put_varint(std::string& out, std::uint32_t v) {
    while (v >= 0x80) {
        out.push_back(static_cast<char>((v & 0x7f) | 0x80));
        v >>= 7;
    }
    out.push_back(static_cast<char>(v));
}

std::uint32_t zigzag(std::int32_t v) {
    return (static_cast<std::uint32_t>(v) << 1) ^ static_cast<std::uint32_t>(v >> 31);
}
std::int32_t unzigzag(std::uint32_t v) { return static_cast<std::int32_t>(v >> 1) ^ -static_cast<std::int32_t>(v & 1); }

// The bits of x and y interleaved (x in the even bits).
std::uint32_t morton(std::uint32_t x, std::uint32_t y) {
    std::uint32_t code = 0;
    for (int b = 0; b < kXyBits; ++b) code |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return code;
}

std::pair<std::uint32_t, std::uint32_t> unmorton(std::uint32_t code) {
    std::uint32_t x = 0, y = 0;
    for (int b = 0; b < kXyBits; ++b) x |= ((code >> (2 * b)) & 1u) << b, y |= ((code >> (2 * b + 1)) & 1u) << b;
    return {x, y};
}

// Reads a body front to back; throws lidarscout::Error past its end.
struct Reader {
    const std::string& body;
    std::size_t offset;
    template <typename T>
    T get() {
        if (offset + sizeof(T) > body.size()) throw Error("a block runs past the body");
        T v;
        std::memcpy(&v, body.data() + offset, sizeof(T));
        offset += sizeof(T);
        return v;
    }
    std::uint32_t varint() {
        std::uint32_t v = 0;
        for (int shift = 0; shift < 35; shift += 7) {
            const auto byte = get<std::uint8_t>();
            v |= static_cast<std::uint32_t>(byte & 0x7f) << shift;
            if (!(byte & 0x80)) return v;
        }
        throw Error("a varint longer than 5 bytes");
    }
};

std::pair<float, float> z_range(std::span<const render::PointAttr> points) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (const auto& p : points) lo = std::min(lo, p.dz), hi = std::max(hi, p.dz);
    return points.empty() ? std::pair{0.0f, 0.0f} : std::pair{lo, hi};
}

// The level of the point of index i (0: every 64th, ... 3: the rest).
int level_of(std::size_t i) {
    int level = kLevels - 1;
    for (std::size_t stride = 4; level > 0 && i % stride == 0; stride *= 4) --level;
    return level;
}

std::pair<float, float> height_range(const std::vector<float>& heights) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (const float h : heights) {
        if (std::isfinite(h)) lo = std::min(lo, h), hi = std::max(hi, h);
    }
    return lo <= hi ? std::pair{lo, hi} : std::pair{0.0f, 0.0f};
}

// Bits of a lattice over `extent` whose steps are at most `step` (0: `most`), within [0, most].
int lattice_bits(double extent, double step, int most) {
    if (!(step > 0) || !(extent > 0)) return extent > 0 ? most : 0;
    return std::clamp(static_cast<int>(std::ceil(std::log2(extent / step + 1.0))), 1, most);
}

std::uint16_t rgb565(const render::PointAttr& p) {
    return static_cast<std::uint16_t>(((p.r >> 3) << 11) | ((p.g >> 2) << 5) | (p.b >> 3));
}

}  // namespace

std::uint32_t parse_attributes(const std::string& text) {
    std::uint32_t bits = 0;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string name = text.substr(start, comma - start);
        if (name == "rgb") bits |= kRgb;
        else if (name == "rgb565") bits |= kRgb565;
        else if (name == "class") bits |= kClass;
        else if (name == "intensity") bits |= kIntensity;
        else throw Error("unknown attribute '" + name.substr(0, 20) + "' (rgb, rgb565, class, intensity)");
        start = comma + 1;
    }
    return bits;
}

void append_block(std::string& out, std::int32_t ix, std::int32_t iy, std::span<const render::PointAttr> points,
                  double size, std::uint32_t attributes, double step) {
    const auto [z_min, z_max] = z_range(points);
    const int xy_bits = lattice_bits(size, step, kXyBits);
    const int z_bits = lattice_bits(z_max - z_min, step, step > 0 ? kZBits : kChunkZBits);
    struct Key {
        std::uint32_t morton, qz, index;
    };
    std::vector<Key> keys(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i];
        keys[i] = {morton(quantize(p.dx, 0, size, 1u << xy_bits), quantize(p.dy, 0, size, 1u << xy_bits)),
                   quantize(p.dz, z_min, z_max, 1u << z_bits), static_cast<std::uint32_t>(i)};
    }
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) { return a.morton < b.morton; });
    std::string positions;
    std::uint32_t previous = 0, previous_z = 0;
    for (const auto& k : keys) {
        put_varint(positions, k.morton - previous);
        put_varint(positions, zigzag(static_cast<std::int32_t>(k.qz) - static_cast<std::int32_t>(previous_z)));
        previous = k.morton, previous_z = k.qz;
    }
    for (const std::uint32_t v : {static_cast<std::uint32_t>(ix), static_cast<std::uint32_t>(iy),
                                  static_cast<std::uint32_t>(points.size())}) {
        put<std::uint32_t>(out, v);
    }
    put<float>(out, z_min);
    put<float>(out, z_max);
    out.append({static_cast<char>(attributes), static_cast<char>(xy_bits), static_cast<char>(z_bits), '\0'});
    put<std::uint32_t>(out, static_cast<std::uint32_t>(positions.size()));
    out += positions;
    if (attributes & kRgb) {
        for (const auto& k : keys) {
            const auto& p = points[k.index];
            out.append({static_cast<char>(p.r), static_cast<char>(p.g), static_cast<char>(p.b)});
        }
    }
    if (attributes & kRgb565) for (const auto& k : keys) put<std::uint16_t>(out, rgb565(points[k.index]));
    if (attributes & kClass) {
        for (const auto& k : keys) out.push_back(static_cast<char>(points[k.index].classification));
    }
    if (attributes & kIntensity) for (const auto& k : keys) put<std::uint16_t>(out, points[k.index].intensity);
}

DecodedBlock decode_block(const std::string& body, std::size_t& offset, double size) {
    Reader r{body, offset};
    DecodedBlock b;
    b.ix = static_cast<std::int32_t>(r.get<std::uint32_t>());
    b.iy = static_cast<std::int32_t>(r.get<std::uint32_t>());
    const std::uint32_t n = r.get<std::uint32_t>();
    const float z_min = r.get<float>(), z_max = r.get<float>();
    const std::uint32_t attributes = r.get<std::uint8_t>(), xy_bits = r.get<std::uint8_t>();
    const std::uint32_t z_bits = r.get<std::uint8_t>();
    r.get<std::uint8_t>();
    const std::uint32_t position_bytes = r.get<std::uint32_t>();
    if (xy_bits > kXyBits || z_bits > kZBits) throw Error("a block's lattice is finer than 11 and 16 bits");
    if (n > body.size() || position_bytes > body.size() - r.offset) throw Error("a block runs past the body");
    b.points.resize(n);
    const double xy_step = xy_bits ? size / ((1u << xy_bits) - 1) : 0;
    const double z_step = z_bits ? (z_max - z_min) / ((1u << z_bits) - 1) : 0;
    std::uint32_t code = 0, qz = 0;
    for (auto& p : b.points) {
        code += r.varint();
        qz += static_cast<std::uint32_t>(unzigzag(r.varint()));
        const auto [qx, qy] = unmorton(code);
        p.dx = static_cast<float>(qx * xy_step), p.dy = static_cast<float>(qy * xy_step);
        p.dz = static_cast<float>(z_min + qz * z_step);
    }
    if (attributes & kRgb) {
        for (auto& p : b.points) p.r = r.get<std::uint8_t>(), p.g = r.get<std::uint8_t>(), p.b = r.get<std::uint8_t>();
    }
    if (attributes & kRgb565) {
        for (auto& p : b.points) {
            const auto c = r.get<std::uint16_t>();  // the top bits of each channel (the page spreads them the same way)
            p.r = static_cast<std::uint8_t>((c >> 11) << 3), p.g = static_cast<std::uint8_t>(((c >> 5) & 63) << 2);
            p.b = static_cast<std::uint8_t>((c & 31) << 3);
        }
    }
    if (attributes & kClass) for (auto& p : b.points) p.classification = r.get<std::uint8_t>();
    if (attributes & kIntensity) for (auto& p : b.points) p.intensity = r.get<std::uint16_t>();
    offset = r.offset;
    return b;
}

std::vector<EncodedLevel> encode_levels(const viewer::PointSet& set, double origin_x, double origin_y,
                                        std::uint32_t attributes) {
    // blocks of kLodBlockM over the tile's extent, each point moved to its block's corner
    float extent_x = 0, extent_y = 0;
    for (const auto& p : set.points) extent_x = std::max(extent_x, p.dx), extent_y = std::max(extent_y, p.dy);
    const int nx = static_cast<int>(extent_x / kLodBlockM) + 1, ny = static_cast<int>(extent_y / kLodBlockM) + 1;
    std::vector<std::vector<std::vector<render::PointAttr>>> blocks(
        kLevels, std::vector<std::vector<render::PointAttr>>(static_cast<std::size_t>(nx) * ny));
    for (std::size_t i = 0; i < set.points.size(); ++i) {
        render::PointAttr p = set.points[i];
        const int bx = std::clamp(static_cast<int>(p.dx / kLodBlockM), 0, nx - 1);
        const int by = std::clamp(static_cast<int>(p.dy / kLodBlockM), 0, ny - 1);
        p.dx -= static_cast<float>(bx * kLodBlockM), p.dy -= static_cast<float>(by * kLodBlockM);
        blocks[level_of(i)][static_cast<std::size_t>(by) * nx + bx].push_back(p);
    }
    std::vector<EncodedLevel> out(kLevels);
    for (int level = 0; level < kLevels; ++level) {
        auto& e = out[level];
        const double spacing = set.spacing_m * std::sqrt(std::pow(4.0, kLevels - 1 - level));
        std::uint32_t used = 0;
        for (const auto& b : blocks[level]) used += !b.empty();
        for (const double v : {set.origin_x - origin_x, set.origin_y - origin_y, set.origin_z, kLodBlockM, spacing}) {
            put<float>(e.body, static_cast<float>(v));
        }
        put<std::uint32_t>(e.body, static_cast<std::uint32_t>(level));
        put<std::uint32_t>(e.body, used);
        put<std::uint32_t>(e.body, 0);
        for (int by = 0; by < ny; ++by) {
            for (int bx = 0; bx < nx; ++bx) {
                const auto& b = blocks[level][static_cast<std::size_t>(by) * nx + bx];
                if (!b.empty()) append_block(e.body, bx, by, b, kLodBlockM, attributes, spacing / kStepsPerSpacing);
                e.points += b.size();
            }
        }
    }
    return out;
}

viewer::PatchHeightmap coarsened(const viewer::PatchHeightmap& h, int step) {
    if (step <= 1 || h.size % step != 0) return h;
    viewer::PatchHeightmap c = h;
    c.size = h.size / step;
    c.texel_m = h.texel_m * step;
    const bool colours = h.colours.size() == h.heights.size();
    c.heights.assign(static_cast<std::size_t>(c.size) * c.size, NAN);
    c.colours.assign(colours ? c.heights.size() : 0, 0);
    for (int j = 0; j < c.size; ++j) {
        for (int i = 0; i < c.size; ++i) {
            double z = 0, rgb[3] = {0, 0, 0};
            int n = 0;
            for (int y = j * step; y < (j + 1) * step; ++y) {
                for (int x = i * step; x < (i + 1) * step; ++x) {
                    const std::size_t k = static_cast<std::size_t>(y) * h.size + x;
                    if (!std::isfinite(h.heights[k])) continue;
                    z += h.heights[k], ++n;
                    for (int ch = 0; colours && ch < 3; ++ch) rgb[ch] += (h.colours[k] >> (8 * ch)) & 0xff;
                }
            }
            if (2 * n < step * step) continue;
            const std::size_t k = static_cast<std::size_t>(j) * c.size + i;
            c.heights[k] = static_cast<float>(z / n);
            if (!colours) continue;
            std::uint32_t rgba = 0xff000000u;
            for (int ch = 0; ch < 3; ++ch) rgba |= static_cast<std::uint32_t>(std::lround(rgb[ch] / n)) << (8 * ch);
            c.colours[k] = rgba;
        }
    }
    return c;
}

void append_heightmap(std::string& out, const viewer::PatchHeightmap& h, double origin_x, double origin_y) {
    const auto [z_min, z_max] = height_range(h.heights);
    const bool colours = h.colours.size() == h.heights.size();
    put<std::int32_t>(out, h.cell.ix);
    put<std::int32_t>(out, h.cell.iy);
    put<std::uint16_t>(out, static_cast<std::uint16_t>(h.size));
    put<std::uint16_t>(out, colours ? 1 : 0);
    put<float>(out, static_cast<float>(h.origin_x - origin_x));
    put<float>(out, static_cast<float>(h.origin_y - origin_y));
    put<float>(out, static_cast<float>(h.texel_m));
    put<float>(out, z_min);
    put<float>(out, z_max);
    for (const float z : h.heights) {
        put<std::uint16_t>(out, std::isfinite(z) ? static_cast<std::uint16_t>(quantize(z, z_min, z_max, 65535))
                                                 : kNoHeight);
    }
    if (!colours) return;
    for (const std::uint32_t c : h.colours) {  // rgba8, red in the low byte
        out.append({static_cast<char>(c & 0xff), static_cast<char>((c >> 8) & 0xff),
                    static_cast<char>((c >> 16) & 0xff)});
    }
}

}  // namespace lidarscout::serve
