#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/frontend/features.h>
#include <sys/stat.h>

namespace quasiloc::frontend
{
const std::vector<std::pair<std::string, FeatureType>>& featureTypeNames()
{
    static const std::vector<std::pair<std::string, FeatureType>> names = {{"orb", FeatureType::Orb},
                                                                           {"sift", FeatureType::Sift},
                                                                           {"akaze", FeatureType::Akaze},
                                                                           {"xfeat", FeatureType::XFeat}};
    return names;
}

std::string toString(FeatureType t)
{
    for (const auto& [name, type] : featureTypeNames())
        if (type == t) return name;
    return "?";
}

void FeatureOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.addEnum("type", type, featureTypeNames(), "the point features");
    t.add("max_keypoints", max_keypoints, "", Range::between(1, 100000), "keypoint budget per image");
    t.add("grid_cols", grid_cols, "", Range::between(1, 256), "spreading grid columns");
    t.add("grid_rows", grid_rows, "", Range::between(1, 256), "spreading grid rows");
    t.add("detect_factor", detect_factor, "", Range::between(1, 20),
          "detectors are asked for this many candidates per kept keypoint");
    t.add("orb_fast_threshold", orb_fast_threshold, "", Range::between(1, 255),
          "ORB FAST threshold for images without a mask (camera images)");
    t.add("orb_fast_threshold_masked", orb_fast_threshold_masked, "", Range::between(1, 255),
          "ORB FAST threshold for images given with a validity mask (quasi-images)");
    t.add("orb_levels", orb_levels, "", Range::between(1, 16), "ORB pyramid levels (scale 1.2)");
    t.add("sift_contrast_threshold", sift_contrast_threshold, "", Range::strictlyBetween(0, 1),
          "SIFT contrast threshold");
    t.add("akaze_threshold", akaze_threshold, "", Range::strictlyBetween(0, 1), "AKAZE detector threshold");
    t.add("xfeat_model_path", xfeat_model_path,
          "XFeat ONNX file (e.g. ../shared/models/xfeat/xfeat_dyn_op11.onnx); required when type = xfeat");
    t.add("xfeat_detection_threshold", xfeat_detection_threshold, "", Range::fromUpTo(0, 1),
          "XFeat keypoint probability threshold after 5x5 NMS");
    t.add("dense_map", dense_map, "compute the dense map (needed by the hybrid line descriptor)");
}

void FeatureOptions::check(const std::string& input) const
{
    checkRanges(input, "Features");
    if (type != FeatureType::XFeat) return;
    const std::string key = input + ": " + core::iniKeyName("Features", "xfeat_model_path");
    struct stat st;
    core::require(!xfeat_model_path.empty(), key, "required when type = xfeat");
    core::require(::stat(xfeat_model_path.c_str(), &st) == 0 && S_ISREG(st.st_mode), key,
                  "'" + xfeat_model_path + "' is not a readable file");
}
}  // namespace quasiloc::frontend
