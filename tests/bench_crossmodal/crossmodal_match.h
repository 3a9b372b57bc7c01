#pragma once
// One frame of bench_crossmodal_match: correspondences between a camera image and the map's quasi-image rendered at
// a pose guess, found by dense descriptor search in the window the guess's uncertainty predicts, counted against
// the true pose.
//
// Map side (the quasi-image rendered at the guess): keypoints are Shi-Tomasi corners of the rank-equalised
// reflectivity and of the depth-edge channel (half the budget each), on pixels a map point won (its own pixel, so
// the pixel is that point's projection at the guess) whose descriptor footprint is mostly valid. Each keypoint's
// map point is its provenance; its true position is that point projected at the true pose.
// Camera side: for each keypoint, every pixel of the square window of radius r = window_base_px + f (rotation +
// translation / depth) (the guess's offsets, the keypoint's depth; at most window_max_px) around the keypoint's own
// position is a candidate, on a grid of step max(1, round(r / 16)) refined at step 1 around the best; the second
// best is the best candidate farther than max(3, 2 step) px from it. A match is accepted when
// distance(best) / distance(second) < ratio; correct when it lies within correct_px of the true position.
//
// Combinations: camera {raw, locally normalised} x map channel {reflectivity, rank-equalised reflectivity,
// depth edges, rank-equalised reflectivity and depth edges kept apart: per keypoint the channel whose match passes
// the ratio test more clearly} x descriptor {NCC, MIND-SSC, orientation field}. XFeat (camera vs the rank-equalised
// reflectivity as an 8-bit image, its own keypoints on both) matched by LighterGlue and by mutual nearest
// neighbour, each gated by the same window.
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/frontend/crossmodal_descriptors.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <string>

namespace quasiloc::bench
{
struct MatchBenchOptions
{
    int keypoints = 150;
    double min_keypoint_distance_px = 10;
    double min_valid_share = 0.8;  ///< of a keypoint's descriptor footprint
    double window_base_px = 8, window_max_px = 64;
    double ratio = 0.9;
    double correct_px = 3;
    int depth_bands = 4;  ///< rank equalisation per log-depth band
    double fill_sigma_px = 3;
    double depth_edge_sigma_px = 3, depth_edge_scale = 0.1;
    double local_norm_sigma_px = 8, local_norm_min_std = 4;
    frontend::CrossModalDescriptorOptions descriptors;
};

constexpr int kCameraVariants = 2;  ///< raw, locally normalised
constexpr int kMapChannels = 4;     ///< reflectivity, rank-equalised, depth edges, rank + depth kept apart
constexpr int kKinds = 3;           ///< NCC, MIND-SSC, orientation field
constexpr int kCombos = kCameraVariants * kMapChannels * kKinds;
constexpr int kXFeatRows = 2;  ///< LighterGlue, mutual NN
inline int comboIndex(int camera, int channel, int kind) { return (camera * kMapChannels + channel) * kKinds + kind; }
std::string cameraVariantName(int camera);
std::string mapChannelName(int channel);
frontend::DescriptorKind kindOf(int kind);

struct MatchCounts
{
    long keypoints = 0, reachable = 0, top1_correct = 0, accepted = 0, correct = 0;
    /** Expected top1_correct of a candidate drawn at random in each keypoint's window (the chance level). */
    double chance = 0;
    /** Sum of the best candidates' offsets from the true position (px), over the keypoints that had one. */
    double sum_dx = 0, sum_dy = 0;
    long found = 0;
    /** Sum over keypoints whose true position is a candidate of the share of window candidates farther from the map
     *  descriptor than the true position is (0.5: the descriptor says nothing; 1: the truth is the best). */
    double beaten_sum = 0;
    long beaten_n = 0;
    void add(const MatchCounts& o);
};

struct GuessResult
{
    std::array<MatchCounts, kCombos> combos{};
    std::array<MatchCounts, kXFeatRows> xfeat{};
    double ms_render = 0, ms_descriptors = 0, ms_search = 0, ms_xfeat = 0;
};

/** XFeat with LighterGlue and mutual NN; `lighterglue` null when that model is missing. */
struct XFeatMatchers
{
    std::unique_ptr<frontend::FeatureExtractor> extractor;
    std::unique_ptr<frontend::PointMatcher> lighterglue, mutual_nn;
};

/** The camera image's six descriptor fields (raw and locally normalised x three kinds) and its XFeat features. */
struct CameraSide
{
    std::array<std::array<frontend::DescriptorField, kKinds>, kCameraVariants> fields;
    frontend::Features xfeat;
};
CameraSide describeCamera(const cv::Mat& image_bgr_or_gray, const MatchBenchOptions& o, XFeatMatchers* xfeat);

/** Renders the quasi-image at T_world_guess, finds and counts the correspondences. */
GuessResult evaluateGuess(const CameraSide& cam, const core::CameraModel& camera, const map::LidarMap& map,
                          quasi::QuasiRenderer& renderer, const Eigen::Isometry3d& T_world_true,
                          const Eigen::Isometry3d& T_world_guess, double guess_t_m, double guess_rot_deg,
                          const MatchBenchOptions& o, XFeatMatchers* xfeat);

}  // namespace quasiloc::bench
