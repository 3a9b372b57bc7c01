#pragma once
// Monocular camera models: pinhole with no distortion, radial-tangential (EuRoC "radial-tangential",
// OpenCV/MRPT "plumb_bob") and equidistant (Kannala-Brandt, OpenCV fisheye).
//
// Convention: a camera-frame point p_cam = (x, y, z), z forward, x right, y down, projects to pixel
// u = (fx * xd + cx, fy * yd + cy) where (xd, yd) = distort(x/z, y/z).
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/img/TCamera.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <opencv2/core.hpp>
#include <string>

namespace quasiloc::core
{
enum class DistortionModel
{
    None,        ///< ideal pinhole
    RadTan,      ///< k1 k2 p1 p2 k3 (OpenCV order); MRPT "plumb_bob", EuRoC "radial-tangential"
    Equidistant  ///< k1 k2 k3 k4 (OpenCV fisheye); MRPT "kannala_brandt", EuRoC "equidistant"
};

std::string toString(DistortionModel m);
/** Accepts our names and MRPT/EuRoC/OpenCV aliases; throws InputError naming `input` otherwise. */
DistortionModel distortionModelFromString(const std::string& name, const std::string& input);

class CameraModel
{
   public:
    int width = 0, height = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    DistortionModel model = DistortionModel::None;
    /// RadTan: k1 k2 p1 p2 k3; Equidistant: k1 k2 k3 k4 (5th unused); None: unused.
    std::array<double, 5> dist{0, 0, 0, 0, 0};

    CameraModel() = default;
    static CameraModel pinhole(int width, int height, double fx, double fy, double cx, double cy);

    /** The same camera at 1/factor of the resolution (factor 2: each pixel covers 2 x 2 of this one's): a pixel
     *  centre u of this camera is (u + 0.5) / factor - 0.5 there; the distortion, on normalised coordinates, is
     *  unchanged. Its size is the whole coarse pixels: a last row or column of fewer than factor pixels is left
     *  out (a 1242x375 KITTI image is 621x187 at factor 2). InputError for a factor < 1 or above the size. */
    CameraModel downscaled(int factor) const;

    /** Projects p_cam. Returns false (and leaves outputs unspecified) when z <= min_depth.
     *  J_px_p, if given, receives d(pixel)/d(p_cam), 2x3. Does not test image bounds. */
    bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px, Eigen::Matrix<double, 2, 3>* J_px_p = nullptr,
                 double min_depth = 1e-6) const;

    /** Normalised (undistorted) coordinates (x/z, y/z) -> distorted normalised coordinates.
     *  J, if given, receives d(distorted)/d(undistorted). */
    Eigen::Vector2d distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* J = nullptr) const;
    /** Inverse of distort() by Gauss-Newton; accurate to ~1e-12 within the image. */
    Eigen::Vector2d undistort(const Eigen::Vector2d& xd) const;

    /** Pixel -> point on the normalised plane z = 1 (so depth * unproject(px) is the 3D point). */
    Eigen::Vector3d unproject(const Eigen::Vector2d& px) const;
    /** Pixel -> unit-length bearing vector. */
    Eigen::Vector3d unprojectBearing(const Eigen::Vector2d& px) const;

    bool isInImage(const Eigen::Vector2d& px, double margin_px = 0) const
    {
        return px.x() >= -0.5 + margin_px && px.y() >= -0.5 + margin_px && px.x() < width - 0.5 - margin_px &&
               px.y() < height - 0.5 - margin_px;
    }

    cv::Matx33d K() const;
    /** Distortion coefficients as OpenCV wants them (5 for RadTan, 4 for Equidistant, 0 for None). */
    cv::Mat distCoeffs() const;

    /** Rejects a model that cannot be used (size, focal lengths, non-finite values). */
    void check(const std::string& input) const;

    mrpt::img::TCamera toTCamera() const;
    static CameraModel fromTCamera(const mrpt::img::TCamera& cam);

    /** INI keys compatible with mrpt::img::TCamera: resolution=[w h], cx, cy, fx, fy,
     *  dist=[k1 k2 p1 p2 k3] (or k1..k4 for kannala_brandt), distortion_model=plumb_bob|kannala_brandt|none. */
    static CameraModel loadFromIni(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
    void saveToIni(mrpt::config::CConfigFileBase& cfg, const std::string& section) const;

    /** An EuRoC/Kalibr sensor.yaml (camera_model: pinhole; radial-tangential or equidistant). */
    static CameraModel fromEurocYaml(const std::string& path);
};

}  // namespace quasiloc::core
