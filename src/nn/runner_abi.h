/* The C interface between lidarscout and its LibTorch runner, liblidarscout_torch.so
 * (src/nn/torch_runner/). The runner is a plugin opened with dlopen only when a network is
 * loaded, so that the programs that never run the network do not pay LibTorch's start-up
 * (~0.5 s) and do not depend on it at load time. Plain C types only; errors come back as text
 * in the caller's buffer. Bump LIDARSCOUT_RUNNER_ABI on any change. */
#ifndef LIDARSCOUT_NN_RUNNER_ABI_H
#define LIDARSCOUT_NN_RUNNER_ABI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LIDARSCOUT_RUNNER_ABI 2

typedef struct LidarscoutRunnerApi {
    int abi; /* LIDARSCOUT_RUNNER_ABI */
    /* Loads a TorchScript model; NULL on failure (the cause in `error`). */
    void* (*open)(const char* model_path, char* error, size_t error_size);
    /* Runs input [n, channels, window, window] (float32, contiguous). On success returns 0 and
     * *output (free with free_output) holds out_dims[0..3] = n, channels, size, size. */
    int (*run)(void* model, const float* input, long n, long channels, long window, float** output, long out_dims[4],
               char* error, size_t error_size);
    /* Runs a model whose forward takes one dict of named planes (the paper's released networks):
     * `count` inputs, inputs[i] float32 [n, 1, window, window] under the key names[i]. Output as
     * run(). */
    int (*run_named)(void* model, const char* const* names, const float* const* inputs, int count, long n, long window,
                     float** output, long out_dims[4], char* error, size_t error_size);
    void (*free_output)(float* output);
    void (*close)(void* model);
    /* Intra-op threads of the runtime (process-wide); 0 leaves the default. */
    void (*set_threads)(int threads);
} LidarscoutRunnerApi;

/* The one symbol the plugin exports. */
const LidarscoutRunnerApi* lidarscout_runner_api(void);

#ifdef __cplusplus
}
#endif

#endif
