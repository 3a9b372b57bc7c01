#pragma once
// Renders the raw (distorted) 8-bit grayscale images of a calibrated stereo rig in the simulated world.
//
// Pipeline per camera (decisions in brackets):
//  1. visibility buffer of an undistorted pinhole with the camera's focal length scaled by render_scale and
//     a field of view wide enough to cover the whole distorted image [software z-buffer, rasterizer.h];
//  2. radiance = albedo texture (mip-mapped, footprint from depth and incidence) x interpolated vertex
//     irradiance (lights x time-varying intensity + ambient) [Lambertian, per-vertex shadows, world.h];
//  3. optional motion blur: mean radiance of several poses across the exposure time;
//  4. the camera's radial-tangential distortion, by cv::remap with a map precomputed from
//     core::CameraModel::unproject (so rendered pixels agree with CameraModel::project);
//  5. sensor: exposure (slow variation + partial auto-exposure after an illumination change), vignetting,
//     shot + read noise (a fixed table of normal deviates indexed by a hash of seed, frame, camera and pixel:
//     deterministic and fast), gamma, 8-bit quantisation.
// Left and right cameras render in two threads.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/sim/rasterizer.h>
#include <quasiloc/sim/world.h>
#include <vector>

namespace quasiloc::sim
{
/** Section [Appearance]; each key's unit, range and meaning: declare() (sim_options.cpp). */
struct AppearanceOptions : public core::DeclaredOptions
{
    double render_scale = 1.0;
    double exposure = 0.9;
    double exposure_variation = 0.12;
    double exposure_period_s = 11.0;
    double vignetting = 0.35;
    double gamma = 2.2;
    double read_noise = 0.8;
    double shot_noise = 0.3;
    int motion_blur_samples = 1;
    double exposure_time_ms = 6.0;
    bool illumination_change = false;
    double illumination_change_start_s = 20.0;
    double illumination_change_duration_s = 12.0;
    double illumination_change_factor = 0.35;
    double auto_exposure_compensation = 0.6;
    double auto_exposure_lag_s = 1.0;
    bool occluder = false;
    double occluder_speed_m_s = 0.8;
    double occluder_path_fraction = 0.35;
    double auto_exposure_step = 0;
    double auto_exposure_interval_s = 0.5;

    void declare(core::OptionTable& t) override;
    /** The declared ranges (InputError naming `input` and the key). */
    void check(const std::string& input) const;
};

/** Light intensity scale per light at time t_rel (seconds since the start of the trajectory). */
std::vector<float> lightScales(const AppearanceOptions& o, size_t num_lights, double t_rel);

/** Sensor gain at t_rel: base exposure x drift x partial compensation of the lights' dimming; with
 *  auto_exposure_step > 0 that value taken at the last update (every auto_exposure_interval_s) and rounded to the
 *  nearest of the levels exposure x (1 + step)^k. */
double exposureAt(const AppearanceOptions& o, size_t num_lights, double t_rel);

/** Mesh of the moving occluder at t_rel (empty when disabled); world frame. */
Mesh occluderMesh(const AppearanceOptions& o, const World& world, double t_rel);

class StereoRenderer
{
   public:
    StereoRenderer(const World& world, const core::StereoRig& rig, const AppearanceOptions& options, uint64_t seed);

    /** Renders both raw images. T_world_cam0 holds one pose per motion-blur sample (1 = no blur), in the
     *  order of the exposure; t_rel = seconds since the start of the trajectory (episodes, exposure); frame_index seeds
     *  the noise. */
    void render(const std::vector<mrpt::poses::CPose3D>& T_world_cam0, double t_rel, uint64_t frame_index,
                cv::Mat& left, cv::Mat& right);

    /** One camera (0 = left, 1 = right) without sensor effects: linear radiance in the raw (distorted) image,
     *  CV_32FC1, and optionally the visibility buffer of the internal pinhole. */
    cv::Mat renderRadiance(int cam, const mrpt::poses::CPose3D& T_world_cam0, double t_rel,
                           VisibilityBuffer* vis_out = nullptr);

    const PinholeIntrinsics& internalPinhole(int cam) const { return pinhole_[cam]; }
    const core::StereoRig& rig() const { return rig_; }

   private:
    void shadeInto(int cam, const Eigen::Isometry3f& T_cam_world, const std::vector<float>& shade, const Mesh& occ,
                   const std::vector<float>& occ_shade, cv::Mat& radiance_acc);
    void radianceDistorted(int cam, const std::vector<mrpt::poses::CPose3D>& T_world_cam0, double t_rel, cv::Mat& out,
                           VisibilityBuffer* vis_out);
    cv::Mat sensor(int cam, const cv::Mat& radiance, double t_rel, uint64_t frame_index) const;

    const World& world_;
    core::StereoRig rig_;
    AppearanceOptions opt_;
    uint64_t seed_;
    PinholeIntrinsics pinhole_[2];
    cv::Mat map1_[2], map2_[2];  ///< remap from raw pixels to the internal pinhole (fixed point)
    cv::Mat vignette_[2];        ///< CV_32FC1 gain per raw pixel
    std::vector<float> normal_table_;
    std::vector<uint8_t> gamma_lut_;
    VisibilityBuffer vis_[2];
};

}  // namespace quasiloc::sim
