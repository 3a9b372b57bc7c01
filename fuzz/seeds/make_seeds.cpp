// make_fuzz_seeds <corpus_root>: writes small valid inputs for every fuzz target into <corpus_root>/<target>/, made by
// our own writers where there is one (LidarMap::save, Database::save, saveCalibration, the LZF compressor) so that the
// seeds are what the programs really write. Binary archives are stored uncompressed (gzip reads them as is), so
// mutations reach the archive rather than the deflate stream. Each seed is a few KB at most.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/bag_options.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/eval/eval_config.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/reloc/localizer.h>
#include <quasiloc/sim/imu_synthesizer.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <quasiloc/tracking/tracking_options.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/timestamps.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/map/lzf.h>
#include <quasiloc/reloc/database.h>
#include <quasiloc/ros/point_cloud2.h>
#include <sstream>

#include "map_import_app.h"

namespace fs = std::filesystem;
using namespace quasiloc;

namespace
{
fs::path root;

void writeBytes(const std::string& target, const std::string& name, const std::string& bytes)
{
    fs::create_directories(root / target);
    std::ofstream(root / target / name, std::ios::binary) << bytes;
}

std::string gunzip(const std::string& path)
{
    mrpt::io::CFileGZInputStream in(path);
    std::string out;
    char buf[4096];
    for (size_t n; (n = in.Read(buf, sizeof buf)) > 0;) out.append(buf, n);
    return out;
}

template <class T>
std::string raw(const T& v)
{
    return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}

const float kPoints[5][4] = {{0, 0, 1, 10}, {1, 0, 2, 200}, {0, 1, 3, 255}, {-1, 2, 4, 0}, {2, -1, 5, 128}};

void clouds()
{
    std::ostringstream ascii, bin;
    ascii << "ply\nformat ascii 1.0\ncomment seed\nelement vertex 5\nproperty float x\nproperty float y\n"
             "property float z\nproperty uchar intensity\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n";
    for (const auto& p : kPoints) ascii << p[0] << " " << p[1] << " " << p[2] << " " << int(p[3]) << "\n";
    ascii << "3 0 1 2\n";
    writeBytes("fuzz_ply", "ascii.ply", ascii.str());
    std::string b =
        "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "property float intensity\nend_header\n";
    b += char(3) + raw(int32_t(0)) + raw(int32_t(1)) + raw(int32_t(2));
    for (const auto& p : kPoints) b += raw(p);
    writeBytes("fuzz_ply", "binary_le.ply", b);
    std::string be =
        "ply\nformat binary_big_endian 1.0\nelement vertex 5\nproperty double x\nproperty double y\n"
        "property double z\nproperty ushort reflectivity\nend_header\n";
    auto rev = [](std::string s) { return std::string(s.rbegin(), s.rend()); };
    for (const auto& p : kPoints)
        be += rev(raw(double(p[0]))) + rev(raw(double(p[1]))) + rev(raw(double(p[2]))) + rev(raw(uint16_t(p[3])));
    writeBytes("fuzz_ply", "binary_be.ply", be);

    const std::string head =
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
        "COUNT 1 1 1 1\nWIDTH 5\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 5\n";
    std::ostringstream pa;
    pa << head << "DATA ascii\n";
    for (const auto& p : kPoints) pa << p[0] << " " << p[1] << " " << p[2] << " " << p[3] << "\n";
    writeBytes("fuzz_pcd", "ascii.pcd", pa.str());
    std::string pb = head + "DATA binary\n";
    for (const auto& p : kPoints) pb += raw(p);
    writeBytes("fuzz_pcd", "binary.pcd", pb);
    std::string soa;  // binary_compressed: field after field
    for (int f = 0; f < 4; ++f)
        for (const auto& p : kPoints) soa += raw(p[f]);
    const auto z = map::lzfCompress(reinterpret_cast<const uint8_t*>(soa.data()), soa.size());
    std::string pc = head + "DATA binary_compressed\n" + raw(uint32_t(z.size())) + raw(uint32_t(soa.size()));
    pc.append(reinterpret_cast<const char*>(z.data()), z.size());
    writeBytes("fuzz_pcd", "binary_compressed.pcd", pc);

    std::string kitti, xyzi = "# x y z i\n";
    for (const auto& p : kPoints)
    {
        kitti += raw(p);
        xyzi += std::to_string(p[0]) + ", " + std::to_string(p[1]) + "\t" + std::to_string(p[2]) + " " +
                std::to_string(p[3]) + "\n";
    }
    writeBytes("fuzz_kitti_bin", "five.bin", kitti);
    writeBytes("fuzz_xyzi", "five.txt", xyzi);
}

void gmm()
{
    auto varint = [](uint64_t v) {
        std::string s;
        do
        {
            s += char((v & 0x7f) | (v >= 0x80 ? 0x80 : 0));
            v >>= 7;
        } while (v);
        return s;
    };
    std::string file = varint(2);
    for (int c = 0; c < 2; ++c)
    {
        std::string mean, cov;
        for (int i = 0; i < 3; ++i) mean += raw(double(i + c));
        for (int i = 0; i < 9; ++i) cov += raw(double(i % 4 == 0 ? 0.01 : 0.0));
        std::string msg("\x08\x01\x10\x00", 4);                                          // is_degenerated, is_salient
        msg += "\x1a" + varint(mean.size()) + mean + "\x22" + varint(cov.size()) + cov;  // packed mean, covariance
        file += varint(msg.size()) + msg;
    }
    writeBytes("fuzz_gmm", "two.gmm", file);
}

void lidarMap()
{
    map::LidarMap m;
    for (const auto& p : kPoints) m.addPoint(p[0], p[1], p[2], p[3] / 255.f);
    const std::string gz = (root / "map.tmp.gz").string();
    m.save(gz);
    writeBytes("fuzz_lidar_map", "five.map", gunzip(gz));
    fs::remove(gz);
}

core::StereoRig rig()
{
    core::StereoRig r;
    r.left = r.right = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6);
    r.T_left_right = mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0);
    return r;
}

void calibration()
{
    dataset::SensorCalibration c;
    c.rig = rig();
    dataset::ImuCalibration imu;
    imu.gyroscope_noise_density = 1.7e-4;
    imu.gyroscope_random_walk = 1.9e-5;
    imu.accelerometer_noise_density = 2.0e-3;
    imu.accelerometer_random_walk = 3.0e-3;
    c.imu = imu;
    const std::string path = (root / "fuzz_calibration_ini" / "calibration.ini").string();
    fs::create_directories(root / "fuzz_calibration_ini");
    dataset::saveCalibration(c, path, "fuzz seed");
}

void database()
{
    reloc::Database db;
    db.camera = core::CameraModel::pinhole(16, 12, 10, 10, 8, 6);
    db.map_file = "map.bin";
    db.map_points = 5;
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
        v.lines.resize(1);
        v.lines_world.resize(1);
        db.index.add(id, v.bow);
        db.views.push_back(v);
    }
    const std::string gz = (root / "db.tmp.gz").string();
    db.save(gz);
    writeBytes("fuzz_database", "two_views.qdb", gunzip(gz));
    fs::remove(gz);
}

/** The effective configuration the programs write, one seed per section that fuzz_program_ini loads (small seeds:
 *  libFuzzer mutates a few KB faster than one 25 KB file). */
void programIni()
{
    auto seed = [](const std::string& section, const mrpt::config::CLoadableOptions& o) {
        mrpt::config::CConfigFileMemory cfg;
        o.saveToConfigFile(cfg, section);
        std::string text;
        cfg.getContent(text);
        writeBytes("fuzz_program_ini", section + ".ini", text);
    };
    seed("MapImport", map_import::MapImportOptions());
    seed("Euroc2Rawlog", dataset::Euroc2RawlogOptions());
    seed("Bag2Rawlog", dataset::Bag2RawlogOptions());
    seed("Rawlog2Bag", dataset::Rawlog2BagOptions());
    seed("Features", frontend::FeatureOptions());
    seed("PointMatching", frontend::PointMatchingOptions());
    seed("QuasiImage", quasi::QuasiOptions());
    seed("Localization", reloc::LocalizerOptions());
    seed("GeometricLocalization", reloc::GeometricLocalizationOptions());
    seed("Tracking", tracking::TrackingRunOptions());
    seed("Initialization", tracking::InitializationOptions());
    seed("MapFactors", tracking::MapFactorOptions());
    seed("Relocalization", tracking::RelocalizationOptions());
    seed("Simulation", sim::SimulationOptions());
    seed("World", sim::WorldOptions());
    seed("Appearance", sim::AppearanceOptions());
    seed("Lidar", sim::LidarOptions());
    seed("IMU", sim::ImuNoiseOptions());
    // quasiloc-eval: [Eval] naming one sequence, and that sequence's section.
    mrpt::config::CConfigFileMemory cfg;
    eval::EvalOptions e;
    e.sequence_names = {"seq"};
    e.saveToConfigFile(cfg, "Eval");
    eval::SequenceOptions().saveToConfigFile(cfg, "Eval.seq");
    std::string text;
    cfg.getContent(text);
    writeBytes("fuzz_program_ini", "Eval.ini", text);
}

mrpt::obs::CObservationStereoImages::Ptr stereoSeed(const core::StereoRig& r, int k)
{
    auto s = mrpt::obs::CObservationStereoImages::Create();
    s->timestamp = dataset::mrptTimeFromNs(1'000'000'000LL + k * 50'000'000LL);
    s->leftCamera = r.left.toTCamera();
    s->rightCamera = r.right.toTCamera();
    s->rightCameraPose = mrpt::poses::CPose3DQuat(r.T_left_right);
    s->cameraPose = mrpt::poses::CPose3DQuat(r.T_body_left);
    cv::Mat img(12, 16, CV_8UC1, cv::Scalar(40 + 20 * k));
    s->imageLeft = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
    s->imageRight = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
    s->hasImageRight = true;
    return s;
}

mrpt::obs::CObservationIMU::Ptr imuSeed(int k)
{
    auto imu = mrpt::obs::CObservationIMU::Create();
    imu->timestamp = dataset::mrptTimeFromNs(1'000'000'000LL + k * 50'000'000LL - 1'000'000LL);
    for (auto i : {mrpt::obs::IMU_X_ACC, mrpt::obs::IMU_Y_ACC, mrpt::obs::IMU_Z_ACC, mrpt::obs::IMU_WX,
                   mrpt::obs::IMU_WY, mrpt::obs::IMU_WZ})
        imu->set(i, i == mrpt::obs::IMU_Z_ACC ? 9.81 : 0.0);
    return imu;
}

void rawlog()
{
    const core::StereoRig r = rig();
    fs::create_directories(root / "fuzz_rawlog");
    {
        mrpt::io::CFileOutputStream out((root / "fuzz_rawlog" / "two_frames.rawlog").string());
        auto arch = mrpt::serialization::archiveFrom(out);
        for (int k = 0; k < 2; ++k) arch << *imuSeed(k) << *stereoSeed(r, k);
    }
    // Classes the reader does not parse, which MRPT reads in a child process (isolated_object_reader.h): an action
    // collection with an action and a sensory frame with an odometry observation, a 2D scan and a GPS observation
    // at the top level.
    mrpt::io::CFileOutputStream out((root / "fuzz_rawlog" / "other_classes.rawlog").string());
    auto arch = mrpt::serialization::archiveFrom(out);
    mrpt::obs::CActionCollection actions;
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), {});
    actions.insert(move);
    mrpt::obs::CSensoryFrame frame;
    auto odometry = mrpt::obs::CObservationOdometry::Create();
    odometry->timestamp = dataset::mrptTimeFromNs(990'000'000);
    frame.insert(odometry);
    frame.insert(imuSeed(0));
    frame.insert(stereoSeed(r, 0));
    mrpt::obs::CObservation2DRangeScan scan;
    scan.timestamp = dataset::mrptTimeFromNs(1'010'000'000);
    scan.resizeScan(8);
    for (size_t i = 0; i < 8; ++i) scan.setScanRange(i, 1.0f + 0.5f * float(i));
    mrpt::obs::CObservationGPS gps;
    gps.timestamp = dataset::mrptTimeFromNs(1'020'000'000);
    mrpt::obs::gnss::Message_NMEA_GGA gga;
    gga.fields.latitude_degrees = 36.8;
    gps.setMsg(gga);
    arch << actions << frame << scan << gps << *imuSeed(1) << *stereoSeed(r, 1);
}

/** PointCloud2 messages (CDR) of the layouts map-build reads from bags: Velodyne (float32 x y z intensity, uint16
 *  ring, float32 time), Ouster (t uint32 ns, reflectivity), float64 big-endian organised with a NaN point and padded
 *  rows, and a truncated one. */
void pointCloud2()
{
    using ros::PointFieldMsg;
    using F = PointFieldMsg;
    struct Layout
    {
        std::string name;
        std::vector<PointFieldMsg> fields;
        std::uint32_t point_step, height, width, row_pad;
        bool big_endian;
    };
    const std::vector<Layout> layouts = {
        {"velodyne",
         {{"x", 0, F::kFloat32, 1},
          {"y", 4, F::kFloat32, 1},
          {"z", 8, F::kFloat32, 1},
          {"intensity", 12, F::kFloat32, 1},
          {"ring", 16, F::kUInt16, 1},
          {"time", 18, F::kFloat32, 1}},
         22,
         1,
         4,
         0,
         false},
        {"ouster",
         {{"x", 0, F::kFloat32, 1},
          {"y", 4, F::kFloat32, 1},
          {"z", 8, F::kFloat32, 1},
          {"t", 16, F::kUInt32, 1},
          {"reflectivity", 20, F::kUInt16, 1},
          {"ring", 22, F::kUInt8, 1}},
         24,
         2,
         2,
         0,
         false},
        {"organised64_be",
         {{"x", 0, F::kFloat64, 1},
          {"y", 8, F::kFloat64, 1},
          {"z", 16, F::kFloat64, 1},
          {"intensity", 24, F::kUInt8, 1},
          {"timestamp", 32, F::kFloat64, 1}},
         40,
         2,
         2,
         8,
         true},
    };
    for (const Layout& L : layouts)
        for (bool truncated : {false, true})
        {
            ros::PointCloud2Msg m;
            m.header = {1317000000123456789, "lidar"};
            m.fields = L.fields;
            m.point_step = L.point_step;
            m.height = L.height;
            m.width = L.width;
            m.row_step = L.width * L.point_step + L.row_pad;
            m.is_bigendian = L.big_endian;
            m.data.resize(std::size_t(m.row_step) * m.height);
            for (std::size_t k = 0; k < m.data.size(); ++k) m.data[k] = std::uint8_t(k * 37 + 11);
            if (L.big_endian)  // the first point without a position: x = NaN (big-endian float64)
                for (int k = 0; k < 8; ++k) m.data[std::size_t(k)] = k == 0 ? 0x7f : k == 1 ? 0xf8 : 0;
            if (truncated) m.data.resize(m.data.size() - 3);
            const std::vector<std::uint8_t> bytes = ros::cdr::encode(m);
            writeBytes("fuzz_point_cloud2", L.name + (truncated ? "_truncated" : ""),
                       std::string(bytes.begin(), bytes.end()));
        }
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::cerr << "usage: make_fuzz_seeds <corpus_root>\n";
        return 2;
    }
    root = argv[1];
    try
    {
        clouds();
        gmm();
        lidarMap();
        calibration();
        database();
        rawlog();
        programIni();
        pointCloud2();
    }
    catch (const std::exception& e)
    {
        std::cerr << "make_fuzz_seeds: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
