#include <gtest/gtest.h>

#include <cstring>

#include <quasiloc/core/error.h>
#include <quasiloc/map/gmm.h>

using namespace quasiloc;

namespace
{
const std::string kGmmDir = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/maps/gmm/";

void checkComponents(const std::vector<map::GmmComponent>& comps)
{
    for (const auto& c : comps)
    {
        ASSERT_TRUE(c.mean.allFinite());
        EXPECT_LT((c.covariance - c.covariance.transpose()).norm(), 1e-9);
        EXPECT_GT(c.covariance.trace(), 0);
    }
}
}  // namespace

TEST(Gmm, ReadsBothGmmFiles)
{
    const auto v1 = map::readGmmFile(kGmmDir + "v1.gmm");
    const auto v2 = map::readGmmFile(kGmmDir + "v2.gmm");
    EXPECT_EQ(v1.size(), 3299u);
    EXPECT_EQ(v2.size(), 5096u);
    checkComponents(v1);
    checkComponents(v2);
    // Room 1 spans roughly x -4.4..3.7, y -3.5..5.0, z 0..3.4 m (data README).
    Eigen::Vector3d lo = v1[0].mean, hi = v1[0].mean;
    for (const auto& c : v1)
    {
        lo = lo.cwiseMin(c.mean);
        hi = hi.cwiseMax(c.mean);
    }
    EXPECT_NEAR(lo.x(), -4.4, 0.2);
    EXPECT_NEAR(hi.x(), 3.7, 0.2);
    EXPECT_NEAR(lo.y(), -3.5, 0.2);
    EXPECT_NEAR(hi.y(), 5.0, 0.2);
    EXPECT_NEAR(hi.z(), 3.4, 0.2);
}

TEST(Gmm, DecodesHandMadeMessageAndRejectsTruncation)
{
    // count=1, then one ComponentProto: is_degenerated=1, packed mean [1,2,3], covariance as 9 unpacked doubles.
    std::vector<uint8_t> msg = {0x08, 0x01, 0x1a, 24};
    auto put_double = [&](double d) {
        uint64_t bits;
        std::memcpy(&bits, &d, 8);
        for (int i = 0; i < 8; ++i) msg.push_back(static_cast<uint8_t>(bits >> (8 * i)));
    };
    for (double d : {1.0, 2.0, 3.0}) put_double(d);
    for (int i = 0; i < 9; ++i)
    {
        msg.push_back(0x21);  // field 4, wire type 1
        put_double(i % 4 == 0 ? 0.5 : 0.0);
    }
    std::vector<uint8_t> bytes;
    bytes.push_back(0x01);
    bytes.push_back(static_cast<uint8_t>(msg.size()));
    for (uint8_t b : msg) bytes.push_back(b);
    const auto comps = map::decodeGmm(bytes, "test");
    ASSERT_EQ(comps.size(), 1u);
    EXPECT_TRUE(comps[0].is_degenerated);
    EXPECT_EQ(comps[0].mean, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(comps[0].covariance, 0.5 * Eigen::Matrix3d::Identity());

    bytes.pop_back();
    EXPECT_THROW(map::decodeGmm(bytes, "test"), core::InputError);
    EXPECT_THROW(map::readGmmFile("/nonexistent.gmm"), core::InputError);
}
