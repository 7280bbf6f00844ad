// dataset/metadata: a virtual replica of thousands of tiles holds at most 1 KiB of metadata per
// tile (its tiles share their source's TileFile), and the count grows with what a tile holds alone.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "dataset/dataset.hpp"
#include "dataset/metadata.hpp"
#include "synth/replicate.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

class DatasetMetadata : public test::TempDirTest {
protected:
    // A virtual replica of the 9 tiles of a survey on a 60 x 60 grid: 3,600 tiles.
    Dataset open_replica() {
        const auto survey = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
        synth::write_virtual_replica(synth::plan_replicas({survey}, path("replica"), {60, 60}));
        return open_dataset({path("replica")});
    }
};

TEST_F(DatasetMetadata, VirtualReplicaHoldsAtMostOneKibPerTile) {
    const Dataset ds = open_replica();
    ASSERT_EQ(ds.tiles.size(), 3600u);
    ASSERT_TRUE(ds.skipped.empty());
    const std::uint64_t bytes = metadata_bytes(ds);
    EXPECT_LE(bytes / ds.tiles.size(), 1024u) << bytes << " bytes for " << ds.tiles.size() << " tiles";
    EXPECT_GE(bytes, ds.tiles.size() * sizeof(DatasetTile));
    std::set<const TileFile*> files;  // a tile of the grid shares its source's
    for (const auto& t : ds.tiles) files.insert(t.tile.file.get());
    EXPECT_EQ(files.size(), 9u);
}

TEST_F(DatasetMetadata, CountGrowsWithWhatATileHoldsAlone) {
    Dataset ds = open_replica();
    const std::uint64_t shared = metadata_bytes(ds);
    std::string& software = ds.tiles[0].tile.header.generating_software;
    const std::uint64_t before = software.capacity() + 1;  // at most what it held on the heap
    software = std::string(5000, 'x');
    const std::uint64_t long_name = metadata_bytes(ds);
    EXPECT_GE(long_name + before, shared + 5000);

    // A tile with a file and records of its own: counted again, chunk table and VLRs included.
    auto own = std::make_shared<TileFile>(*ds.tiles[1].tile.file);
    own->records = std::make_shared<TileRecords>(*own->records);
    const std::uint64_t chunk_table = own->chunks->heap_bytes();
    ds.tiles[1].tile.file = own;
    const std::uint64_t unshared = metadata_bytes(ds);
    EXPECT_GE(unshared, long_name + sizeof(TileFile) + sizeof(TileRecords) + chunk_table + own->path.size());
}

}  // namespace
}  // namespace lidarscout::dataset
