// The paper's released height network (cg-tuwien/lidarscout: ipes_cnn.pt, TorchScript) as a
// baseline of `eval --methods released --released-model PATH`. The file is the user's: it is
// never shipped. Its conventions, from the reference viewer (modules/progressive_octree/
// HeightmapGenerator.h, heightmap_interp/src/pc2hm_dl.cpp, utilities.cu kernel_denormalize):
//   - input: one dict {"patch_hm_nearest", "patch_hm_linear"}, each float32 [n, 1, 96, 96],
//     the 96 x 96 window of 10 m texels around the 64 x 64 patch (as ours); where linear
//     interpolation has no triangle (outside the hull) the nearest height is used;
//   - heights: h_in = (z - c) / R_in * 10, c = the mean height of the window's chunk points,
//     R_in = sqrt(2)/2 * texel * 96 * 1.5 (the context radius; 1,018 m at 10 m texels);
//   - output: [n, 1, 64, 64], the centre crop (done inside the model), denormalised as
//     z = out / 10 * R_out + c with R_out = sqrt(2)/2 * texel * 64 * 1.5 (679 m at 10 m);
//   - the height model has no colour (ipes_cnn_rgb.pt, the colour model, is not handled here):
//     the reconstruction's colour is empty and eval scores no colour for it.
// Texel layout: the model is a CNN, so its output is in the frame of its input; our window
// images (texel centres) go in and the output is read in the same frame. (The reference viewer
// samples its grid at texel corners, half a texel off: a shift of the whole frame.)
// The published file was traced on CUDA and creates one (empty) tensor on "cuda:0": on a CPU-only
// LibTorch it fails until converted by `python3 -m lidarscout_train.released_cpu IN OUT`
// (load() says so).
#pragma once

#include <memory>
#include <string>

#include "nn/heightmap_network.hpp"
#include "recon/methods.hpp"

namespace lidarscout::nn {

inline constexpr int kReleasedWindow = 96, kReleasedPatch = 64;

// Our normalised heights (h = (z - centre_z) / r, r = half the window, recon/patch_space.hpp)
// to the released model's input units around `centre` (also ours), and its output back.
float to_released_height(float h, float centre);
float from_released_height(float out, float centre);

// Loads the file and runs one probe patch; throws lidarscout::Error (naming the file) when it
// cannot load or run, or when its output is not [n, 1, 64, 64].
std::shared_ptr<const HeightmapNetwork> load_released_model(const std::string& path, int threads = 0);

// Runs the released model on 96 x 96 window inputs; one 64 x 64 reconstruction (normalised
// heights as ours, no colour) per patch, method Released.
std::vector<recon::Reconstruction> infer_released(const HeightmapNetwork& model,
                                                  std::span<const recon::InterpolatedPatch* const> patches);

recon::BatchReconstructor released_batch_reconstructor(std::shared_ptr<const HeightmapNetwork> model);

}  // namespace lidarscout::nn
