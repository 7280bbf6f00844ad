// libFuzzer target: a STAC catalog / VPC document (dataset/stac_catalog) as read by every command
// that opens a catalog: the bounded JSON reader, the item fields and the links. Links to other
// documents resolve against the input's /proc path and are mostly refused or missing; a
// lidarscout::Error or an error line in the catalog is the expected outcome for bad input, a crash
// or an uncaught exception of another type is a bug. Every message must stay short (strings a
// catalog author wrote are cut where they are printed).
#include <cstdint>
#include <cstdlib>

#include "core/error.hpp"
#include "dataset/stac_catalog.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const auto file = lidarscout::fuzz::input_file(data, size);
        if (!file) return 0;
        lidarscout::dataset::CatalogLimits limits;
        limits.max_documents = 4;
        limits.max_items = 1000;
        std::size_t sidecars = 0;  // the sidecar link told as it is read: once at most, a path never empty
        const auto catalog = lidarscout::dataset::read_catalog(file->path(), limits, {}, [&](const std::string& p) {
            if (p.empty() || ++sidecars > 1) std::abort();
        });
        for (const auto& line : catalog.errors) {
            if (line.size() > 4096) std::abort();
        }
    } catch (const lidarscout::Error& e) {
        if (std::string_view(e.what()).size() > 4096) std::abort();
    }
    return 0;
}
