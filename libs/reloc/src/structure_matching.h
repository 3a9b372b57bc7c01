#pragma once
// Dense cross-modal matching at a pose guess for the structure localizer (structure_localizer.h): the map rendered at
// the guess gives keypoints (Shi-Tomasi corners of the rank-equalised reflectivity and of the depth-edge channel, on
// pixels a map point won: the pixel is that point's projection at the guess), each is searched in the camera's
// orientation field within a square window of radius r = base + f (sigma_rad + sigma_m / depth) (at most max) around
// its pixel, kept when best / second best distance < ratio (the second best farther than max(3, 2 step) px), and
// lifted to its map point through the provenance.
#include <Eigen/Core>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/frontend/crossmodal_descriptors.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_image.h>
#include <quasiloc/reloc/structure_localizer.h>
#include <vector>

namespace quasiloc::reloc
{
struct GuessCorrespondences
{
    std::vector<Eigen::Vector2d> camera_px;
    std::vector<Eigen::Vector3d> p_world;
    std::vector<Eigen::Vector2d> guess_px;  ///< the keypoint's pixel at the guess
    int keypoints = 0;                      ///< map keypoints searched
};

/** The map's two channels at the quasi-image: rank-equalised reflectivity and depth edges, holes filled. */
std::vector<cv::Mat> structureChannels(const quasi::QuasiImage& q, const StructureLocalizerOptions& o);

/** Correspondences of the camera field with the quasi-image q rendered at the guess (in the camera's geometry). */
GuessCorrespondences matchAtGuess(const frontend::DescriptorField& camera_field, const quasi::QuasiImage& q,
                                  const map::LidarMap& map, const core::CameraModel& camera, double sigma_m,
                                  double sigma_rad, const StructureLocalizerOptions& o);

/** The correspondences whose displacement (camera pixel - the keypoint's pixel at the guess) lies within
 *  radius_px of the displacement most of them share (the one with the most others within radius_px): near the
 *  truth the correct matches move together (the guess's rotation error shifts them all alike), wrong ones scatter
 *  over the window. `at_guess`: each correspondence's pixel at the guess. radius_px <= 0: all kept. */
GuessCorrespondences consensusOfDisplacements(const GuessCorrespondences& m,
                                              const std::vector<Eigen::Vector2d>& at_guess, double radius_px);

}  // namespace quasiloc::reloc
