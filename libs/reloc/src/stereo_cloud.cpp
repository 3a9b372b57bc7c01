// StereoCloud: dense stereo points of one frame (stereo_cloud.h).
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <unordered_set>

namespace quasiloc::reloc
{
void StereoCloudOptions::check(const std::string& input, const std::string& section) const
{
    auto key = [&](const char* k) { return input + ": " + core::iniKeyName(section, k); };
    core::require(num_disparities >= 16 && num_disparities % 16 == 0, key("num_disparities"),
                  "must be a positive multiple of 16");
    core::require(block_size >= 1 && block_size % 2 == 1, key("block_size"), "must be odd and >= 1");
    core::require(uniqueness_ratio >= 0 && uniqueness_ratio <= 100, key("uniqueness_ratio"), "must be in [0, 100]");
    core::require(min_depth_m > 0 && max_depth_m > min_depth_m, key("max_depth_m"),
                  "needs 0 < min_depth_m < max_depth_m");
    core::require(voxel_m >= 0, key("query_voxel_m"), "must be >= 0");
    core::require(max_points >= 10, key("max_points"), "must be >= 10");
    core::require(disparity_sigma_px >= 0, key("disparity_sigma_px"), "must be >= 0");
    core::require(downscale == 1 || downscale == 2, key("stereo_downscale"), "must be 1 or 2");
    core::require(num_disparities % (16 * downscale) == 0, key("num_disparities"),
                  "must be a multiple of 16 x stereo_downscale");
}

namespace
{
/** The voxels StereoCloud::points has filled: a bit per voxel of the box where the points can be (their frustum),
 *  a hash set for any other (none, unless rounding puts a point outside). Bits, because a frame inserts tens of
 *  thousands of points and a hash set alone was most of the cloud's cost. */
class VoxelSet
{
   public:
    explicit VoxelSet(const VoxelBox& box) : box_(box), bits_(size_t((box.nx * box.ny * box.nz + 63) / 64), 0) {}
    /** True when voxel (ix, iy, iz) was empty (it is filled now). */
    bool insert(int64_t ix, int64_t iy, int64_t iz)
    {
        const int64_t x = ix - box_.x0, y = iy - box_.y0, z = iz - box_.z0;
        if (x >= 0 && x < box_.nx && y >= 0 && y < box_.ny && z >= 0 && z < box_.nz)
        {
            const size_t bit = size_t((z * box_.ny + y) * box_.nx + x);
            uint64_t& word = bits_[bit >> 6];
            const uint64_t mask = uint64_t(1) << (bit & 63);
            const bool fresh = !(word & mask);
            word |= mask;
            return fresh;
        }
        return others_.insert(((ix & 0x1fffff) << 42) | ((iy & 0x1fffff) << 21) | (iz & 0x1fffff)).second;
    }

   private:
    VoxelBox box_;
    std::vector<uint64_t> bits_;
    std::unordered_set<int64_t> others_;  ///< keys of 21 bits per axis, as before the box
};

/** The voxel indices a point of the cloud can have: the rectified left camera's frustum between min_depth_m and
 *  max_depth_m, one voxel of margin for rounding. Empty (the hash set alone) when there is no voxel thinning or
 *  the box would hold more than kMaxVoxels voxels. */
VoxelBox frustumVoxels(const core::StereoRectification& rect, const cv::Size& size, const StereoCloudOptions& o)
{
    constexpr int64_t kMaxVoxels = int64_t(1) << 23;  // a bit each: 1 MB
    const double v = o.voxel_m;
    if (!(v > 0)) return {};
    const double f = rect.P_left(0, 0), cx = rect.P_left(0, 2), cy = rect.P_left(1, 2);
    // Pixel centres lie in [-0.5, size - 0.5] at any downscale; x / z is linear in u, so the corners bound it.
    const double x_lo = (-0.5 - cx) / f, x_hi = (size.width - 0.5 - cx) / f;
    const double y_lo = (-0.5 - cy) / f, y_hi = (size.height - 0.5 - cy) / f;
    auto cells = [&](double a_per_z, double b_per_z, int64_t& lo, int64_t& n) {
        const double zs[2] = {o.min_depth_m, o.max_depth_m};
        double mn = 0, mx = 0;
        for (double z : zs)
            for (double t : {a_per_z * z, b_per_z * z})
            {
                mn = std::min(mn, t);
                mx = std::max(mx, t);
            }
        lo = int64_t(std::floor(mn / v)) - 1;
        n = int64_t(std::floor(mx / v)) + 2 - lo;
    };
    VoxelBox box;
    cells(x_lo, x_hi, box.x0, box.nx);
    cells(y_lo, y_hi, box.y0, box.ny);
    cells(1.0, 1.0, box.z0, box.nz);
    if (box.nx * box.ny > kMaxVoxels / box.nz) return {};
    return box;
}
}  // namespace

StereoCloud::StereoCloud(const core::StereoRig& rig, const StereoCloudOptions& options)
    : options_(options), rect_(rig.rectify(0.0)), size_(rig.left.width, rig.left.height)
{
    options_.check("stereo cloud", "GeometricLocalization");
    voxels_ = frustumVoxels(rect_, size_, options_);
}

std::vector<Eigen::Vector3f> StereoCloud::compute(const cv::Mat& left_raw, const cv::Mat& right_raw,
                                                  const std::string& input) const
{
    return points(disparity(left_raw, right_raw, input));
}

StereoDisparity StereoCloud::disparity(const cv::Mat& left_raw, const cv::Mat& right_raw,
                                       const std::string& input) const
{
    for (const cv::Mat* im : {&left_raw, &right_raw})
    {
        core::require(!im->empty() && im->type() == CV_8UC1, input, "stereo images must be 8-bit grey");
        core::require(im->size() == size_, input,
                      "image size " + std::to_string(im->cols) + " x " + std::to_string(im->rows) +
                          " differs from the calibration's " + std::to_string(size_.width) + " x " +
                          std::to_string(size_.height));
    }
    StereoDisparity d;
    rect_.rectify(left_raw, right_raw, d.left_rect, d.right_rect);
    const int s = options_.downscale;
    d.scale = s;
    cv::Mat left = d.left_rect, right = d.right_rect;
    if (s > 1)
    {
        cv::resize(d.left_rect, left, cv::Size(), 1.0 / s, 1.0 / s, cv::INTER_AREA);
        cv::resize(d.right_rect, right, cv::Size(), 1.0 / s, 1.0 / s, cv::INTER_AREA);
    }
    const int b = options_.block_size;
    auto sgbm = cv::StereoSGBM::create(0, options_.num_disparities / s, b, 8 * b * b, 32 * b * b, 1, 63,
                                       options_.uniqueness_ratio, 100 / (s * s), 2, cv::StereoSGBM::MODE_SGBM_3WAY);
    sgbm->compute(left, right, d.disparity);  // CV_16S, disparity x 16, in pixels of the (scaled) pair
    return d;
}

std::vector<Eigen::Vector3f> StereoCloud::points(const StereoDisparity& d) const
{
    const cv::Mat& disparity = d.disparity;
    const int s = d.scale;

    const double f = rect_.P_left(0, 0), cx = rect_.P_left(0, 2), cy = rect_.P_left(1, 2);
    const double fb = f * rect_.baseline_m;
    const Eigen::Matrix3f R_cam_rect =
        Eigen::Matrix3d(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(rect_.R_left.val))
            .transpose()
            .cast<float>();
    std::vector<Eigen::Vector3f> points;
    VoxelSet occupied(voxels_);
    const double v = options_.voxel_m;
    for (int y = 0; y < disparity.rows; ++y)
    {
        const int16_t* row = disparity.ptr<int16_t>(y);
        for (int x = 0; x < disparity.cols; ++x)
        {
            if (row[x] <= 0) continue;
            const double z = fb / (s * row[x] / 16.0);
            if (z < options_.min_depth_m || z > options_.max_depth_m) continue;
            // Centre of the scaled pixel in full-resolution coordinates.
            const double px_u = s * (x + 0.5) - 0.5, px_v = s * (y + 0.5) - 0.5;
            const Eigen::Vector3f p_rect(float((px_u - cx) * z / f), float((px_v - cy) * z / f), float(z));
            if (v > 0 && !occupied.insert(int64_t(std::floor(p_rect.x() / v)), int64_t(std::floor(p_rect.y() / v)),
                                          int64_t(std::floor(p_rect.z() / v))))
                continue;
            points.push_back(R_cam_rect * p_rect);
        }
    }
    if (points.size() > size_t(options_.max_points))
    {
        std::vector<Eigen::Vector3f> kept;
        const double step = double(points.size()) / options_.max_points;
        for (int i = 0; i < options_.max_points; ++i) kept.push_back(points[size_t(i * step)]);
        points.swap(kept);
    }
    return points;
}

}  // namespace quasiloc::reloc
