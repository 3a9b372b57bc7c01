#include <gtest/gtest.h>

#include <quasiloc/sim/euroc_room_data.h>

using namespace quasiloc;

namespace
{
const std::string kMaps = std::string(QUASILOC_SHARED_DIR) + "/data/euroc/maps/";
}  // namespace

TEST(EurocRoomData, ReadsLineMaps)
{
    EXPECT_EQ(sim::readLineSegments(kMaps + "lines/v1_line_3d.txt").size(), 891u);
    EXPECT_EQ(sim::readLineSegments(kMaps + "lines/v2_line_3d.txt").size(), 908u);
}
