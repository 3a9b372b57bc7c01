#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/sim/campus_world.h>
#include <quasiloc/sim/spectral_materials.h>
#include <quasiloc/sim/world_builder.h>
#include <set>

using namespace quasiloc;

namespace
{
sim::WorldOptions smallCampus()
{
    sim::WorldOptions o;
    o.world = sim::ViconRoom::campus;
    o.campus.block_size_m = 40;
    o.campus.blocks_per_side = 2;
    o.max_cell_m = 2.0;
    o.texture_size_px = 64;
    o.shadow_map_px = 0;
    o.clearance_m = 1.5;
    o.materials = sim::MaterialSet::spectral;
    return o;
}

/** Cam0 positions along the street y = 0, 3.5 m left of its centreline (beside the parking strip of the blocks'
 *  kerb), at a car camera's height. */
std::vector<Eigen::Vector3f> pathAlongFirstStreet(const sim::CampusLayout& l)
{
    std::vector<Eigen::Vector3f> path;
    for (double x = 0; x <= l.street(l.blocks); x += 0.25) path.emplace_back(float(x), 3.5f, 1.65f);
    return path;
}

/** The triangles of `mesh` whose material is not one of the ground's. */
sim::Mesh furniture(const sim::Mesh& mesh)
{
    sim::Mesh out;
    out.vertices = mesh.vertices;
    for (const sim::Triangle& t : mesh.triangles)
        if (t.material != sim::kAsphalt && t.material != sim::kConcrete && t.material != sim::kRoadPaint)
            out.triangles.push_back(t);
    return out;
}
}  // namespace

TEST(CampusLayout, SizeFollowsTheOptionsAndBadBlocksAreRefused)
{
    sim::CampusOptions o;
    o.block_size_m = 100;
    o.blocks_per_side = 10;  // 1 km between the outer streets
    const sim::CampusLayout l = sim::makeCampusLayout(o, "test");
    EXPECT_DOUBLE_EQ(l.street(l.blocks) - l.street(0), 1000.0);
    EXPECT_GT(l.extent.sizes().x(), 1000.0 + o.street_width_m);
    EXPECT_TRUE(l.onCarriageway({250, 300}, 1.0));   // on the street x = 300
    EXPECT_TRUE(l.onCarriageway({500, 500}, 1.0));   // an intersection
    EXPECT_FALSE(l.onCarriageway({250, 250}, 0.0));  // a block's middle
    EXPECT_FALSE(l.onCarriageway({250, 305.5}, 1.0));
    o.block_size_m = 25;  // no room for a block inside 12 m of street and 2 x 3 m of sidewalk
    EXPECT_THROW(sim::makeCampusLayout(o, "test"), core::InputError);
}

TEST(CampusWorld, GroundIsContinuousAndEveryPartOfAStreetSceneIsThere)
{
    const sim::WorldOptions o = smallCampus();
    const sim::CampusLayout l = sim::makeCampusLayout(o.campus, "test");
    sim::WorldStats st;
    const sim::World w = sim::buildCampusWorld(o, l, 3, {}, &st);
    std::set<uint16_t> materials;
    for (const sim::Triangle& t : w.mesh.triangles) materials.insert(t.material);
    for (uint16_t m : {sim::kAsphalt, sim::kRoadPaint, sim::kGlass, sim::kFoliage, sim::kBark, sim::kCarPaint,
                       sim::kPersonClothes, sim::kConcrete})
        EXPECT_TRUE(materials.count(m)) << "material " << m << " missing";
    EXPECT_GT(st.objects_placed, 20u);
    ASSERT_EQ(w.lights.size(), 1u);  // the sun, far above
    EXPECT_GT(w.lights[0].position.z(), 500.f);
    // Continuous ground: every point of the extent lies on a horizontal triangle at the road or the kerb's height.
    std::vector<const sim::Triangle*> ground;
    for (const sim::Triangle& t : w.mesh.triangles)
    {
        const float z = w.mesh.vertices[t.v[0]].p.z();
        bool flat = true;
        for (uint32_t v : t.v) flat = flat && std::abs(w.mesh.vertices[v].p.z() - z) < 1e-4f;
        if (flat && z < 0.2f) ground.push_back(&t);
    }
    for (double x = l.extent.min().x() + 0.37; x < l.extent.max().x(); x += 3.1)
        for (double y = l.extent.min().y() + 0.41; y < l.extent.max().y(); y += 3.1)
        {
            bool covered = false;
            for (const sim::Triangle* t : ground)
            {
                const Eigen::Vector2f a = w.mesh.vertices[t->v[0]].p.head<2>(),
                                      b = w.mesh.vertices[t->v[1]].p.head<2>(),
                                      c = w.mesh.vertices[t->v[2]].p.head<2>();
                const Eigen::Vector2f p = Eigen::Vector2d(x, y).cast<float>();
                auto cross = [](const Eigen::Vector2f& u, const Eigen::Vector2f& v) {
                    return u.x() * v.y() - u.y() * v.x();
                };
                const float d1 = cross(b - a, p - a), d2 = cross(c - b, p - b), d3 = cross(a - c, p - c);
                if ((d1 >= -1e-4f && d2 >= -1e-4f && d3 >= -1e-4f) || (d1 <= 1e-4f && d2 <= 1e-4f && d3 <= 1e-4f))
                {
                    covered = true;
                    break;
                }
            }
            ASSERT_TRUE(covered) << "no ground at " << x << ", " << y;
        }
    // Road paint is bright at 905 nm against the asphalt (the markings show in the LiDAR's reflectivity); glass
    // is dark to the camera.
    const double paint = cv::mean(w.materials[sim::kRoadPaint].reflectivity)[0];
    const double asphalt = cv::mean(w.materials[sim::kAsphalt].reflectivity)[0];
    EXPECT_GT(paint, 4 * asphalt);
    EXPECT_LT(w.materials[sim::kGlass].meanAlbedo(), 0.2);
}

TEST(CampusWorld, FurnitureKeepsClearOfTheRoute)
{
    const sim::WorldOptions o = smallCampus();
    const sim::CampusLayout l = sim::makeCampusLayout(o.campus, "test");
    const std::vector<Eigen::Vector3f> path = pathAlongFirstStreet(l);
    sim::WorldStats free_st, kept_st;
    const sim::World free_world = sim::buildCampusWorld(o, l, 3, {}, &free_st);
    const sim::World kept = sim::buildCampusWorld(o, l, 3, path, &kept_st);
    EXPECT_GE(sim::minClearance(furniture(kept.mesh), path, 5.0), o.clearance_m);
    // Without the path, parked cars stand within 1.5 m of it (they park along that kerb): the check did act.
    EXPECT_LT(sim::minClearance(furniture(free_world.mesh), path, 5.0), o.clearance_m);
    EXPECT_GT(kept_st.objects_rejected, 0u);
}

TEST(CampusWorld, MappingTourDrivesEveryStreet)
{
    const sim::WorldOptions o = smallCampus();
    const sim::CampusLayout l = sim::makeCampusLayout(o.campus, "test");
    const std::vector<Eigen::Vector3f> tour = sim::campusMappingTour(l);
    const float end = float(l.street(l.blocks));
    for (int k = 0; k <= l.blocks; ++k)
        for (int axis = 0; axis < 2; ++axis)
        {
            const float c = float(l.street(k));
            bool driven = false;  // a leg from one end of the street to the other
            for (size_t i = 0; i + 1 < tour.size(); ++i)
            {
                const Eigen::Vector3f a = tour[i], b = tour[i + 1];
                if (std::abs(a[1 - axis] - c) < 1e-3f && std::abs(b[1 - axis] - c) < 1e-3f &&
                    std::abs(std::abs(b[axis] - a[axis]) - end) < 1e-3f)
                    driven = true;
            }
            EXPECT_TRUE(driven) << "street " << k << " along axis " << axis;
        }
    for (size_t i = 0; i + 1 < tour.size(); ++i)  // legs along the streets only
        EXPECT_TRUE(std::abs(tour[i].x() - tour[i + 1].x()) < 1e-3f || std::abs(tour[i].y() - tour[i + 1].y()) < 1e-3f);
}
