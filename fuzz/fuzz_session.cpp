// libFuzzer target: a viewer session file (viewer/session_file) read, written back and read again:
// the bounded JSON reader, the typed fields and the version check. A lidarscout::Error is the
// expected outcome for bad input; a crash, another exception, a session that does not read back
// the same, or one whose saved text grows far beyond its input is a bug.
#include <cstdint>
#include <cstdlib>

#include "core/error.hpp"
#include "fuzz_input.hpp"
#include "viewer/session_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace lidarscout::viewer;
    try {
        const auto file = lidarscout::fuzz::input_file(data, size);
        if (!file) return 0;
        const SessionFile session = read_session(file->path());
        const std::string saved = session_json(session).dump(2);
        if (saved.size() > 64 * size + 65536) std::abort();  // saving stays linear in the input
        const SessionFile again = session_from_json(nlohmann::json::parse(saved), "saved");
        if (again.paths != session.paths || again.camera != session.camera) std::abort();
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
