// Running the reconstruction methods by name on a patch (see methods.hpp).
#include "recon/methods.hpp"

#include <optional>
#include <string>

#include "core/error.hpp"
#include "recon/interpolation.hpp"

namespace lidarscout::recon {
namespace {

// One channel set (heights or colours) through one method.
Image run(Method method, const PatchPoints& patch, const PatchGeometry* geometry, const PointValues& values,
          const MethodOptions& options) {
    switch (method) {
        case Method::Nearest: return nearest_image(*geometry, values);
        case Method::Linear: return linear_image(*geometry, values);
        case Method::Cubic: return cubic_image(*geometry, values, patch.spec.grid_extent(), options.cubic);
        case Method::Splat: return splat(grid_positions(patch), values, patch.size(), options.splat).values;
        case Method::Cnn:
        case Method::Released: break;
    }
    throw Error::in_stage("recon", "unknown method");
}

}  // namespace

std::string_view method_name(Method method) {
    switch (method) {
        case Method::Nearest: return "nearest";
        case Method::Linear: return "linear";
        case Method::Cubic: return "cubic";
        case Method::Splat: return "splat";
        case Method::Cnn: return "cnn";
        case Method::Released: return "released";
    }
    return "?";
}

Method method_from_name(std::string_view name) {
    for (const Method m : kAllMethods) {
        if (method_name(m) == name) return m;
    }
    for (const Method m : {Method::Cnn, Method::Released}) {
        if (method_name(m) == name) return m;
    }
    throw Error::in_stage("recon",
                          "unknown method '" + std::string(name) + "' (nearest, linear, cubic, splat, cnn, released)");
}

bool is_network(Method method) { return method == Method::Cnn || method == Method::Released; }

std::vector<Reconstruction> reconstruct(const PatchPoints& patch, std::span<const Method> methods,
                                        const MethodOptions& options) {
    std::vector<Reconstruction> out;
    std::optional<PatchGeometry> geometry;
    std::optional<PointValues> heights, colours;
    for (const Method method : methods) {
        if (is_network(method)) {
            throw Error::in_stage("recon", "the " + std::string(method_name(method)) +
                        " method runs in batches through a network, not reconstruct()");
        }
        Reconstruction r;
        r.method = method;
        r.status = patch.status;
        if (patch.status == PatchStatus::Ok) {
            if (method != Method::Splat && !geometry) geometry = build_geometry(patch);
            if (!heights) heights = height_values(patch);
            r.height = run(method, patch, geometry ? &*geometry : nullptr, *heights, options);
            if (patch.has_rgb) {
                if (!colours) colours = colour_values(patch);
                r.rgb = run(method, patch, geometry ? &*geometry : nullptr, *colours, options);
            } else {
                r.rgb = Image(patch.size(), 3);
            }
        }
        out.push_back(std::move(r));
    }
    return out;
}

Reconstruction reconstruct(const PatchPoints& patch, Method method, const MethodOptions& options) {
    return std::move(reconstruct(patch, std::span<const Method>(&method, 1), options).front());
}

}  // namespace lidarscout::recon
