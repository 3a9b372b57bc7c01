// Direct alignment on a synthetic room: the camera image is the map's own quasi-image rendered at the true
// pose (so the edge and NMI terms have a known optimum), the model is built at a perturbed pose.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <opencv2/imgproc.hpp>

#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/estimation/direct_factor.h>
#include <quasiloc/estimation/tracking_window.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>

#include "direct_alignment_detail.h"
#include "test_helpers.h"

using namespace quasiloc;

namespace
{
struct Scene
{
    map::LidarMap map = quasi::makeSyntheticRoom(400000);
    core::CameraModel camera = core::CameraModel::pinhole(752, 480, 458.0, 457.0, 367.0, 248.0);
    Eigen::Isometry3d T_world_cam_true = estimation::test::syntheticRoomCameraPose();
    quasi::QuasiOptions qo;
    std::unique_ptr<quasi::QuasiRenderer> renderer;
    Scene() { renderer = std::make_unique<quasi::QuasiRenderer>(map, qo); }
    quasi::QuasiImage render(const Eigen::Isometry3d& T)
    {
        quasi::QuasiImage q;
        renderer->render(core::fromIsometry(T), camera, q);
        return q;
    }
    estimation::DirectAlignmentModel model(const estimation::DirectAlignmentOptions& o, const Eigen::Isometry3d& T)
    {
        const quasi::QuasiImage q = render(T);
        return estimation::buildDirectAlignmentModel(o, q.depth, q.reflectivity, q.valid, q.sparse, camera, T);
    }
};

using estimation::test::perturbedPose;

double translationError(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B)
{
    return (A.translation() - B.translation()).norm();
}
double rotationErrorDeg(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B)
{
    return Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle() * 180 / M_PI;
}
}  // namespace

TEST(DirectAlignment, ModelPointsProjectOntoTheirEdges)
{
    Scene s;
    estimation::DirectAlignmentOptions o;
    const auto model = s.model(o, s.T_world_cam_true);
    ASSERT_GT(model.edge_points_world.size(), 500u);
    const quasi::QuasiImage q = s.render(s.T_world_cam_true);
    const auto field = estimation::buildCameraEdgeField(o, q.gray);
    double inliers = 0;
    estimation::edgeCost(o, field, 0, s.camera, model, s.T_world_cam_true, &inliers);
    EXPECT_GT(inliers, 0.5) << "map edges of the quasi-image should mostly lie on its own Canny edges";
}

TEST(DirectAlignment, EdgeAndNmiTermsAreBestAtTheTruePose)
{
    Scene s;
    estimation::DirectAlignmentOptions o;
    const auto model = s.model(o, s.T_world_cam_true);
    const auto field = estimation::buildCameraEdgeField(o, s.render(s.T_world_cam_true).gray);
    const double cost0 = estimation::edgeCost(o, field, 0, s.camera, model, s.T_world_cam_true);
    const quasi::QuasiImage q = s.render(s.T_world_cam_true);
    const auto nmi = estimation::buildNmiSamples(o, q.depth, q.reflectivity, q.sparse, s.camera, s.T_world_cam_true);
    ASSERT_GT(nmi.points_world.size(), 1000u);
    const double nmi0 = estimation::normalizedMutualInformation(o, field, s.camera, nmi, s.T_world_cam_true);
    // Scan each tangent direction over +-5 cm / +-1 deg.
    for (int k = 0; k < 6; ++k)
        for (double f : {-1.0, -0.5, 0.5, 1.0})
        {
            estimation::Vector6d d = estimation::Vector6d::Zero();
            d[k] = f * (k < 3 ? M_PI / 180 : 0.05);
            const Eigen::Isometry3d T = estimation::boxPlus(s.T_world_cam_true, d);
            EXPECT_GT(estimation::edgeCost(o, field, 0, s.camera, model, T), cost0)
                << "direction " << k << " step " << f;
            EXPECT_LT(estimation::normalizedMutualInformation(o, field, s.camera, nmi, T), nmi0)
                << "direction " << k << " step " << f;
        }
}

TEST(DirectAlignment, ConvergesFromPerturbedPoses)
{
    Scene s;
    estimation::DirectAlignmentOptions o;
    const auto field = estimation::buildCameraEdgeField(o, s.render(s.T_world_cam_true).gray);
    for (int seed = 1; seed <= 3; ++seed)
    {
        const Eigen::Isometry3d T0 = perturbedPose(s.T_world_cam_true, 0.1, 1.0, seed);
        const auto model = s.model(o, T0);  // built where the prediction is, as a tracker would
        Eigen::Isometry3d T = T0;
        estimation::DirectAlignmentStats st;
        ASSERT_TRUE(estimation::alignDirect(o, field, s.camera, model, T, &st));
        EXPECT_LT(translationError(T, s.T_world_cam_true), 0.02) << "seed " << seed;
        EXPECT_LT(rotationErrorDeg(T, s.T_world_cam_true), 0.2) << "seed " << seed;
        EXPECT_LT(st.final_edge_cost, st.initial_edge_cost);
    }
}

TEST(DirectAlignment, BadInputIsRejected)
{
    estimation::DirectAlignmentOptions o;
    EXPECT_THROW(estimation::buildCameraEdgeField(o, cv::Mat()), core::InputError);
    EXPECT_THROW(estimation::buildCameraEdgeField(o, cv::Mat(10, 10, CV_32F)), core::InputError);
    mrpt::config::CConfigFileMemory ini;
    ini.setContent("[DirectAlignment]\ntruncation_px = 0\n");
    EXPECT_THROW(core::loadOptionsChecked(o, ini, "DirectAlignment", "test.ini"), core::InputError);
}

TEST(DirectAlignment, FusedClassDistancesMatchOpenCvDistanceTransform)
{
    // Random sparse pixels in 6 classes (a pixel may be in several), one class empty.
    cv::Mat bits = cv::Mat::zeros(97, 131, CV_8UC1);
    cv::RNG rng(7);
    for (int i = 0; i < 300; ++i)
        bits.at<uint8_t>(rng.uniform(0, bits.rows), rng.uniform(0, bits.cols)) |= uint8_t(rng.uniform(1, 32));
    for (double truncation : {3.0, 12.0, 40.0})
    {
        std::vector<cv::Mat> fused;
        estimation::classDistanceTransforms(bits, 6, truncation, fused);
        ASSERT_EQ(fused.size(), 6u);
        for (int k = 0; k < 6; ++k)
        {
            cv::Mat not_in_class, expected;
            cv::compare(bits & cv::Scalar(1 << k), 0, not_in_class, cv::CMP_EQ);
            cv::distanceTransform(not_in_class, expected, cv::DIST_L2, cv::DIST_MASK_3, CV_32F);
            cv::min(expected, truncation, expected);
            ASSERT_EQ(fused[size_t(k)].type(), CV_32FC1);
            EXPECT_LT(cv::norm(fused[size_t(k)], expected, cv::NORM_INF), 0.01 + 1e-3 * truncation)
                << "class " << k << ", truncation " << truncation;
        }
    }
    std::vector<cv::Mat> out;
    EXPECT_THROW(estimation::classDistanceTransforms(cv::Mat(), 6, 12, out), core::InputError);
    EXPECT_THROW(estimation::classDistanceTransforms(bits, 9, 12, out), core::InputError);
}

TEST(DirectEdgeFactor, AnalyticJacobianMatchesNumeric)
{
    Scene s;
    estimation::DirectAlignmentOptions o;
    const auto field = estimation::buildCameraEdgeField(o, s.render(s.T_world_cam_true).gray);
    const auto model = s.model(o, s.T_world_cam_true);
    // A body frame that is not the camera (rotated and shifted), so the extrinsic enters the chain rule.
    Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
    T_body_cam.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T_body_cam.translation() = Eigen::Vector3d(0.05, -0.02, 0.1);
    const Eigen::Isometry3d T_map_body = perturbedPose(s.T_world_cam_true, 0.03, 0.5, 2) * T_body_cam.inverse();
    // huber_px large: the derivative check is about the chain rule, not the robust kernel.
    estimation::DirectEdgeCostFunction f(field, 0, s.camera, model, T_body_cam, 1.5, o.truncation_px, 100.0);
    const int n = f.num_residuals();
    double x[estimation::kPoseSize];
    estimation::poseToParams(T_map_body, x);
    std::vector<double> r0(static_cast<size_t>(n)), J(static_cast<size_t>(n) * estimation::kPoseSize);
    const double* params[] = {x};
    double* jac[] = {J.data()};
    ASSERT_TRUE(f.Evaluate(params, r0.data(), jac));
    // Numeric derivative along each tangent direction through PoseManifold::Plus (central differences). The
    // field is bilinear between pixels, so compare where both are smooth: residuals well below the truncation.
    estimation::PoseManifold manifold;
    std::vector<double> rel;
    for (int k = 0; k < 6; ++k)
    {
        // Big enough that the float pixel coordinates of the sampling do not drown the difference (0.1 px).
        const double h = 2e-4;
        double d[6] = {0, 0, 0, 0, 0, 0}, xp[7], xm[7];
        d[k] = h;
        manifold.Plus(x, d, xp);
        d[k] = -h;
        manifold.Plus(x, d, xm);
        std::vector<double> rp(static_cast<size_t>(n)), rm(static_cast<size_t>(n));
        double san = 0, saa = 0;
        const double* pp[] = {xp};
        const double* pm[] = {xm};
        ASSERT_TRUE(f.Evaluate(pp, rp.data(), nullptr));
        ASSERT_TRUE(f.Evaluate(pm, rm.data(), nullptr));
        for (int i = 0; i < n; ++i)
        {
            if (r0[size_t(i)] * 1.5 > 0.5 * o.truncation_px || r0[size_t(i)] < 0.5) continue;
            const double numeric = (rp[size_t(i)] - rm[size_t(i)]) / (2 * h);
            const double analytic = J[size_t(i) * estimation::kPoseSize + size_t(k)];
            // The analytic Jacobian uses central differences of the field over +-1 px (smoother than the local
            // bilinear slope): equal up to the field's curvature over a pixel.
            rel.push_back(std::abs(numeric - analytic) / (1.0 + std::abs(numeric)));
            san += analytic * numeric, saa += analytic * analytic;
        }
        std::printf("direction %d: slope numeric/analytic %.3f\n", k, san / saa);
        EXPECT_NEAR(san / saa, 1.0, 0.1) << "direction " << k;
        for (int i = 0; i < n; ++i) EXPECT_EQ(J[size_t(i) * estimation::kPoseSize + 6], 0.0);
    }
    ASSERT_GT(rel.size(), 1000u);
    std::sort(rel.begin(), rel.end());
    const double median = rel[rel.size() / 2], p90 = rel[rel.size() * 9 / 10];
    std::printf("compared %zu derivatives, relative difference median %.3f, 90th percentile %.3f\n", rel.size(), median,
                p90);
    // The analytic Jacobian takes the field's slope by central differences over +-1 px, the numeric one the local
    // bilinear slope: equal on average (slope ~1 per direction), not point by point at the distance field's kinks.
    EXPECT_LT(median, 0.25);
    EXPECT_LT(p90, 1.0);
}

TEST(DirectAlignment, SamplingGuardUsesTheFloatCoordinates)
{
    // A coordinate just below rows - 2 in double rounds to rows - 2 in float; the central difference at +1 would
    // then read a row past the image. The guard must reject it (this read made the tracker non-deterministic).
    const cv::Mat m(120, 188, CV_32FC1, cv::Scalar(0));
    const double y = 118.0 - 1e-9;
    ASSERT_EQ(float(y), 118.0f);
    EXPECT_FALSE(estimation::detail::insideForBilinear(m, 50.f, float(y)));
    EXPECT_TRUE(estimation::detail::insideForBilinear(m, 50.f, 117.99f));
}

TEST(DirectEdgeFactor, WindowWithTheDirectTermConvergesFromLevelA)
{
    // The estimator window with the direct term as a factor on the current pose (map_term = factor in the
    // tracker) and a weak prior (0.2 m / 2 deg) at a pose perturbed by 0.1 m / 1 deg: the window's solution lies
    // near the truth, not at the prior.
    Scene s;
    estimation::DirectAlignmentOptions o;
    const auto field = estimation::buildCameraEdgeField(o, s.render(s.T_world_cam_true).gray);
    // A body frame that is not the camera, so the term goes through the extrinsic.
    Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
    T_body_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
    T_body_cam.translation() = Eigen::Vector3d(0.02, 0.05, -0.03);
    estimation::StereoGeometry stereo;
    stereo.left = estimation::CameraGeometry{s.camera, T_body_cam};
    stereo.right = s.camera;
    for (int seed = 1; seed <= 2; ++seed)
    {
        const Eigen::Isometry3d T0 = perturbedPose(s.T_world_cam_true, 0.1, 1.0, seed);
        const auto model = s.model(o, T0);
        estimation::WindowInput in;
        in.stereo = &stereo;
        in.current.T_map_body = T0 * T_body_cam.inverse();
        in.prior.mean = in.current;
        in.prior.information.setIdentity();
        in.prior.information.topLeftCorner<3, 3>() *= 1 / std::pow(2 * M_PI / 180, 2);
        in.prior.information.block<3, 3>(3, 3) *= 1 / (0.2 * 0.2);
        estimation::DirectEdgeTerm d;
        d.field = &field;
        d.model = &model;
        d.camera = &s.camera;
        in.direct_terms.push_back(d);
        estimation::EstimatorOptions eo;
        estimation::WindowResult result;
        ASSERT_TRUE(estimation::estimateWindow(eo, estimation::ReweightingOptions{}, in, result));
        const Eigen::Isometry3d T = result.current.T_map_body * T_body_cam;
        std::printf("seed %d: window with the direct term: %.3f m %.3f deg (start 0.1 m 1 deg)\n", seed,
                    translationError(T, s.T_world_cam_true), rotationErrorDeg(T, s.T_world_cam_true));
        EXPECT_LT(translationError(T, s.T_world_cam_true), 0.03) << "seed " << seed;
        EXPECT_LT(rotationErrorDeg(T, s.T_world_cam_true), 0.3) << "seed " << seed;
    }
    estimation::WindowInput bad;
    bad.stereo = &stereo;
    bad.direct_terms.push_back(estimation::DirectEdgeTerm{});
    estimation::WindowResult r;
    EXPECT_THROW(estimation::estimateWindow(estimation::EstimatorOptions{}, estimation::ReweightingOptions{}, bad, r),
                 core::InputError);
}

TEST(DirectAlignment, OrientationClassesEqualTheAngleDefinitionAwayFromSectorBorders)
{
    // The definition the classes replace: t = (angle mod 180 deg) / (180 / bins deg), class = round(t) mod bins,
    // the second class on the side of t - round(t).
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> g(-400, 400);
    for (int bins : {1, 4, 6, 8, 16})
    {
        const estimation::OrientationClasses classes(bins);
        int tested = 0;
        for (int i = 0; i < 20000; ++i)
        {
            const float gx = float(g(rng)), gy = float(g(rng));
            if (gx == 0 && gy == 0) continue;
            double a = std::atan2(double(gy), double(gx));
            if (a < 0) a += M_PI;
            if (a >= M_PI) a -= M_PI;
            const double t = a / (M_PI / bins);
            if (std::abs(2 * t - std::round(2 * t)) < 1e-9) continue;  // on a sector border: either side is right
            const int expected = int(std::lround(t)) % bins;
            const int expected_second = (expected + (t - std::round(t) >= 0 ? 1 : bins - 1)) % bins;
            int second = -1;
            ASSERT_EQ(classes.classOf(gx, gy, &second), expected)
                << "bins " << bins << " g (" << gx << ", " << gy << ")";
            ASSERT_EQ(second, expected_second) << "bins " << bins << " g (" << gx << ", " << gy << ")";
            ++tested;
        }
        EXPECT_GT(tested, 19000);
    }
}

// The edge field's percentile: the value nth_element would give, on arrays of every kind (spread over the range,
// concentrated in one bucket, squared norms of Sobel derivatives, all equal) and at every rank kind.
TEST(DirectAlignment, KthSmallestIsTheValueNthElementGives)
{
    std::mt19937 rng(5);
    for (int trial = 0; trial < 400; ++trial)
    {
        const size_t n = 1 + rng() % 3000;
        std::vector<int32_t> v(n);
        for (int32_t& x : v) switch (trial % 4)
            {
                case 0: x = int32_t(rng() % (1u << 22)); break;
                case 1: x = int32_t(2048 * 7 + rng() % 2048); break;
                case 2:
                {
                    const int a = int(rng() % 2041) - 1020, b = int(rng() % 2041) - 1020;
                    x = a * a + b * b;
                    break;
                }
                default: x = 4242;
            }
        for (const size_t k : {size_t(0), n - 1, size_t(rng() % n), size_t(double(n) * 0.85)})
        {
            if (k >= n) continue;
            std::vector<int32_t> sorted = v;
            std::nth_element(sorted.begin(), sorted.begin() + long(k), sorted.end());
            ASSERT_EQ(quasiloc::estimation::detail::kthSmallest(v, k), sorted[k]) << "trial " << trial << ", k " << k;
        }
    }
}

// pairBits classifies the edge field's pixels four at a time: the classes classOf gives, on every 3x3 Sobel
// gradient of an 8-bit image (each component in [-1020, 1020]; the sector borders and the folds included), for
// every fused bin count, at every position of a batch (the four-lane part and the scalar tail).
TEST(DirectAlignment, OrientationPairBitsAreClassOfsOnEverySobelGradient)
{
    constexpr int kMax = 1020;
    std::vector<float> gx, gy;
    for (int y = -kMax; y <= kMax; ++y)
        for (int x = -kMax; x <= kMax; ++x)
        {
            gx.push_back(float(x));
            gy.push_back(float(y));
        }
    for (int bins = 1; bins <= 8; ++bins)
    {
        const estimation::OrientationClasses classes(bins);
        std::vector<uint8_t> bits(gx.size() - 1);
        classes.pairBits(gx.data() + 1, gy.data() + 1, bits.size(), bits.data());  // odd count: a scalar tail too
        for (size_t i = 0; i < bits.size(); ++i)
        {
            int second = 0;
            const int b = classes.classOf(gx[i + 1], gy[i + 1], &second);
            ASSERT_EQ(int(bits[i]), int((1u << b) | (1u << second)))
                << "bins " << bins << " g (" << gx[i + 1] << ", " << gy[i + 1] << ")";
        }
    }
    const estimation::OrientationClasses nine(9);
    uint8_t out = 0;
    const float one = 1;
    EXPECT_THROW(nine.pairBits(&one, &one, 1, &out), core::InputError);
}
