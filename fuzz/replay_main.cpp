// The fuzz targets without libFuzzer: runs a target's entry point once on every file of the
// given corpus folders (or files), so the suite replays the committed corpora with the normal
// compiler (`FuzzCorpus.*` tests). A crash or abort fails the test; an empty or missing corpus
// is an error too, so the replay cannot pass by reading nothing.
// Usage: fuzz_NAME_replay CORPUS_DIR_OR_FILE...
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::filesystem::path> corpus_files(int argc, char** argv) {
    std::vector<std::filesystem::path> files;
    for (int i = 1; i < argc; ++i) {
        const std::filesystem::path root(argv[i]);
        if (std::filesystem::is_regular_file(root)) {
            files.push_back(root);
            continue;
        }
        if (!std::filesystem::is_directory(root)) continue;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
            if (entry.is_regular_file()) files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

int main(int argc, char** argv) {
    const auto files = corpus_files(argc, argv);
    if (files.empty()) {
        std::fprintf(stderr, "%s: no corpus files in the given paths\n", argc > 0 ? argv[0] : "replay");
        return 2;
    }
    std::size_t bytes = 0;
    for (const auto& path : files) {
        const auto data = read_bytes(path);
        bytes += data.size();
        LLVMFuzzerTestOneInput(data.data(), data.size());
    }
    std::printf("replayed %zu inputs, %zu bytes\n", files.size(), bytes);
    return 0;
}
