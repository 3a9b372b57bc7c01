// Cross-modal map points (crossmodal_points.h): a textured wall whose camera image is the map's reflectivity
// inverted and compressed (the relation KITTI shows above the road): the orientation field finds the map points'
// true pixels, and an unrelated camera image gives few associations and no better than chance.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/tracking/crossmodal_points.h>

#include <cstdio>
#include <random>

using namespace quasiloc;

namespace
{
const core::CameraModel kCamera = core::CameraModel::pinhole(320, 240, 300, 300, 160, 120);
constexpr int kCols = 300, kRows = 200;  // the wall's points, 1 cm apart: 1 px at 3 m

/** Random filled polygons and ellipses of random levels on a 1 cm grid (CV_32F in [0, 1]). */
cv::Mat texture(unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    cv::Mat t(kRows, kCols, CV_32F, cv::Scalar(0.5));
    for (int i = 0; i < 70; ++i)
    {
        const cv::Point c(int(U(rng) * kCols), int(U(rng) * kRows));
        const cv::Size axes(4 + int(U(rng) * 18), 4 + int(U(rng) * 18));
        cv::ellipse(t, c, axes, U(rng) * 180, 0, 360, cv::Scalar(U(rng)), cv::FILLED);
        std::vector<cv::Point> poly;
        for (int k = 0; k < 3 + i % 3; ++k)
            poly.emplace_back(c.x + int((U(rng) - 0.5) * 40), c.y + int((U(rng) - 0.5) * 40));
        cv::fillPoly(t, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(U(rng)));
    }
    return t;
}

map::LidarMap wall(const cv::Mat& reflectivity)
{
    map::LidarMap m;
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kCols; ++c)
            m.addPoint(float(-1.5 + c * 0.01), float(-1.0 + r * 0.01), 3.0f, reflectivity.at<float>(r, c));
    return m;
}

/** The camera at the identity sees texture pixel (c, r) at (c + 10, r + 20); grey = 230 - 180 t^2 (inverted,
 *  compressed), a flat 128 around the wall. */
cv::Mat cameraImage(const cv::Mat& t)
{
    cv::Mat img(240, 320, CV_8U, cv::Scalar(128));
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kCols; ++c)
        {
            const float v = t.at<float>(r, c);
            img.at<uint8_t>(r + 20, c + 10) = cv::saturate_cast<uint8_t>(230 - 180 * v * v);
        }
    return img;
}

struct Scene
{
    map::LidarMap map;
    quasi::QuasiImage q;
};

void render(Scene& s, const Eigen::Isometry3d& T_world_cam)
{
    quasi::QuasiRenderer renderer(s.map, quasi::QuasiOptions{});
    renderer.render(core::fromIsometry(T_world_cam), kCamera, s.q);
}
}  // namespace

TEST(CrossModalPoints, FindsTheTruePixelsOfAnInvertedImageAndKeepsTheirDistribution)
{
    const cv::Mat t = texture(3);
    Scene s{wall(t), {}};
    const Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
    // The aligned pose 1 cm and 0.1 deg off the truth, as the tracker's edge alignment leaves it.
    Eigen::Isometry3d T_aligned = T_true;
    T_aligned.translation() = Eigen::Vector3d(0.01, -0.005, 0);
    T_aligned.rotate(Eigen::AngleAxisd(0.1 * M_PI / 180, Eigen::Vector3d::UnitY()));
    render(s, T_aligned);
    tracking::CrossModalPointOptions o;
    const frontend::DescriptorField cam = tracking::describeCameraForMapPoints(cameraImage(t), o);
    tracking::CrossModalPointStats stats;
    const auto a =
        tracking::associateCrossModalPoints(cam, s.q, s.map, kCamera, T_aligned, 0.01, 0.2 * M_PI / 180, o, &stats);
    ASSERT_GE(stats.map_keypoints, 40);
    ASSERT_GE(int(a.size()), 20);
    const int correct = tracking::countCorrect(a, kCamera, T_true);
    EXPECT_GE(correct, int(0.8 * double(a.size()))) << correct << " of " << a.size();
    int several = 0, found_at_truth = 0;
    for (const auto& x : a)
    {
        ASSERT_FALSE(x.p_map.empty());
        ASSERT_EQ(x.p_map.size(), x.probability.size());
        EXPECT_LE(int(x.p_map.size()), o.max_candidates);
        double sum = 0;
        for (double p : x.probability) sum += p;
        EXPECT_NEAR(sum, 1.0, 1e-9);
        several += x.p_map.size() > 1;
        // The searched map point's true projection is where its match was found.
        Eigen::Vector2d u;
        ASSERT_TRUE(kCamera.project(x.p_searched, u));
        found_at_truth += (u - x.px).norm() <= 3.0;
    }
    EXPECT_GE(found_at_truth, int(0.8 * double(a.size()))) << found_at_truth << " of " << a.size();
    // One candidate is no distribution: some observations must leave several map points possible.
    EXPECT_GT(several, 0);
    std::printf(
        "%zu associations of %d map keypoints, %d correct, %d searched points found at the truth, %d with "
        "several candidates\n",
        a.size(), stats.map_keypoints, correct, found_at_truth, several);

    // A single hypothesis per observation with max_candidates = 1.
    o.max_candidates = 1;
    for (const auto& x : tracking::associateCrossModalPoints(cam, s.q, s.map, kCamera, T_aligned, 0.01, 0.0035, o))
        EXPECT_EQ(x.p_map.size(), 1u);
}

TEST(CrossModalPoints, AnUnrelatedImageGivesFewAndWrongAssociations)
{
    const cv::Mat t = texture(3);
    Scene s{wall(t), {}};
    const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    render(s, T);
    tracking::CrossModalPointOptions o;
    const auto related = tracking::associateCrossModalPoints(tracking::describeCameraForMapPoints(cameraImage(t), o),
                                                             s.q, s.map, kCamera, T, 0.01, 0.0035, o);
    const auto unrelated = tracking::associateCrossModalPoints(
        tracking::describeCameraForMapPoints(cameraImage(texture(17)), o), s.q, s.map, kCamera, T, 0.01, 0.0035, o);
    EXPECT_LT(unrelated.size() * 2, related.size());
    EXPECT_LE(tracking::countCorrect(unrelated, kCamera, T), int(unrelated.size() / 3) + 1);
}

TEST(CrossModalPoints, AxisLinesGiveTheReprojectionResidualPerCandidate)
{
    tracking::CrossModalPointAssociation a;
    a.px = Eigen::Vector2d(100.5, 60.25);
    a.p_map = {Eigen::Vector3d(0.1, 0.2, 3.0), Eigen::Vector3d(0.12, 0.2, 3.0)};
    a.probability = {0.7, 0.3};
    std::vector<estimation::LineFactorInput> lines;
    tracking::appendAxisLineFactors({a}, 1.5, lines);
    ASSERT_EQ(lines.size(), 2u);
    for (size_t c = 0; c < 2; ++c)
    {
        Eigen::Vector2d u;
        ASSERT_TRUE(kCamera.project(a.p_map[c], u));
        for (int axis = 0; axis < 2; ++axis)
        {
            const auto& l = lines[size_t(axis)];
            ASSERT_EQ(l.candidates.size(), 2u);
            EXPECT_DOUBLE_EQ(l.candidates[c].probability, a.probability[c]);
            EXPECT_DOUBLE_EQ(l.sigma_px, 1.5);
            EXPECT_NEAR(l.line_px.dot(Eigen::Vector3d(u.x(), u.y(), 1)), (u - a.px)[axis], 1e-12);
        }
    }
    EXPECT_EQ(a.nominal(), 0);
}
