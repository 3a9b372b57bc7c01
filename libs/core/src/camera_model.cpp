#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/yaml_read.h>

#include <algorithm>
#include <cmath>

namespace quasiloc::core
{
std::string toString(DistortionModel m)
{
    switch (m)
    {
        case DistortionModel::None: return "none";
        case DistortionModel::RadTan: return "plumb_bob";
        case DistortionModel::Equidistant: return "kannala_brandt";
    }
    return "?";
}

DistortionModel distortionModelFromString(const std::string& name, const std::string& input)
{
    std::string n = name;
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
    if (n == "none" || n == "pinhole" || n.empty()) return DistortionModel::None;
    if (n == "plumb_bob" || n == "radtan" || n == "radial-tangential" || n == "radial_tangential")
        return DistortionModel::RadTan;
    if (n == "kannala_brandt" || n == "equidistant" || n == "fisheye" || n == "equi")
        return DistortionModel::Equidistant;
    throw InputError(input, "unknown distortion model '" + name +
                                "' (expected none, plumb_bob/radtan/radial-tangential or "
                                "kannala_brandt/equidistant)");
}

CameraModel CameraModel::pinhole(int width, int height, double fx, double fy, double cx, double cy)
{
    CameraModel c;
    c.width = width;
    c.height = height;
    c.fx = fx;
    c.fy = fy;
    c.cx = cx;
    c.cy = cy;
    return c;
}

CameraModel CameraModel::downscaled(int factor) const
{
    core::require(factor >= 1 && width >= factor && height >= factor, "CameraModel::downscaled",
                  "factor " + std::to_string(factor) + " must be >= 1 and at most the image size " +
                      std::to_string(width) + "x" + std::to_string(height));
    const double s = 1.0 / factor;
    CameraModel c = *this;
    c.width = width / factor;
    c.height = height / factor;
    c.fx = fx * s;
    c.fy = fy * s;
    c.cx = (cx + 0.5) * s - 0.5;
    c.cy = (cy + 0.5) * s - 0.5;
    return c;
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xn, Eigen::Matrix2d* J) const
{
    const double x = xn.x(), y = xn.y();
    switch (model)
    {
        case DistortionModel::None:
            if (J) J->setIdentity();
            return xn;
        case DistortionModel::RadTan:
        {
            const double k1 = dist[0], k2 = dist[1], p1 = dist[2], p2 = dist[3], k3 = dist[4];
            const double r2 = x * x + y * y;
            const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
            if (J)
            {
                // d(radial)/d(r2)
                const double dr = k1 + r2 * (2 * k2 + 3 * k3 * r2);
                (*J)(0, 0) = radial + 2 * x * x * dr + 2 * p1 * y + 6 * p2 * x;
                (*J)(0, 1) = 2 * x * y * dr + 2 * p1 * x + 2 * p2 * y;
                (*J)(1, 0) = 2 * x * y * dr + 2 * p1 * x + 2 * p2 * y;
                (*J)(1, 1) = radial + 2 * y * y * dr + 6 * p1 * y + 2 * p2 * x;
            }
            return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                    y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
        }
        case DistortionModel::Equidistant:
        {
            const double k1 = dist[0], k2 = dist[1], k3 = dist[2], k4 = dist[3];
            const double r = std::sqrt(x * x + y * y);
            if (r < 1e-10)
            {
                if (J) J->setIdentity();
                return xn;
            }
            const double th = std::atan(r), th2 = th * th;
            const double poly = 1 + th2 * (k1 + th2 * (k2 + th2 * (k3 + th2 * k4)));
            const double thd = th * poly;
            const double s = thd / r;  // scale applied to (x, y)
            if (J)
            {
                const double dthd_dth = 1 + th2 * (3 * k1 + th2 * (5 * k2 + th2 * (7 * k3 + th2 * 9 * k4)));
                const double dth_dr = 1 / (1 + r * r);
                const double ds_dr = (dthd_dth * dth_dr * r - thd) / (r * r);
                (*J)(0, 0) = s + ds_dr * x * x / r;
                (*J)(0, 1) = ds_dr * x * y / r;
                (*J)(1, 0) = ds_dr * x * y / r;
                (*J)(1, 1) = s + ds_dr * y * y / r;
            }
            return {s * x, s * y};
        }
    }
    return xn;
}

Eigen::Vector2d CameraModel::undistort(const Eigen::Vector2d& xd) const
{
    if (model == DistortionModel::None) return xd;
    // Gauss-Newton on distort(x) = xd, starting from the distorted point.
    Eigen::Vector2d x = xd;
    Eigen::Matrix2d J;
    for (int it = 0; it < 30; ++it)
    {
        const Eigen::Vector2d err = distort(x, &J) - xd;
        if (err.squaredNorm() < 1e-26) break;
        const Eigen::Vector2d step = J.inverse() * err;
        x -= step;
        if (!std::isfinite(x.x()) || !std::isfinite(x.y())) return {NAN, NAN};
    }
    return x;
}

bool CameraModel::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px, Eigen::Matrix<double, 2, 3>* J_px_p,
                          double min_depth) const
{
    const double z = p_cam.z();
    if (!(z > min_depth)) return false;
    const double iz = 1.0 / z;
    const Eigen::Vector2d xn(p_cam.x() * iz, p_cam.y() * iz);
    Eigen::Matrix2d Jd;
    const Eigen::Vector2d xd = distort(xn, J_px_p ? &Jd : nullptr);
    px = {fx * xd.x() + cx, fy * xd.y() + cy};
    if (J_px_p)
    {
        Eigen::Matrix<double, 2, 3> Jn;
        Jn << iz, 0, -xn.x() * iz, 0, iz, -xn.y() * iz;
        Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
        F(0, 0) = fx;
        F(1, 1) = fy;
        *J_px_p = F * Jd * Jn;
    }
    return true;
}

Eigen::Vector3d CameraModel::unproject(const Eigen::Vector2d& px) const
{
    const Eigen::Vector2d xd((px.x() - cx) / fx, (px.y() - cy) / fy);
    const Eigen::Vector2d xn = undistort(xd);
    return {xn.x(), xn.y(), 1.0};
}

Eigen::Vector3d CameraModel::unprojectBearing(const Eigen::Vector2d& px) const { return unproject(px).normalized(); }

cv::Matx33d CameraModel::K() const { return cv::Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1); }

cv::Mat CameraModel::distCoeffs() const
{
    switch (model)
    {
        case DistortionModel::None: return cv::Mat::zeros(1, 5, CV_64F);
        case DistortionModel::RadTan: return (cv::Mat_<double>(1, 5) << dist[0], dist[1], dist[2], dist[3], dist[4]);
        case DistortionModel::Equidistant: return (cv::Mat_<double>(1, 4) << dist[0], dist[1], dist[2], dist[3]);
    }
    return {};
}

void CameraModel::check(const std::string& input) const
{
    require(width > 0 && height > 0, input,
            "image size must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
    require(std::isfinite(fx) && std::isfinite(fy) && fx > 0 && fy > 0, input,
            "focal lengths fx, fy must be positive and finite");
    require(std::isfinite(cx) && std::isfinite(cy), input, "principal point cx, cy must be finite");
    for (double d : dist) require(std::isfinite(d), input, "distortion coefficients must be finite");
}

mrpt::img::TCamera CameraModel::toTCamera() const
{
    mrpt::img::TCamera c;
    c.ncols = width;
    c.nrows = height;
    c.setIntrinsicParamsFromValues(fx, fy, cx, cy);
    switch (model)
    {
        case DistortionModel::None: c.distortion = mrpt::img::DistortionModel::none; break;
        case DistortionModel::RadTan: c.setDistortionPlumbBob(dist[0], dist[1], dist[2], dist[3], dist[4]); break;
        case DistortionModel::Equidistant: c.setDistortionKannalaBrandt(dist[0], dist[1], dist[2], dist[3]); break;
    }
    return c;
}

CameraModel CameraModel::fromTCamera(const mrpt::img::TCamera& c)
{
    CameraModel m = pinhole(c.ncols, c.nrows, c.fx(), c.fy(), c.cx(), c.cy());
    switch (c.distortion)
    {
        case mrpt::img::DistortionModel::none: m.model = DistortionModel::None; break;
        case mrpt::img::DistortionModel::plumb_bob:
            m.model = DistortionModel::RadTan;
            m.dist = {c.k1(), c.k2(), c.p1(), c.p2(), c.k3()};
            break;
        case mrpt::img::DistortionModel::kannala_brandt:
            m.model = DistortionModel::Equidistant;
            m.dist = {c.k1(), c.k2(), c.k3(), c.k4(), 0};
            break;
    }
    return m;
}

CameraModel CameraModel::loadFromIni(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    const std::string input = "INI section [" + section + "]";
    require(cfg.sectionExists(section), input, "section is missing (camera parameters expected)");
    mrpt::img::TCamera c;
    try
    {
        c.loadFromConfigFile(section, cfg);
    }
    catch (const std::exception& e)
    {
        throw InputError(input, std::string("invalid camera parameters: ") + e.what());
    }
    CameraModel m = fromTCamera(c);
    m.check(input);
    return m;
}

void CameraModel::saveToIni(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    // The keys of mrpt::img::TCamera, written here at full precision (TCamera rounds to 7 digits, which
    // moves EuRoC's distortion coefficients by 1e-8).
    auto num = [](double v) {
        char buf[40];
        std::snprintf(buf, sizeof(buf), "%.17g", v);
        return std::string(buf);
    };
    cfg.write(section, "resolution", "[" + std::to_string(width) + " " + std::to_string(height) + "]");
    cfg.write(section, "cx", num(cx));
    cfg.write(section, "cy", num(cy));
    cfg.write(section, "fx", num(fx));
    cfg.write(section, "fy", num(fy));
    // TCamera's INI layout: plumb_bob dist=[k1 k2 p1 p2 k3], kannala_brandt dist=[k1 k2 k3 k4].
    const std::array<double, 5> d = model == DistortionModel::None ? std::array<double, 5>{0, 0, 0, 0, 0} : dist;
    const size_t n = model == DistortionModel::Equidistant ? 4 : 5;
    std::string ds = "[";
    for (size_t i = 0; i < n; ++i) ds += (i ? " " : "") + num(d[i]);
    cfg.write(section, "dist", ds + "]");
    cfg.write(section, "distortion_model", toString(model));
}

CameraModel CameraModel::fromEurocYaml(const std::string& path)
{
    const YAML::Node doc = loadYamlMap(path, "camera sensor.yaml");
    const auto key = [&](const char* name) { return path + ": " + name; };
    const auto intr = yamlNumbers(doc["intrinsics"], key("intrinsics"));
    require(intr.size() == 4, key("intrinsics"), "must hold 4 values [fu, fv, cu, cv]");
    const auto res = yamlNumbers(doc["resolution"], key("resolution"));
    require(res.size() == 2, key("resolution"), "must hold 2 values [width, height]");
    const int width = yamlInteger(doc["resolution"][0], key("resolution") + "[0]", 1, 1 << 16);
    const int height = yamlInteger(doc["resolution"][1], key("resolution") + "[1]", 1, 1 << 16);
    const std::string cam_model = yamlText(doc["camera_model"], key("camera_model"), "");
    require(cam_model.empty() || cam_model == "pinhole", key("camera_model"),
            "'" + cam_model + "' is not supported (only pinhole)");
    CameraModel m = pinhole(width, height, intr[0], intr[1], intr[2], intr[3]);
    const std::string dist_model = yamlText(doc["distortion_model"], key("distortion_model"), "");
    m.model = distortionModelFromString(dist_model, path + " (distortion_model)");
    const size_t expected = m.model == DistortionModel::None ? 0 : 4;
    const auto distc = doc["distortion_coefficients"].IsDefined()
                           ? yamlNumbers(doc["distortion_coefficients"], key("distortion_coefficients"))
                           : std::vector<double>{};
    require(distc.size() >= expected && distc.size() <= 5, key("distortion_coefficients"),
            "must hold " + std::to_string(expected) + " values for " + dist_model);
    for (size_t i = 0; i < distc.size(); ++i) m.dist[i] = distc[i];
    m.check(path);
    return m;
}

}  // namespace quasiloc::core
