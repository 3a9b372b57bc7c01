// The structure localizer on the simulated room: a query whose image is the map's reflectivity seen from a pose
// between the views, its grey levels inverted (the camera/LiDAR gap at its simplest: point by point unrelated in
// sign, the same structure), is retrieved and localized to < 0.1 m; an image of noise is not localized; the
// retrieval grid scores a shifted copy of an image best at that shift.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/reloc/structure_localizer.h>
#include <quasiloc/reloc/view_sampling.h>

#include "structure_retrieval.h"
#include "test_room.h"

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

quasi::QuasiOptions quasiOptions()
{
    quasi::QuasiOptions q;
    q.reflectivity_scope = "map";
    return q;
}

struct Fixture
{
    map::LidarMap map;
    core::CameraModel camera;
    std::vector<mrpt::poses::CPose3D> views;
};

const Fixture& fixture()
{
    static const Fixture f = [] {
        Fixture f;
        f.map = reloc::test::testRoomMap(reloc::test::testRoom(kShared));
        const std::string calib = kShared + "/data/euroc/calib/";
        f.camera = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml").left;
        // A 3 x 3 grid of positions 0.5 m apart, 8 headings: the query lies between them.
        for (double x : {-1.0, -0.5, 0.0})
            for (double y : {-0.5, 0.0, 0.5})
                for (int h = 0; h < 8; ++h) f.views.push_back(reloc::viewPose(x, y, 1.3, h * M_PI / 4, -0.1));
        return f;
    }();
    return f;
}

/** The reflectivity seen from T, inverted: 255 where the map is darkest, mid-grey where it shows nothing. */
cv::Mat invertedReflectivity(const Fixture& f, const mrpt::poses::CPose3D& T)
{
    quasi::QuasiRenderer renderer(f.map, quasiOptions());
    quasi::QuasiImage q;
    renderer.render(T, f.camera, q);
    cv::Mat img(q.reflectivity.size(), CV_8U, cv::Scalar(128));
    cv::Mat scaled;
    q.reflectivity.convertTo(scaled, CV_8U, -255, 255);
    scaled.copyTo(img, q.valid);
    return img;
}
}  // namespace

TEST(StructureRetrieval, AShiftedImageScoresBestAtItsShift)
{
    cv::Mat img(240, 320, CV_8U);
    cv::randu(img, 0, 255);
    cv::GaussianBlur(img, img, cv::Size(0, 0), 3);
    const int cell = 16;
    cv::Mat shifted = cv::Mat(img.size(), CV_8U, cv::Scalar(0));
    img(cv::Rect(2 * cell, cell, img.cols - 2 * cell, img.rows - cell))
        .copyTo(shifted(cv::Rect(0, 0, img.cols - 2 * cell, img.rows - cell)));
    const frontend::CrossModalDescriptorOptions d;
    const reloc::OrientationGrid view = reloc::orientationGrid(img, cv::Mat(), cell, d);
    const reloc::OrientationGrid cam = reloc::orientationGrid(shifted, cv::Mat(), cell, d);
    const reloc::GridShift s = reloc::bestGridShift(cam, {&view}, 4, 3, 0.5);
    EXPECT_EQ(s.dx, 2);
    EXPECT_EQ(s.dy, 1);
    EXPECT_GT(s.score, 0.5);
}

// One test for the room (its map takes seconds to sample; ctest runs every TEST in its own process).
TEST(StructureLocalizer, InvertedReflectivityBetweenViewsLocalizesAndNoiseDoesNot)
{
    const Fixture& f = fixture();
    reloc::StructureLocalizerOptions o;
    o.candidates = 8;  // the query is retrieved within these; keeps the test short
    reloc::StructureLocalizer localizer(f.map, f.views, f.camera, quasiOptions(), o);
    // 0.2 m and 0.2 m from the nearest view, 20 deg from its heading, 5 deg from its pitch.
    const mrpt::poses::CPose3D T_true = reloc::viewPose(-0.3, 0.2, 1.25, 0.35, -0.18);
    const Eigen::Isometry3d truth = core::toIsometry(T_true);
    const reloc::LocalizationReport r = localizer.localize(invertedReflectivity(f, T_true), &truth);
    SCOPED_TRACE(localizer.describeLast());
    ASSERT_TRUE(r.localized) << r.reason;
    EXPECT_LT(core::translationDistance(r.T_world_cam, truth), 0.1);
    EXPECT_LT(core::rotationDistanceRad(r.T_world_cam, truth), 1.0 * M_PI / 180);
    EXPECT_GE(localizer.lastDiagnostics().first_good_rank, 0);

    cv::Mat noise(f.camera.height, f.camera.width, CV_8U);
    cv::randu(noise, 0, 255);
    EXPECT_FALSE(localizer.localize(noise).localized);
}
