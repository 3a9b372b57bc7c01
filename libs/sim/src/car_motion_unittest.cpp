#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/car_motion.h>

using namespace quasiloc;

namespace
{
sim::CampusLayout layout()
{
    sim::CampusOptions o;
    o.block_size_m = 60;
    o.blocks_per_side = 3;
    return sim::makeCampusLayout(o, "test");
}
}  // namespace

TEST(CarMotion, RouteFollowsTheStreetsWithoutTurningBack)
{
    const sim::CampusLayout l = layout();
    sim::CarOptions o;
    o.route_length_m = 1200;
    const std::vector<Eigen::Vector2d> route = sim::planCarRoute(l, o, 7);
    ASSERT_GE(route.size(), 2u);
    EXPECT_GE((route.size() - 1) * l.pitch, o.route_length_m);
    for (size_t i = 0; i + 1 < route.size(); ++i)
    {
        EXPECT_NEAR((route[i + 1] - route[i]).norm(), l.pitch, 1e-9);  // one block to a neighbouring intersection
        EXPECT_TRUE(l.onCarriageway(route[i + 1], 0.0));
        if (i > 0) EXPECT_GT((route[i + 1] - route[i - 1]).norm(), 1.0) << "turned back at " << i;
    }
}

TEST(CarMotion, DrivesTheLaneWithinItsLimitsWithStopsAndTurns)
{
    const sim::CampusLayout l = layout();
    sim::CarOptions o;
    o.route_length_m = 1500;
    o.stop_probability = 0.5;
    const sim::CarMotion m = sim::driveCarRoute(l, sim::planCarRoute(l, o, 3), o, 100.0, 3, "test");
    EXPECT_GE(m.length_m, 1400.0);
    EXPECT_GT(m.turns, 0u);
    EXPECT_GT(m.stops, 0u);
    EXPECT_NEAR(m.top_speed_m_s, o.max_speed_m_s, 1e-6);
    const auto& P = m.T_world_base.poses;
    ASSERT_GT(P.size(), 1000u);
    EXPECT_NEAR(P[1].t - P[0].t, 1 / o.sample_rate_hz, 1e-9);
    // On the carriageway the whole way, level, at the road's height.
    for (const auto& tp : P)
    {
        ASSERT_TRUE(l.onCarriageway({tp.pose.x(), tp.pose.y()}, 0.5)) << tp.pose;
        ASSERT_NEAR(tp.pose.z(), 0.0, 1e-9);
        ASSERT_LT(std::abs(tp.pose.pitch()) + std::abs(tp.pose.roll()), 0.05);
    }
    // Speed and acceleration over 0.1 s windows within the limits; standing at the start; stops while driving.
    const size_t w = size_t(0.1 * o.sample_rate_hz);
    double v_max = 0, a_max = 0, v_prev = 0;
    size_t stopped_windows = 0;
    for (size_t i = w; i < P.size(); i += w)
    {
        const double v = std::hypot(P[i].pose.x() - P[i - w].pose.x(), P[i].pose.y() - P[i - w].pose.y()) / 0.1;
        v_max = std::max(v_max, v);
        if (i > w) a_max = std::max(a_max, std::abs(v - v_prev) / 0.1);
        v_prev = v;
        if (v < 1e-6 && P[i].t - P[0].t > o.standing_s + 1 && P.back().t - P[i].t > o.standing_s + 1) ++stopped_windows;
    }
    EXPECT_LE(v_max, o.max_speed_m_s + 0.01);
    EXPECT_GT(v_max, 0.95 * o.max_speed_m_s);
    EXPECT_LE(a_max, o.max_accel_m_s2 * 1.1);
    EXPECT_GT(stopped_windows, 5u);
    EXPECT_NEAR(P[size_t(o.sample_rate_hz)].pose.x(), P[0].pose.x(), 1e-9);  // standing the first second
}

TEST(CarMotion, TurnRadiusTooLargeForTheBlocksIsRefused)
{
    const sim::CampusLayout l = layout();
    sim::CarOptions o;
    o.turn_radius_m = 40;
    o.route_length_m = 600;
    EXPECT_THROW(sim::driveCarRoute(l, sim::planCarRoute(l, o, 1), o, 0.0, 1, "test"), core::InputError);
}
