// run_batch_reads: both back ends, buffered and sector-aligned (direct) reads, deliver
// exactly the bytes a plain pread gives; reads past the end come back as errors.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <map>
#include <mutex>
#include <random>

#include "io/batch_reader.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout::io {
namespace {

class ListSource : public ReadSource {
public:
    explicit ListSource(std::vector<ReadRequest> requests) : requests_(std::move(requests)) {}
    std::size_t next(std::span<ReadRequest> out) override {
        std::lock_guard lock(mutex_);
        std::size_t n = 0;
        while (n < out.size() && next_ < requests_.size()) out[n++] = requests_[next_++];
        return n;
    }
    void complete(const ReadRequest& r, std::span<const std::uint8_t> data, const ErrorRecord* error) override {
        std::lock_guard lock(mutex_);
        if (!error) {
            results[r.tag].assign(data.begin(), data.end());
        } else {
            errors[r.tag] = *error;
        }
    }
    std::map<std::uint64_t, std::vector<std::uint8_t>> results;
    std::map<std::uint64_t, ErrorRecord> errors;

private:
    std::mutex mutex_;
    std::vector<ReadRequest> requests_;
    std::size_t next_ = 0;
};

struct Case {
    ReadBackend backend;
    bool direct;
};

class BatchReader : public ::testing::TestWithParam<Case> {};

TEST_P(BatchReader, DeliversTheRequestedBytes) {
    if (GetParam().backend == ReadBackend::IoUring && !io_uring_available()) GTEST_SKIP() << "no io_uring here";
    const auto path = (test::surveys_dir() / "ky-red-river-gorge" / "N105E348.laz").string();
    const auto file = File::open(path);
    const int fd = ::open(path.c_str(), O_RDONLY | (GetParam().direct ? O_DIRECT : 0));
    ASSERT_GE(fd, 0);
    std::mt19937_64 rng(7);
    std::vector<ReadRequest> requests;
    for (std::uint64_t i = 0; i < 3000; ++i) {
        const std::uint32_t len = 1 + rng() % 9000;  // up to three sectors, any alignment
        requests.push_back({fd, rng() % (file.size() - len), len, i});
    }
    requests.push_back({fd, file.size() - 10, 20, 5000});  // runs past the end
    ListSource source(requests);
    BatchReadOptions opt;
    opt.backend = GetParam().backend;
    opt.direct = GetParam().direct;
    opt.queue_depth = 16;
    opt.threads = GetParam().backend == ReadBackend::Pread ? 8 : 2;
    EXPECT_EQ(run_batch_reads(source, opt), GetParam().backend);
    ::close(fd);
    ASSERT_EQ(source.results.size(), 3000u);
    for (const auto& r : requests) {
        if (r.tag == 5000) continue;
        std::vector<std::uint8_t> expected(r.length);
        file.read_exact(r.offset, expected);
        ASSERT_EQ(source.results[r.tag], expected) << "request " << r.tag;
    }
    ASSERT_EQ(source.errors.size(), 1u);
    EXPECT_NE(source.errors[5000].cause.find("short read"), std::string::npos);
    EXPECT_EQ(source.errors[5000].offset, file.size() - 10);  // the request's offset
}

INSTANTIATE_TEST_SUITE_P(Backends, BatchReader,
                         ::testing::Values(Case{ReadBackend::Pread, false}, Case{ReadBackend::Pread, true},
                                           Case{ReadBackend::IoUring, false}, Case{ReadBackend::IoUring, true}),
                         [](const auto& info) {
                             return std::string(backend_name(info.param.backend)) +
                                    (info.param.direct ? "_direct" : "_buffered");
                         });

TEST(BatchReaderErrors, ErrorsNameTheTargetsFileAndOffset) {
    const auto path = (test::surveys_dir() / "ky-red-river-gorge" / "N105E348.laz").string();
    const auto size = File::open(path).size();
    const auto target = ReadTarget::open(path, false);
    ListSource source({target.request(size - 4, 8, 1), target.request(0, 8, 2)});
    BatchReadOptions opt;
    opt.backend = ReadBackend::Pread;
    opt.threads = 1;
    run_batch_reads(source, opt);
    ASSERT_EQ(source.errors.size(), 1u);
    const ErrorRecord& e = source.errors.at(1);
    EXPECT_EQ(e.file, path);
    EXPECT_EQ(e.offset, size - 4);
    EXPECT_EQ(e.cause, kShortRead);
    EXPECT_EQ(source.results.at(2).size(), 8u);
}

TEST(BatchReaderErrors, BadDescriptorIsReportedPerRead) {
    ListSource source({{-1, 0, 10, 1}, {-1, 100, 10, 2}});
    BatchReadOptions opt;
    opt.backend = ReadBackend::Pread;
    opt.threads = 1;
    run_batch_reads(source, opt);
    ASSERT_EQ(source.errors.size(), 2u);
    EXPECT_NE(source.errors[1].cause.find("read failed"), std::string::npos);
    EXPECT_EQ(source.errors[2].offset, 100u);
    EXPECT_EQ(source.errors[2].file, "");  // a bare descriptor names no file
}

}  // namespace
}  // namespace lidarscout::io
