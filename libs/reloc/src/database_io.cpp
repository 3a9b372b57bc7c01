#include "database_io.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>

#include <cstdint>
#include <functional>
#include <string>

#include "archive_io.h"

namespace quasiloc::reloc::detail
{
namespace
{
/** What a view's keypoint stores (cv::KeyPoint is not guaranteed trivially copyable across versions). */
struct StoredKeypoint
{
    float x, y, size, angle, response;
    int32_t octave;
};

std::string iniText(const std::function<void(mrpt::config::CConfigFileBase&)>& save)
{
    mrpt::config::CConfigFileMemory mem;
    save(mem);
    std::string text;
    mem.getContent(text);
    return text;
}
}  // namespace

void writeView(mrpt::serialization::CArchive& out, const DatabaseView& v)
{
    out.WriteAs<int32_t>(v.id);
    const auto m = v.T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) out << m(r, c);
    std::vector<StoredKeypoint> kps;
    kps.reserve(v.points.keypoints.size());
    for (const auto& k : v.points.keypoints) kps.push_back({k.pt.x, k.pt.y, k.size, k.angle, k.response, k.octave});
    writeVector(out, kps);
    writeMat(out, v.points.descriptors);
    writeVector(out, v.words);
    writeVector(out, v.points_world);
    writeVector(out, v.lines);
    writeVector(out, v.lines_world);
    out << v.valid_fraction;
    writeVector(out, v.bow);
}

DatabaseView readView(mrpt::serialization::CArchive& in, bool with_words)
{
    DatabaseView v;
    v.id = in.ReadAs<int32_t>();
    mrpt::math::CMatrixDouble44 m = mrpt::math::CMatrixDouble44::Identity();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) in >> m(r, c);
    v.T_world_cam = mrpt::poses::CPose3D(m);
    for (const auto& k : readVector<StoredKeypoint>(in))
        v.points.keypoints.emplace_back(cv::Point2f(k.x, k.y), k.size, k.angle, k.response, k.octave);
    v.points.descriptors = readMat(in);
    v.words = readVector<WordId>(in);
    v.points_world = readVector<Eigen::Vector3f>(in);
    v.lines = readVector<frontend::LineSegment>(in);
    v.lines_world = readVector<std::array<Eigen::Vector3f, 2>>(in);
    in >> v.valid_fraction;
    v.bow = readVector<std::pair<WordId, float>>(in);
    const size_t n = v.points.keypoints.size();
    if (v.points_world.size() != n || size_t(v.points.descriptors.rows) != n ||
        v.words.size() != (with_words ? n : 0) || v.lines_world.size() != v.lines.size())
        throw std::runtime_error("view " + std::to_string(v.id) + " has inconsistent array sizes");
    return v;
}

void writeCameraAndFeatures(mrpt::serialization::CArchive& out, const core::CameraModel& camera,
                            const frontend::FeatureOptions& features)
{
    out << iniText([&](auto& c) { camera.saveToIni(c, "camera"); });
    out << iniText([&](auto& c) { features.saveToConfigFile(c, "Features"); });
}

void readCameraAndFeatures(mrpt::serialization::CArchive& in, core::CameraModel& camera,
                           frontend::FeatureOptions& features)
{
    const std::string camera_ini = readString(in), features_ini = readString(in);
    camera = core::CameraModel::loadFromIni(mrpt::config::CConfigFileMemory(camera_ini), "camera");
    features.loadFromConfigFile(mrpt::config::CConfigFileMemory(features_ini), "Features");
}

void writeArchiveAtomically(const std::string& path, const std::function<void(mrpt::serialization::CArchive&)>& write)
{
    core::StagedOutputs staged;
    const std::string tmp = staged.addFile(path);
    {
        mrpt::io::CFileGZOutputStream stream;
        std::string err;
        core::require(stream.open(tmp, 1, err), path, "cannot open for writing: " + err);
        try
        {
            auto out = mrpt::serialization::archiveFrom(stream);
            write(out);
        }
        catch (const std::exception& e)
        {
            throw core::InputError(path, "write failed: " + mrpt::exception_to_str(e));
        }
        stream.close();
    }
    staged.commit();
}

}  // namespace quasiloc::reloc::detail
