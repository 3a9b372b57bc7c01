#pragma once
// Global localization by geometry: the stereo camera's own depth against the LiDAR map's geometry, with the
// gravity direction from the accelerometer. No appearance has to agree across modalities: on the simulated world
// the camera's texture and the LiDAR's reflectivity are different material responses (camera queries of the view
// database localize 0 %, quasiloc-localize), but stereo and LiDAR see the same walls, boxes and poles.
//
//  1. query: the frame's stereo points in the left camera frame (stereo_cloud.h);
//  1b. on a large map (more than retrieval_min_positions candidate positions to search), place retrieval first
//     (place_retrieval.h): the query's horizontal range profile against the profiles precomputed at the map's places
//     (place_index.h; read from places_file when the localizer is made, or else built at the first search that
//     needs them, so a run whose searches all stay within a small region prior never pays for them), and the
//     coarse search below scores
//     only the candidate positions within retrieval_radius_m of the retrieval_places best places, at the headings
//     within retrieval_yaw_margin_deg of theirs. The ambiguity test then weighs the places found there. A query whose
//     stereo points cover fewer than retrieval_min_sectors cells is "not localized" (searching the whole map would
//     take tens of seconds; the next frame is asked instead);
//  2. coarse search over 4 DoF: camera positions on a grid over the map's free space (view_sampling.h, at several
//     heights) x num_yaws headings, roll and pitch from gravity; a candidate's score is the mean squared distance
//     (truncated at coarse_truncation_m) of score_points query points to the map (map::DistanceField); with a
//     SearchSphere (a prior: relocalization near the last confirmed pose) only the positions inside it, and with
//     its heading only the headings within the heading's bound;
//  3. the best refine_candidates candidates that differ (> 0.5 m or > 20 deg apart) are refined over 6 DoF by
//     Gauss-Newton on the distance field, with the truncation shrinking (refine_truncations_m): query points the
//     map does not explain (people, clutter, stereo errors) stop pulling;
//  4. the best refined pose is polished by point-to-point ICP against the map points themselves (those near the query,
//     gathered through the visibility index, near_points.h; polish_truncations_m): the field's trilinear interpolant
//     has its minima at voxel centres, which biased the answer by a fraction of a voxel (simulated room, 4 cm voxels: 2
//     cm / 1 deg before polishing);
//  5. decision: the refined pose with the most inliers (points within inlier_m + 2 depth sigmas of the map) is the
//  answer when
//     their share is >= min_inlier_ratio and no refined pose farther than 0.3 m or 5 deg from it reaches
//     ambiguity_ratio of its inliers; otherwise "not localized" with the reason (never a weak guess).
//
// Options: [GeometricLocalization] (GeometricLocalizationOptions::declare, geometric_localizer_options.cpp).
//
// Frames: world z up (gravity along -z), as in the map frames of EuRoC/Vicon and KITTI.
#include <Eigen/Geometry>
#include <memory>
#include <mutex>
#include <optional>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/visibility_index.h>
#include <quasiloc/reloc/place_index.h>
#include <quasiloc/reloc/place_retrieval.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/reloc/view_sampling.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::reloc
{
struct GeometricLocalizationOptions : public core::DeclaredOptions
{
    double field_voxel_m = 0.04, field_max_distance_m = 0.5;
    map::DistanceFieldLayout field_layout = map::DistanceFieldLayout::Auto;
    double field_memory_budget_mb = 1024, field_focus_radius_m = 12;  ///< field_layout = streamed
    std::string field_tile_cache;                                     ///< field_layout = streamed
    /** Keys num_disparities ... stereo_downscale of this section. Why max_depth_m = 3.5 (farther SGBM points were
     *  biased) and stereo_downscale = 2 (4x faster, and more exact): docs/experiments.md. */
    StereoCloudOptions stereo;
    double grid_spacing_m = 0.25;
    std::vector<double> heights_m{0.5, 0.8, 1.1, 1.4, 1.7, 2.0};
    double clearance_m = 0.2;
    bool require_enclosed = true;
    /** view_sampling.h. 0 (a ceiling always needed): on the real V1_01 micro set only 30 positions have one, and
     *  with all 4,279 wall-enclosed ones the start is a wrong place (docs/benchmarks.md). */
    double ceiling_min_share = 0;
    std::vector<double> region;
    int num_yaws = 36;
    int score_points = 200;
    double coarse_truncation_m = 0.3;
    int refine_candidates = 16;
    std::vector<double> refine_truncations_m{0.3, 0.15, 0.08};
    int refine_iterations = 8;
    std::vector<double> polish_truncations_m{0.1, 0.05};
    double inlier_m = 0.06;
    /** inlierRatio: the depth part of an inlier's tolerance along the map's normal (a depth error moves a point along
     *  its ray, and off a surface by the ray's share along the normal), not whole. */
    bool check_depth_along_normal = false;
    /** Between the inlier ratios at true and at wrong poses (docs/experiments.md). */
    double min_inlier_ratio = 0.7;
    double ambiguity_ratio = 0.9;
    /** Place retrieval (place_retrieval.h). A room's few thousand positions are searched whole, as before: the
     *  stage is for maps of many rooms (docs/place_retrieval.md). */
    int retrieval_min_positions = 20000;
    std::string places_file;
    double place_spacing_m = 0.5;
    PlaceDescriptorOptions place;
    int retrieval_places = 100;
    double retrieval_radius_m = 0.5, retrieval_height_m = 0.35;
    double retrieval_yaw_margin_deg = 15;
    int retrieval_min_sectors = 6;
    /** The place profile of a stereo pair is made of its points up to this depth (the geometric check's stop at
     *  max_depth_m): a far wall is a few centimetres off, well within the profile's tolerance. */
    double place_query_depth_m = 6.0;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, or values that do not fit
     *  together (the stereo keys, the region, empty lists). */
    void check(const std::string& input) const;
};

/** A prior on where the camera is (a relocalization after a loss: near the last confirmed pose): the coarse search
 *  scores only the candidate positions within radius_m of centre (world), and the ambiguity test only weighs
 *  places found there. With R_world_cam (the orientation the lost track still knows from its gyroscope) the
 *  same holds for rotations: only headings within heading_bound_deg of it are searched and weighed, which
 *  leaves out a room's turned twin and a corridor seen from its other end. */
struct SearchSphere
{
    SearchSphere() = default;
    SearchSphere(const Eigen::Vector3d& centre_world, double radius) : centre(centre_world), radius_m(radius) {}

    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius_m = 0;
    std::optional<Eigen::Matrix3d> R_world_cam;
    double heading_bound_deg = 180;
    /** Whether R's heading (the azimuth of its viewing direction) is within heading_bound_deg of R_world_cam's
     *  (always, without a heading). Tilt is left to gravity, which levels every candidate. */
    bool headingAdmits(const Eigen::Matrix3d& R) const;
};

/** The answer to one query, with what a person needs to see why it failed. */
struct GeometricLocalization
{
    bool localized = false;
    std::string reason;                                             ///< why not localized (empty when localized)
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< the best refined pose (also when rejected)
    double inlier_ratio = 0;                                        ///< of the best refined pose
    double runner_up_inlier_ratio = 0;                        ///< best refined pose that is a different place (0: none)
    double runner_up_offset_m = 0, runner_up_offset_deg = 0;  ///< how far that place is from the answer
    bool ambiguous = false;  ///< rejected (only) because other places explain the points nearly as well
    /** Those places (refined poses, best first): a caller with another cue (e.g. the image) may pick among the
     *  answer and these. */
    std::vector<Eigen::Isometry3d> alternatives;
    size_t query_points = 0, candidates = 0;
    size_t retrieved_places = 0;  ///< places the retrieval stage kept (0: the stage did not run)
    double ms_cloud = 0, ms_retrieval = 0, ms_search = 0, ms_refine = 0;
};

class GeometricLocalizer
{
   public:
    /** Builds the distance field, a visibility index of the map and the candidate positions. InputError naming
     *  `input` (the map) for an empty map, a field too large, or no free position. `map` must outlive the localizer. */
    GeometricLocalizer(const map::LidarMap& map, const core::StereoRig& rig, const GeometricLocalizationOptions& o,
                       const std::string& input = "map");
    /** The same with a distance field built by buildField() and the map's visibility index, shared with others
     *  (tracking::MapContext): on a large map each is as big as the points. */
    GeometricLocalizer(const map::LidarMap& map, const core::StereoRig& rig, const GeometricLocalizationOptions& o,
                       std::shared_ptr<const map::DistanceField> field,
                       std::shared_ptr<const map::VisibilityIndex> index, const std::string& input = "map");
    /** The distance field of `o` (field_voxel_m, field_max_distance_m). InputError naming `input` as the
     *  constructor. */
    static std::shared_ptr<const map::DistanceField> buildField(const map::LidarMap& map,
                                                                const GeometricLocalizationOptions& o,
                                                                const std::string& input);
    ~GeometricLocalizer();

    /** Localizes one raw stereo pair; up_cam: world +z (the opposite of gravity) in the left camera frame.
     *  points_cam (optional): the pair's query points, for a caller that scores other poses on them too. */
    GeometricLocalization localize(const cv::Mat& left_raw, const cv::Mat& right_raw, const Eigen::Vector3d& up_cam,
                                   const SearchSphere* near = nullptr,
                                   std::vector<Eigen::Vector3f>* points_cam = nullptr) const;
    /** The same from query points already in the left camera frame; place_points: the pair's points for the place
     *  profile (placeStereoPoints; nullptr: points_cam). */
    GeometricLocalization localizePoints(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Vector3d& up_cam,
                                         const SearchSphere* near = nullptr,
                                         const std::vector<Eigen::Vector3f>* place_points = nullptr) const;

    /** Gauss-Newton refinement of T_world_cam (the refine stage alone); returns the share of inliers. */
    double refine(const std::vector<Eigen::Vector3f>& points_cam, Eigen::Isometry3d& T_world_cam) const;

    /** The query points of a raw stereo pair (left camera frame). */
    std::vector<Eigen::Vector3f> stereoPoints(const cv::Mat& left_raw, const cv::Mat& right_raw) const
    {
        return stereo_.compute(left_raw, right_raw);
    }
    /** Both clouds of a raw stereo pair from one matching: stereoPoints and, on a map with a retrieval stage,
     *  placeStereoPoints (else empty). A multi-frame query joins these of several frames (stereo_span.h). */
    std::pair<std::vector<Eigen::Vector3f>, std::vector<Eigen::Vector3f>> queryClouds(const cv::Mat& left_raw,
                                                                                      const cv::Mat& right_raw) const;
    /** The points of a raw stereo pair for its place profile: up to place_query_depth_m. */
    std::vector<Eigen::Vector3f> placeStereoPoints(const cv::Mat& left_raw, const cv::Mat& right_raw) const
    {
        return place_stereo_.compute(left_raw, right_raw);
    }
    /** Share of the points the map explains at T_world_cam (within inlier_m + 2 depth sigmas; with
     *  check_depth_along_normal, + 2 depth sigmas x |the ray's direction . the map's normal there|): how a tracker
     *  checks, independently of its own map term, that it is where it believes it is. */
    double inlierRatio(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Isometry3d& T_world_cam) const;

    const map::DistanceField& field() const { return *field_; }
    size_t positions() const { return positions_.size(); }
    const std::vector<Eigen::Vector3d>& candidatePositions() const { return positions_; }
    /** The places and their profiles (nullptr: no retrieval stage on this map), built at the first call when no
     *  places_file was given. Thread-safe. */
    const PlaceIndex* places() const;
    /** The retrieval stage alone: the best places for the query (empty when it has too few covered cells);
     *  top_k 0: retrieval_places. */
    std::vector<RetrievedPlace> retrieve(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Vector3d& up_cam,
                                         const SearchSphere* near = nullptr, size_t top_k = 0) const;
    /** Time spent building or reading the places (0 until they exist). */
    double placesBuildSeconds() const { return places_build_s_; }

    /** Point-to-point ICP of T_world_cam against the map points (the polish stage alone). */
    void polish(const std::vector<Eigen::Vector3f>& points_cam, Eigen::Isometry3d& T_world_cam) const;

   private:
    std::vector<double> pointWeights(const std::vector<Eigen::Vector3f>& points_cam) const;
    void setUpPlaces(const map::LidarMap& map, const std::string& input);
    void buildPlaces() const;
    /** Per searched position, the coarse yaws to score near the retrieved places (all false: none). */
    std::vector<std::vector<bool>> retrievedYaws(const std::vector<size_t>& searched,
                                                 const std::vector<RetrievedPlace>& retrieved) const;

    GeometricLocalizationOptions options_;
    std::shared_ptr<const map::DistanceField> field_;
    std::shared_ptr<const map::VisibilityIndex> index_;
    StereoCloud stereo_;
    StereoCloud place_stereo_;                ///< the same matching, points up to place_query_depth_m
    std::vector<Eigen::Vector3d> positions_;  ///< candidate camera positions (world)
    bool retrieval_ = false;                  ///< the map has a retrieval stage (large, or a places_file given)
    MapFingerprint map_fingerprint_;
    mutable std::once_flag places_once_;
    mutable std::unique_ptr<PlaceIndex> places_;
    mutable double places_build_s_ = 0;
};

/** Whether a stereo point at p_world (seen along ray_world) is explained by the map: within inlier_m +
 *  depth_tolerance_m of it, or with along_normal within inlier_m + depth_tolerance_m x |cos| of the angle between the
 *  ray and the field's gradient (the map's normal), the whole tolerance where the field has no gradient. */
bool depthAwareInlier(const map::DistanceField& field, const Eigen::Vector3f& p_world, const Eigen::Vector3f& ray_world,
                      double inlier_m, double depth_tolerance_m, bool along_normal);

/** The candidate camera positions of `o` on `map` (grid order), as the localizer samples them. InputError naming
 *  `input` when there is none. */
std::vector<Eigen::Vector3d> candidatePositions(const map::LidarMap& map, const GeometricLocalizationOptions& o,
                                                const std::string& input);
/** The places of `positions` (selectPlaces with o.place_spacing_m), as positions. */
std::vector<Eigen::Vector3f> placePositions(const std::vector<Eigen::Vector3d>& positions,
                                            const GeometricLocalizationOptions& o);

/** World +z in the camera frame, from accelerometer samples of a platform that is not accelerating much: the
 *  mean specific force (body frame) points up. R_cam_body: rotation of the body frame into the camera frame. */
Eigen::Vector3d upInCamera(const std::vector<Eigen::Vector3d>& acc_body, const Eigen::Matrix3d& R_cam_body);

}  // namespace quasiloc::reloc
