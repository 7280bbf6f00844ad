// load_with_progress (see loader_progress.hpp).
#include "cli/loader_progress.hpp"

#include <chrono>

#include "cli/progress.hpp"

namespace lidarscout::cli {

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
