// The edge of a benchmark program, as the CLI's: `--help` prints its usage; what the body throws
// becomes one line naming the program and the cause, and a non-zero exit status (1 for an error
// of the library or of the arguments, 2 for anything else), never an abort.
#pragma once

#include <cstdio>
#include <cstring>
#include <exception>

#include "core/error.hpp"

namespace lidarscout::bench {

template <class Body>
int bench_main(const char* name, const char* usage, int argc, char** argv, Body body) {
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::printf("Usage: %s %s\n", name, usage);
            return 0;
        }
    }
    try {
        return body(argc, argv);
    } catch (const Error& e) {
        std::fprintf(stderr, "%s: %s\n", name, e.what());
        return 1;
    } catch (const std::invalid_argument& e) {  // std::stoi and friends on a bad number
        std::fprintf(stderr, "%s: bad argument (%s); see --help\n", name, e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", name, e.what());
        return 2;
    }
}

}  // namespace lidarscout::bench
