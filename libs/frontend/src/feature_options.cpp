#include <quasiloc/core/error.h>
#include <quasiloc/frontend/features.h>
#include <sys/stat.h>

#include "ini_read.h"

namespace quasiloc::frontend
{
using namespace detail;

std::string toString(FeatureType t)
{
    switch (t)
    {
        case FeatureType::Orb: return "orb";
        case FeatureType::Sift: return "sift";
        case FeatureType::Akaze: return "akaze";
        case FeatureType::XFeat: return "xfeat";
    }
    return "?";
}

void FeatureOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    type = readString(cfg, s, "type", type);
    max_keypoints = readInt(cfg, s, "max_keypoints", max_keypoints);
    grid_cols = readInt(cfg, s, "grid_cols", grid_cols);
    grid_rows = readInt(cfg, s, "grid_rows", grid_rows);
    detect_factor = readDouble(cfg, s, "detect_factor", detect_factor);
    orb_fast_threshold = readInt(cfg, s, "orb_fast_threshold", orb_fast_threshold);
    orb_fast_threshold_masked = readInt(cfg, s, "orb_fast_threshold_masked", orb_fast_threshold_masked);
    orb_levels = readInt(cfg, s, "orb_levels", orb_levels);
    sift_contrast_threshold = readDouble(cfg, s, "sift_contrast_threshold", sift_contrast_threshold);
    akaze_threshold = readDouble(cfg, s, "akaze_threshold", akaze_threshold);
    xfeat_model_path = readString(cfg, s, "xfeat_model_path", xfeat_model_path);
    xfeat_detection_threshold = readDouble(cfg, s, "xfeat_detection_threshold", xfeat_detection_threshold);
    dense_map = readBool(cfg, s, "dense_map", dense_map);
}

void FeatureOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "type", type, 30, 40, "orb | sift | akaze | xfeat");
    c.write(s, "max_keypoints", max_keypoints, 30, 40, "keypoint budget per image");
    c.write(s, "grid_cols", grid_cols, 30, 40, "spreading grid columns");
    c.write(s, "grid_rows", grid_rows, 30, 40, "spreading grid rows");
    c.write(s, "detect_factor", detect_factor, 30, 40, "candidates detected per kept keypoint");
    c.write(s, "orb_fast_threshold", orb_fast_threshold, 30, 40, "ORB FAST threshold (images without a mask)");
    c.write(s, "orb_fast_threshold_masked", orb_fast_threshold_masked, 30, 40,
            "ORB FAST threshold (images with a validity mask: quasi-images)");
    c.write(s, "orb_levels", orb_levels, 30, 40, "ORB pyramid levels");
    c.write(s, "sift_contrast_threshold", sift_contrast_threshold, 30, 40, "SIFT contrast threshold");
    c.write(s, "akaze_threshold", akaze_threshold, 30, 40, "AKAZE detector threshold");
    c.write(s, "xfeat_model_path", xfeat_model_path, 30, 40, "XFeat ONNX file (type = xfeat)");
    c.write(s, "xfeat_detection_threshold", xfeat_detection_threshold, 30, 40, "XFeat keypoint probability");
    c.write(s, "dense_map", dense_map, 30, 40, "compute the dense map for line descriptors");
}

FeatureType FeatureOptions::featureType() const
{
    if (type == "orb") return FeatureType::Orb;
    if (type == "sift") return FeatureType::Sift;
    if (type == "akaze") return FeatureType::Akaze;
    if (type == "xfeat") return FeatureType::XFeat;
    throw core::InputError("[Features] type", "'" + type + "' is not one of orb, sift, akaze, xfeat");
}

void FeatureOptions::check(const std::string& input) const
{
    const std::string S = "Features";
    requireKey(type == "orb" || type == "sift" || type == "akaze" || type == "xfeat", input, S, "type",
               "'" + type + "' is not one of orb, sift, akaze, xfeat");
    requireKey(max_keypoints >= 1 && max_keypoints <= 100000, input, S, "max_keypoints", "must be in [1, 100000]");
    requireKey(grid_cols >= 1 && grid_cols <= 256, input, S, "grid_cols", "must be in [1, 256]");
    requireKey(grid_rows >= 1 && grid_rows <= 256, input, S, "grid_rows", "must be in [1, 256]");
    requireKey(detect_factor >= 1 && detect_factor <= 20, input, S, "detect_factor", "must be in [1, 20]");
    requireKey(orb_fast_threshold >= 1 && orb_fast_threshold <= 255, input, S, "orb_fast_threshold",
               "must be in [1, 255]");
    requireKey(orb_fast_threshold_masked >= 1 && orb_fast_threshold_masked <= 255, input, S, "orb_fast_threshold_masked",
               "must be in [1, 255]");
    requireKey(orb_levels >= 1 && orb_levels <= 16, input, S, "orb_levels", "must be in [1, 16]");
    requireKey(sift_contrast_threshold > 0 && sift_contrast_threshold < 1, input, S, "sift_contrast_threshold",
               "must be in (0, 1)");
    requireKey(akaze_threshold > 0 && akaze_threshold < 1, input, S, "akaze_threshold", "must be in (0, 1)");
    requireKey(xfeat_detection_threshold >= 0 && xfeat_detection_threshold < 1, input, S,
               "xfeat_detection_threshold", "must be in [0, 1)");
    if (type == "xfeat")
    {
        struct stat st;
        requireKey(!xfeat_model_path.empty(), input, S, "xfeat_model_path", "required when type = xfeat");
        requireKey(::stat(xfeat_model_path.c_str(), &st) == 0 && S_ISREG(st.st_mode), input, S, "xfeat_model_path",
                   "'" + xfeat_model_path + "' is not a readable file");
    }
}
}  // namespace quasiloc::frontend
