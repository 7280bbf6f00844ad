// open_with_progress, load_with_progress (see stage_progress.hpp).
#include "cli/stage_progress.hpp"

#include <chrono>

#include "cli/progress.hpp"

namespace lidarscout::cli {

dataset::Dataset open_with_progress(const std::vector<std::string>& paths, dataset::DatasetOptions options) {
    Progress progress("headers", 0);
    options.progress = [&](std::size_t, std::size_t total) {
        progress.set_total(total);
        progress.add();
    };
    auto ds = dataset::open_dataset(paths, options);
    progress.finish();
    return ds;
}

void load_with_progress(dataset::ChunkPointLoader& loader) {
    Progress progress("chunk points", loader.total());
    std::uint64_t shown = 0;
    loader.start();
    while (!loader.wait_for(std::chrono::milliseconds(50))) {
        const auto now = loader.loaded() + loader.failed();
        progress.add(now - shown);
        shown = now;
    }
    loader.wait();
    progress.add(loader.loaded() + loader.failed() - shown);
    progress.finish();
}

}  // namespace lidarscout::cli
