// The reconstruction methods by name, for evaluation and training data: "nearest", "linear",
// "cubic" and "splat" (the baselines of the paper's Tables 2 and 3) and "cnn", the heightmap
// network, which runs in batches through a BatchReconstructor (nn/heightmap_network.hpp
// provides one) instead of reconstruct(). Each turns a window's chunk points into a height image and a colour image
// of the whole window (96 x 96 by default) in normalised units (patch_space.hpp); crop the
// centre (crop_centre) for the patch itself.
//
//   nearest  the nearest chunk point's value, everywhere
//   linear   barycentric in the real triangles, nearest outside (interpolation.hpp)
//   cubic    Clough-Tocher in the real triangles, nearest outside (cubic.hpp)
//   splat    per-texel means, normalised Gaussian convolution; NaN far from points (splat.hpp)
//
// A patch with too few chunk points gets status TooFewPoints and empty images: never a guess.
#pragma once

#include <array>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "recon/cubic.hpp"
#include "recon/patch_space.hpp"
#include "recon/splat.hpp"

namespace lidarscout::recon {

// Cnn: our network; Released: the paper's released height network (nn/released_model.hpp).
enum class Method { Nearest, Linear, Cubic, Splat, Cnn, Released };

// The methods reconstruct() runs (all but the networks).
inline constexpr std::array<Method, 4> kAllMethods{Method::Nearest, Method::Linear, Method::Cubic, Method::Splat};

std::string_view method_name(Method method);
// Throws lidarscout::Error for an unknown name (the message lists the known ones).
Method method_from_name(std::string_view name);
// Cnn and Released: the methods that run in batches through a network.
bool is_network(Method method);

struct Reconstruction {
    Method method = Method::Linear;
    PatchStatus status = PatchStatus::TooFewPoints;
    Image height;  // 1 channel, normalised heights
    Image rgb;     // 3 channels in [0, 1]; NaN without colour
};

struct MethodOptions {
    CubicOptions cubic;
    SplatOptions splat;
};

// Throws lidarscout::Error for the networks (Cnn, Released: they run through a BatchReconstructor).
Reconstruction reconstruct(const PatchPoints& patch, Method method, const MethodOptions& options = {});
// Several methods on one patch, sharing the triangulation, face map and nearest map.
std::vector<Reconstruction> reconstruct(const PatchPoints& patch, std::span<const Method> methods,
                                        const MethodOptions& options = {});

struct InterpolatedPatch;
// A batched method over interpolated patches (the network): one patch-sized reconstruction per
// input, heights normalised, colours NaN when `has_rgb` is false.
using BatchReconstructor =
    std::function<std::vector<Reconstruction>(std::span<const InterpolatedPatch* const> patches, bool has_rgb)>;

}  // namespace lidarscout::recon
