// Shared by the viewer tests: a survey tile found by its file name.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "dataset/dataset.hpp"

namespace lidarscout::viewer::survey {

// The index of the tile whose file name (without extension) is `stem`; a test failure and 0
// when there is none.
inline std::uint32_t tile_named(const dataset::Dataset& ds, const std::string& stem) {
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        if (std::filesystem::path(ds.tiles[i].tile.path()).stem() == stem) return i;
    }
    ADD_FAILURE() << "no tile " << stem;
    return 0;
}

}  // namespace lidarscout::viewer::survey
