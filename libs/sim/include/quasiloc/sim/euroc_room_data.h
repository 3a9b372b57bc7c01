#pragma once
// Reader of the 3D line maps of the EuRoC Vicon rooms (maps/lines/*.txt), one of the two descriptions of
// the rooms that survive without the Leica scans; the other, the GMMLoc Gaussian-mixture maps
// (maps/gmm/*.gmm), is read by quasiloc/map/gmm.h.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace quasiloc::sim
{
struct LineSegment3D
{
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
};

/** Reads "x1 y1 z1 x2 y2 z2" rows (metres); InputError naming file and line for anything else. */
std::vector<LineSegment3D> readLineSegments(const std::string& path);

}  // namespace quasiloc::sim
