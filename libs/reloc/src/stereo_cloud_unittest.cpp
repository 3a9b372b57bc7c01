// StereoCloud::points against a reference written from its contract (stereo_cloud.h): each valid disparity pixel's
// point in the rectified frame, kept when its depth is in range and it is the first, in row order, of its voxel_m
// voxel (a std::set of voxel keys here), then rotated back to the raw left camera. A slanted plane with noise and
// rows without disparity.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <random>
#include <set>
#include <tuple>

using namespace quasiloc;

namespace
{
const std::string kCalib = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/calib/";

cv::Mat slantedPlaneDisparity(int rows, int cols)
{
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> noise(-8, 8);
    cv::Mat d(rows, cols, CV_16S);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x)
            d.at<int16_t>(y, x) = int16_t(y % 17 == 0 ? 0 : 16 * (6 + 0.05 * x + 0.03 * y) + noise(rng));
    return d;
}

std::vector<Eigen::Vector3f> reference(const core::StereoRectification& rect, const reloc::StereoCloudOptions& o,
                                       const reloc::StereoDisparity& d)
{
    const double f = rect.P_left(0, 0), cx = rect.P_left(0, 2), cy = rect.P_left(1, 2), fb = f * rect.baseline_m;
    const Eigen::Matrix3f R_cam_rect =
        Eigen::Matrix3d(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(rect.R_left.val))
            .transpose()
            .cast<float>();
    std::set<std::tuple<int64_t, int64_t, int64_t>> voxels;
    std::vector<Eigen::Vector3f> out;
    const int s = d.scale;
    for (int y = 0; y < d.disparity.rows; ++y)
        for (int x = 0; x < d.disparity.cols; ++x)
        {
            const int16_t v = d.disparity.at<int16_t>(y, x);
            if (v <= 0) continue;
            const double z = fb / (s * v / 16.0);
            if (z < o.min_depth_m || z > o.max_depth_m) continue;
            const Eigen::Vector3f p((float((s * (x + 0.5) - 0.5 - cx) * z / f)),
                                    float((s * (y + 0.5) - 0.5 - cy) * z / f), float(z));
            const auto key =
                std::make_tuple(int64_t(std::floor(p.x() / o.voxel_m)), int64_t(std::floor(p.y() / o.voxel_m)),
                                int64_t(std::floor(p.z() / o.voxel_m)));
            if (voxels.insert(key).second) out.push_back(R_cam_rect * p);
        }
    return out;
}
}  // namespace

TEST(StereoCloud, OnePointPerVoxelTheFirstInRowOrder)
{
    const core::StereoRig rig = core::StereoRig::fromEuroc(kCalib + "cam0_sensor.yaml", kCalib + "cam1_sensor.yaml");
    reloc::StereoCloudOptions o;
    o.max_points = 1000000;  // no k-th thinning: the voxels alone
    reloc::StereoDisparity d;
    d.scale = 2;
    d.disparity = slantedPlaneDisparity(240, 376);
    const std::vector<Eigen::Vector3f> points = reloc::StereoCloud(rig, o).points(d);
    const std::vector<Eigen::Vector3f> expected = reference(rig.rectify(0.0), o, d);
    ASSERT_GT(expected.size(), 500u);
    ASSERT_EQ(points.size(), expected.size());
    for (size_t i = 0; i < points.size(); ++i) ASSERT_EQ(points[i], expected[i]) << "point " << i;
}

TEST(StereoCloud, ThinsToMaxPointsEveryKth)
{
    const core::StereoRig rig = core::StereoRig::fromEuroc(kCalib + "cam0_sensor.yaml", kCalib + "cam1_sensor.yaml");
    reloc::StereoCloudOptions o;
    o.max_points = 100;
    reloc::StereoDisparity d;
    d.scale = 2;
    d.disparity = slantedPlaneDisparity(240, 376);
    const std::vector<Eigen::Vector3f> all = reference(rig.rectify(0.0), o, d);
    const std::vector<Eigen::Vector3f> points = reloc::StereoCloud(rig, o).points(d);
    ASSERT_EQ(points.size(), 100u);
    const double step = double(all.size()) / 100;
    for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(points[i], all[size_t(double(i) * step)]) << "point " << i;
}
