// Regression tests for what fuzzing the database reader found (fuzz/, docs/fuzzing.md): length fields of a corrupt
// .qdb sized allocations before any data was read (libFuzzer: RSS over 2 GB), now the lengths are read as the
// data arrives and a lie ends in an InputError naming the file.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/reloc/database.h>
#include <string>
#include <unistd.h>

using namespace quasiloc;

namespace
{
/** A two-view database with a trained two-word vocabulary, as its uncompressed archive bytes. */
std::string smallDatabaseArchive(const std::string& dir)
{
    reloc::Database db;
    db.camera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6);
    db.map_file = "map.bin";
    cv::Mat d[2] = {cv::Mat(3, 32, CV_8U), cv::Mat(3, 32, CV_8U)};
    cv::RNG rng(1);
    for (auto& m : d) rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    reloc::VocabularyOptions vo;
    vo.branching = 2;
    vo.depth = 1;
    db.vocabulary = reloc::Vocabulary::train({d[0], d[1]}, vo);
    for (int id = 0; id < 2; ++id)
    {
        reloc::DatabaseView v;
        v.id = id;
        for (int k = 0; k < 3; ++k)
        {
            v.points.keypoints.emplace_back(cv::Point2f(2.f + 3 * k, 4.f), 7.f);
            v.points_world.emplace_back(float(k), 0.f, 2.f);
        }
        v.points.descriptors = d[id];
        v.words = db.vocabulary.words(d[id]);
        v.bow = db.vocabulary.transform(d[id]);
        db.index.add(id, v.bow);
        db.views.push_back(v);
    }
    const std::string gz = dir + "/db.qdb";
    db.save(gz);
    mrpt::io::CFileGZInputStream in(gz);
    std::string out;
    char buf[4096];
    for (size_t n; (n = in.Read(buf, sizeof buf)) > 0;) out.append(buf, n);
    return out;
}

uint32_t u32At(const std::string& s, size_t at)
{
    uint32_t v;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}

template <class T>
void putAt(std::string& s, size_t at, T v)
{
    std::memcpy(s.data() + at, &v, sizeof v);
}

void expectRejected(const std::string& path, const std::string& archive)
{
    std::ofstream(path, std::ios::binary | std::ios::trunc) << archive;  // gzip reads an uncompressed file as is
    try
    {
        reloc::Database::load(path);
        ADD_FAILURE() << "a corrupt database was accepted";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}
}  // namespace

TEST(FuzzFindings, DatabaseLengthFieldsAreNotTrustedBeforeTheDataIsThere)
{
    const std::string dir = testing::TempDir() + "/qdb_fuzz_" + std::to_string(::getpid());
    std::filesystem::create_directories(dir);
    const std::string good = smallDatabaseArchive(dir), path = dir + "/bad.qdb";
    // Layout: magic (23 bytes), version (uint32), camera INI and [Features] INI (uint32 length + text each),
    // blur sigma (double), map file (string), map points (uint64), view count (uint64), views ...
    const size_t camera_at = 23 + 4;
    const size_t features_at = camera_at + 4 + u32At(good, camera_at);
    const size_t map_file_at = features_at + 4 + u32At(good, features_at) + 8;
    const size_t views_at = map_file_at + 4 + u32At(good, map_file_at) + 8;
    ASSERT_EQ(good.substr(map_file_at + 4, 7), "map.bin") << "the database layout changed";

    std::string bad = good;
    putAt(bad, camera_at, uint32_t(0xFFFFFFF0u));  // a 4 GB camera INI text
    expectRejected(path, bad);
    bad = good;
    putAt(bad, map_file_at, uint32_t(0xFFFFFFF0u));  // a 4 GB map file name
    expectRejected(path, bad);
    bad = good;
    putAt(bad, views_at, uint64_t((1u << 24) - 1));  // 16 M views (reserved up front: ~6 GB)
    expectRejected(path, bad);
    bad = good;
    putAt(bad, views_at + 8 + 4 + 12 * 8, uint64_t(1) << 30);  // first view: 1 G keypoints (24 GB)
    expectRejected(path, bad);

    std::ofstream(path, std::ios::binary | std::ios::trunc) << good;
    EXPECT_EQ(reloc::Database::load(path).views.size(), 2u);
    std::filesystem::remove_all(dir);
}
