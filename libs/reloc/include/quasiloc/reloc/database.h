#pragma once
// The database of virtual views: for every view rendered from the LiDAR map, its pose, its point features
// (keypoints, descriptors) with the map point each keypoint lifts to through the quasi-image's provenance, its
// line segments with their LiDAR support, and its bag-of-words vector and per-keypoint words; plus the vocabulary and
// the inverted index trained on those descriptors, the camera model the views were rendered with, and the [Features]
// options (the localizer extracts query features with exactly these, so the two sides always agree).
//
// File format: MRPT serialization (mrpt::serialization::CArchive over a gzip stream, like the map file), a
// magic string and a format version first. Chosen over SQLite because the localizer needs the whole database
// in memory anyway (retrieval touches every view's word list), MRPT's archive is already a dependency, and it
// stores cv::Mat/Eigen data as flat arrays without a schema to maintain; a person inspects a database with
// `quasiloc-localize`'s diagnostics or the views' TUM file that quasiloc-build-db writes beside it.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/frontend/features.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/reloc/inverted_index.h>
#include <quasiloc/reloc/vocabulary.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct DatabaseView
{
    int id = -1;                       ///< index in Database::views
    mrpt::poses::CPose3D T_world_cam;  ///< where it was rendered
    /** Keypoints and descriptors, all of them (retrieval uses every descriptor); no dense map. */
    frontend::Features points;
    std::vector<WordId> words;  ///< per keypoint: its vocabulary word (the localizer's matching buckets)
    /** Per keypoint: the lifted map point in the world frame; NaN when the keypoint does not lift. */
    std::vector<Eigen::Vector3f> points_world;
    std::vector<frontend::LineSegment> lines;                 ///< segments detected on the quasi-image
    std::vector<std::array<Eigen::Vector3f, 2>> lines_world;  ///< their LiDAR support line's end points (NaN: none)
    float valid_fraction = 0;                                 ///< share of the quasi-image's pixels with a value
    BowVector bow;

    int numLifted() const;
    bool lifted(size_t i) const { return std::isfinite(points_world[i].x()); }
};

struct Database
{
    core::CameraModel camera;           ///< the views' pixel geometry
    frontend::FeatureOptions features;  ///< how the views' features were extracted
    double image_blur_sigma_px = 0;     ///< ... after this blur (preprocessImage), applied to queries too
    std::string map_file;               ///< the map it was built from (informative)
    size_t map_points = 0;
    std::vector<DatabaseView> views;
    Vocabulary vocabulary;
    InvertedIndex index;

    /** Writes atomically (temporary file + rename). */
    void save(const std::string& path) const;
    /** InputError naming `path` for a missing file, a file that is not a quasiloc database, or another
     *  format version. */
    static Database load(const std::string& path);
    /** "N views, M keypoints (K lifted), W words". */
    std::string summary() const;
};

/** What database views and queries go through before feature extraction: a Gaussian blur of sigma_px (none
 *  when 0). */
void preprocessImage(const cv::Mat& gray, double sigma_px, cv::Mat& out);

}  // namespace quasiloc::reloc
