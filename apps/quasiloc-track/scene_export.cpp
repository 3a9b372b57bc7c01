#include "scene_export.h"

#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/stock_objects.h>

#include <quasiloc/core/error.h>

namespace quasiloc::app
{
namespace
{
mrpt::opengl::CSetOfLines::Ptr polyline(const core::Trajectory& traj, const mrpt::img::TColor& color)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setColor_u8(color);
    lines->setLineWidth(2.0f);
    for (size_t i = 0; i < traj.poses.size(); ++i)
    {
        const auto& p = traj.poses[i].pose;
        if (i == 0)
            lines->appendLine(p.x(), p.y(), p.z(), p.x(), p.y(), p.z());
        else
            lines->appendLineStrip(p.x(), p.y(), p.z());
    }
    return lines;
}
}  // namespace

void writeTrackingScene(const std::string& path, const map::LidarMap& map, const core::Trajectory& groundtruth,
                        const core::Trajectory& estimate, size_t max_map_points, size_t axes_every)
{
    mrpt::opengl::COpenGLScene scene;
    auto cloud = mrpt::opengl::CPointCloudColoured::Create();
    const size_t step = std::max<size_t>(1, (map.size() + max_map_points - 1) / std::max<size_t>(1, max_map_points));
    for (size_t i = 0; i < map.size(); i += step)
    {
        const float g = 0.2f + 0.8f * map.reflectivity(i);
        cloud->push_back(map.xs()[i], map.ys()[i], map.zs()[i], g, g, g);
    }
    cloud->setPointSize(1.5f);
    scene.insert(cloud);
    if (!groundtruth.poses.empty()) scene.insert(polyline(groundtruth, mrpt::img::TColor(0, 200, 0)));
    if (!estimate.poses.empty()) scene.insert(polyline(estimate, mrpt::img::TColor(230, 0, 0)));
    for (size_t i = 0; axes_every > 0 && i < estimate.poses.size(); i += axes_every)
    {
        auto axes = mrpt::opengl::stock_objects::CornerXYZSimple(0.15f, 2.0f);
        axes->setPose(estimate.poses[i].pose);
        scene.insert(axes);
    }
    core::require(scene.saveToFile(path), path, "cannot write the .3Dscene file");
}

}  // namespace quasiloc::app
