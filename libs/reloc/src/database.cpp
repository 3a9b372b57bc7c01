#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <filesystem>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/reloc/database.h>
#include <sstream>

#include "archive_io.h"
#include "database_io.h"

namespace quasiloc::reloc
{
namespace
{
const std::string kMagic = "quasiloc-reloc-database";
constexpr uint32_t kVersion = 3;
}  // namespace

void preprocessImage(const cv::Mat& gray, double sigma_px, cv::Mat& out)
{
    if (sigma_px > 0)
        cv::GaussianBlur(gray, out, cv::Size(), sigma_px, sigma_px, cv::BORDER_REPLICATE);
    else
        out = gray;
}

int DatabaseView::numLifted() const
{
    int n = 0;
    for (size_t i = 0; i < points_world.size(); ++i) n += lifted(i) ? 1 : 0;
    return n;
}

void Database::save(const std::string& path) const
{
    detail::writeArchiveAtomically(path, [&](mrpt::serialization::CArchive& out) {
        out.WriteBuffer(kMagic.data(), kMagic.size());
        out.WriteAs<uint32_t>(kVersion);
        detail::writeCameraAndFeatures(out, camera, features);
        out << image_blur_sigma_px << map_file;
        out.WriteAs<uint64_t>(map_points);
        out.WriteAs<uint64_t>(views.size());
        for (const auto& v : views) detail::writeView(out, v);
        vocabulary.write(out);
        index.write(out);
    });
}

Database Database::load(const std::string& path)
{
    core::require(std::filesystem::is_regular_file(path), path, "database file not found");
    mrpt::io::CFileGZInputStream stream;
    core::require(stream.open(path), path, "cannot open the database for reading");
    Database db;
    try
    {
        auto in = mrpt::serialization::archiveFrom(stream);
        // Fixed-size magic first: a foreign file fails here, before any length field is trusted.
        std::string magic(kMagic.size(), '\0');
        core::require(in.ReadBuffer(magic.data(), magic.size()) == magic.size(), path,
                      "is too short to be a quasiloc database");
        core::require(magic == kMagic, path, "is not a quasiloc database (build one with quasiloc-build-db)");
        const uint32_t version = in.ReadAs<uint32_t>();
        core::require(version == kVersion, path,
                      "database format version " + std::to_string(version) + ", this program reads version " +
                          std::to_string(kVersion) + ": rebuild it with quasiloc-build-db");
        detail::readCameraAndFeatures(in, db.camera, db.features);
        in >> db.image_blur_sigma_px;
        db.map_file = detail::readString(in);
        db.map_points = in.ReadAs<uint64_t>();
        const uint64_t n = in.ReadAs<uint64_t>();
        core::require(n < (uint64_t(1) << 24), path, "corrupt view count " + std::to_string(n));
        db.views.reserve(std::min<uint64_t>(n, 1024));  // not n: a view is ~300 bytes and n is not trusted yet
        for (uint64_t i = 0; i < n; ++i) db.views.push_back(detail::readView(in, true));
        for (auto& v : db.views)
        {
            v.points.type = db.features.type;
            v.points.image_size = cv::Size(db.camera.width, db.camera.height);
        }
        db.vocabulary = Vocabulary::read(in);
        db.index = InvertedIndex::read(in);
        for (const auto& v : db.views)
            for (WordId w : v.words)
                core::require(
                    w < db.vocabulary.numWords(), path,
                    "view " + std::to_string(v.id) + " has word " + std::to_string(w) + " outside the vocabulary");
    }
    catch (const core::InputError& e)
    {
        if (e.input() == path) throw;
        // From a part (the camera INI, the vocabulary, the index): named with the database file too.
        throw core::InputError(path, e.input() + ": " + e.problem());
    }
    catch (const std::exception& e)
    {
        throw core::InputError(
            path, "cannot be read as a quasiloc database (truncated or corrupt): " + mrpt::exception_to_str(e));
    }
    core::require(db.index.size() == db.views.size(), path, "the inverted index does not cover every view");
    return db;
}

std::string Database::summary() const
{
    size_t kps = 0, lifted = 0, lines = 0;
    for (const auto& v : views)
    {
        kps += v.points.size();
        lifted += size_t(v.numLifted());
        lines += v.lines.size();
    }
    std::ostringstream s;
    s << views.size() << " views, " << kps << " keypoints (" << lifted << " lifted to the map), " << lines
      << " line segments, " << vocabulary.numWords() << " words, features " << frontend::toString(features.type);
    return s.str();
}

}  // namespace quasiloc::reloc
