#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <random>
#include <thread>

namespace quasiloc::sim
{
namespace
{
uint64_t splitmix64(uint64_t& x)
{
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/** Smooth 0..1..0 envelope of an episode [start, start + duration] with 1 s ramps. */
double episodeWeight(double t, double start, double duration)
{
    const double ramp = 1.0;
    if (t <= start || t >= start + duration) return 0;
    const double w = std::min({1.0, (t - start) / ramp, (start + duration - t) / ramp});
    return w * w * (3 - 2 * w);
}

/** The internal undistorted pinhole that covers every raw pixel of `cam`. */
PinholeIntrinsics coveringPinhole(const core::CameraModel& cam, double scale)
{
    double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
    auto visit = [&](double u, double v) {
        const Eigen::Vector3d n = cam.unproject(Eigen::Vector2d(u, v));
        xmin = std::min(xmin, n.x());
        xmax = std::max(xmax, n.x());
        ymin = std::min(ymin, n.y());
        ymax = std::max(ymax, n.y());
    };
    for (int u = 0; u <= cam.width; u += 2)
    {
        visit(u - 0.5, -0.5);
        visit(u - 0.5, cam.height - 0.5);
    }
    for (int v = 0; v <= cam.height; v += 2)
    {
        visit(-0.5, v - 0.5);
        visit(cam.width - 0.5, v - 0.5);
    }
    PinholeIntrinsics k;
    const double margin = 3;
    k.fx = static_cast<float>(cam.fx * scale);
    k.fy = static_cast<float>(cam.fy * scale);
    k.cx = static_cast<float>(-xmin * k.fx + margin);
    k.cy = static_cast<float>(-ymin * k.fy + margin);
    k.width = static_cast<int>(std::ceil((xmax - xmin) * k.fx + 2 * margin));
    k.height = static_cast<int>(std::ceil((ymax - ymin) * k.fy + 2 * margin));
    return k;
}

void appendPersonBox(Mesh& m, const Eigen::Vector3f& c, const Eigen::Matrix3f& R, const Eigen::Vector3f& s)
{
    m.addBox(c, R, s, kPersonClothes, 0.3f);
}
}  // namespace

std::vector<float> lightScales(const AppearanceOptions& o, size_t num_lights, double t_rel)
{
    std::vector<float> s(num_lights, 1.f);
    if (!o.illumination_change) return s;
    const double w = episodeWeight(t_rel, o.illumination_change_start_s, o.illumination_change_duration_s);
    for (size_t l = 0; l < num_lights; ++l)
    {
        const double target = (l % 2 == 1) ? 0.0 : o.illumination_change_factor;  // every other light turns off
        s[l] = static_cast<float>(1.0 + w * (target - 1.0));
    }
    return s;
}

namespace
{
double continuousExposure(const AppearanceOptions& o, size_t num_lights, double t_rel)
{
    double e = o.exposure * (1.0 + o.exposure_variation * std::sin(2 * M_PI * t_rel / o.exposure_period_s));
    if (o.illumination_change && num_lights > 0)
    {
        const std::vector<float> s = lightScales(o, num_lights, t_rel - o.auto_exposure_lag_s);
        double mean = 0;
        for (float v : s) mean += v;
        mean /= static_cast<double>(num_lights);
        e *= std::pow(std::max(mean, 0.05), -o.auto_exposure_compensation);
    }
    return e;
}
}  // namespace

double exposureAt(const AppearanceOptions& o, size_t num_lights, double t_rel)
{
    if (o.auto_exposure_step <= 0) return continuousExposure(o, num_lights, t_rel);
    const double t_update = std::floor(t_rel / o.auto_exposure_interval_s) * o.auto_exposure_interval_s;
    const double target = continuousExposure(o, num_lights, t_update);
    const double level = std::round(std::log(target / o.exposure) / std::log1p(o.auto_exposure_step));
    return o.exposure * std::pow(1 + o.auto_exposure_step, level);
}

Mesh occluderMesh(const AppearanceOptions& o, const World& world, double t_rel)
{
    Mesh m;
    if (!o.occluder) return m;
    const Eigen::Vector3f centre = world.room.center(), size = world.room.sizes();
    const float a = static_cast<float>(o.occluder_path_fraction) * size.x();
    const float b = static_cast<float>(o.occluder_path_fraction) * size.y();
    const float mean_radius = 0.5f * (a + b);
    const float theta = static_cast<float>(o.occluder_speed_m_s * t_rel) / mean_radius;
    const Eigen::Vector3f pos(centre.x() + a * std::cos(theta), centre.y() + b * std::sin(theta), world.room.min().z());
    const float heading = std::atan2(b * std::cos(theta), -a * std::sin(theta));
    const Eigen::Matrix3f R = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitZ()).toRotationMatrix();
    appendPersonBox(m, pos + Eigen::Vector3f(0, 0, 0.42f), R, {0.25f, 0.38f, 0.84f});  // legs
    appendPersonBox(m, pos + Eigen::Vector3f(0, 0, 1.15f), R, {0.28f, 0.48f, 0.62f});  // torso
    appendPersonBox(m, pos + Eigen::Vector3f(0, 0, 1.60f), R, {0.22f, 0.18f, 0.26f});  // head
    return m;
}

StereoRenderer::StereoRenderer(const World& world, const core::StereoRig& rig, const AppearanceOptions& options,
                               uint64_t seed)
    : world_(world), rig_(rig), opt_(options), seed_(seed)
{
    opt_.check("[Appearance]");
    const core::CameraModel* cams[2] = {&rig_.left, &rig_.right};
    for (int c = 0; c < 2; ++c)
    {
        const core::CameraModel& cam = *cams[c];
        pinhole_[c] = coveringPinhole(cam, opt_.render_scale);
        cv::Mat mx(cam.height, cam.width, CV_32F), my(cam.height, cam.width, CV_32F);
        vignette_[c].create(cam.height, cam.width, CV_32F);
        const double corner2 =
            std::pow(std::max(cam.cx, cam.width - cam.cx), 2) + std::pow(std::max(cam.cy, cam.height - cam.cy), 2);
        for (int v = 0; v < cam.height; ++v)
            for (int u = 0; u < cam.width; ++u)
            {
                const Eigen::Vector3d n = cam.unproject(Eigen::Vector2d(u, v));
                mx.at<float>(v, u) = static_cast<float>(pinhole_[c].fx * n.x() + pinhole_[c].cx);
                my.at<float>(v, u) = static_cast<float>(pinhole_[c].fy * n.y() + pinhole_[c].cy);
                const double r2 = (std::pow(u - cam.cx, 2) + std::pow(v - cam.cy, 2)) / corner2;
                vignette_[c].at<float>(v, u) = static_cast<float>(1.0 - opt_.vignetting * r2);
            }
        cv::convertMaps(mx, my, map1_[c], map2_[c], CV_16SC2);
    }
    std::mt19937_64 rng(seed ^ 0x5EEDull);
    std::normal_distribution<float> normal(0.f, 1.f);
    normal_table_.resize(1 << 16);
    for (float& x : normal_table_) x = normal(rng);
    gamma_lut_.resize(4096);
    for (int i = 0; i < 4096; ++i)
        gamma_lut_[i] = static_cast<uint8_t>(std::lround(255.0 * std::pow(i / 4095.0, 1.0 / opt_.gamma)));
}

void StereoRenderer::shadeInto(int cam, const Eigen::Isometry3f& T_cam_world, const std::vector<float>& shade,
                               const Mesh& occ, const std::vector<float>& occ_shade, cv::Mat& acc)
{
    const PinholeIntrinsics& K = pinhole_[cam];
    VisibilityBuffer& vis = vis_[cam];
    vis.reset(K.width, K.height);
    RasterOptions ro;
    rasterize(world_.mesh, K, T_cam_world, ro, vis);
    const auto n_world = static_cast<int32_t>(world_.mesh.triangles.size());
    if (!occ.triangles.empty())
    {
        ro.id_offset = n_world;
        rasterize(occ, K, T_cam_world, ro, vis);
    }
    const Eigen::Matrix3f R = T_cam_world.linear();
    const float inv_f = 1.f / std::sqrt(K.fx * K.fy);
    int32_t last = -2;
    const Vertex* v[3] = {nullptr, nullptr, nullptr};
    float s[3] = {0, 0, 0};
    const Material* mat = nullptr;
    float footprint_per_depth = 0;
    for (int y = 0; y < K.height; ++y)
    {
        float* row = acc.ptr<float>(y);
        for (int x = 0; x < K.width; ++x)
        {
            const VisibilitySample& px = vis.px[vis.index(x, y)];
            const int32_t id = px.tri;
            if (id < 0) continue;
            if (id != last)
            {
                const bool is_occ = id >= n_world;
                const Mesh& m = is_occ ? occ : world_.mesh;
                const Triangle& t = m.triangles[is_occ ? id - n_world : id];
                const std::vector<float>& sh = is_occ ? occ_shade : shade;
                for (int i = 0; i < 3; ++i)
                {
                    v[i] = &m.vertices[t.v[i]];
                    s[i] = sh[t.v[i]];
                }
                mat = &world_.materials[t.material];
                // Texture footprint of a pixel per metre of depth, from the ray through this first pixel of the
                // triangle: range / f / sqrt(cos incidence). Triangles are small, so one value per triangle (and
                // per run of pixels) is enough to pick the mip level.
                const Eigen::Vector3f ray((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.f);
                const float ray_norm = ray.norm();
                const float cos_in = std::max(std::abs((R * v[0]->n).dot(ray)) / ray_norm, 0.05f);
                footprint_per_depth = ray_norm * inv_f / std::sqrt(cos_in);
                last = id;
            }
            const float b1 = px.b1, b2 = px.b2, b0 = 1.f - b1 - b2;
            const Eigen::Vector2f uv = b0 * v[0]->uv + b1 * v[1]->uv + b2 * v[2]->uv;
            const float irradiance = b0 * s[0] + b1 * s[1] + b2 * s[2];
            row[x] += mat->albedo(uv, px.depth * footprint_per_depth) * irradiance;
        }
    }
}

void StereoRenderer::radianceDistorted(int cam, const std::vector<mrpt::poses::CPose3D>& T_world_cam0, double t_rel,
                                       cv::Mat& out, VisibilityBuffer* vis_out)
{
    const PinholeIntrinsics& K = pinhole_[cam];
    cv::Mat acc = cv::Mat::zeros(K.height, K.width, CV_32F);
    const std::vector<float> scales = lightScales(opt_, world_.lights.size(), t_rel);
    std::vector<float> shade;
    world_.vertexShading(scales, shade);
    const Mesh occ = occluderMesh(opt_, world_, t_rel);
    std::vector<float> occ_shade(occ.vertices.size(), world_.ambient);
    for (size_t i = 0; i < occ.vertices.size(); ++i)
        for (size_t l = 0; l < world_.lights.size(); ++l)
        {
            const Eigen::Vector3f d = world_.lights[l].position - occ.vertices[i].p;
            const float r2 = d.squaredNorm();
            occ_shade[i] += scales[l] * world_.lights[l].intensity * std::abs(occ.vertices[i].n.dot(d)) /
                            std::sqrt(r2) / (r2 + 0.25f);
        }
    const mrpt::poses::CPose3D T_cam0_cam = cam == 0 ? mrpt::poses::CPose3D() : rig_.T_left_right;
    for (const auto& T : T_world_cam0)
    {
        const Eigen::Isometry3f T_cam_world = core::toIsometry(T + T_cam0_cam).inverse().cast<float>();
        shadeInto(cam, T_cam_world, shade, occ, occ_shade, acc);
    }
    if (T_world_cam0.size() > 1) acc *= 1.0 / static_cast<double>(T_world_cam0.size());
    cv::remap(acc, out, map1_[cam], map2_[cam], cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    if (vis_out) *vis_out = vis_[cam];
}

cv::Mat StereoRenderer::renderRadiance(int cam, const mrpt::poses::CPose3D& T_world_cam0, double t_rel,
                                       VisibilityBuffer* vis_out)
{
    cv::Mat out;
    radianceDistorted(cam, {T_world_cam0}, t_rel, out, vis_out);
    return out;
}

cv::Mat StereoRenderer::sensor(int cam, const cv::Mat& radiance, double t_rel, uint64_t frame_index) const
{
    const float gain = static_cast<float>(exposureAt(opt_, world_.lights.size(), t_rel) * 255.0);
    const float read2 = static_cast<float>(opt_.read_noise * opt_.read_noise);
    const float shot2 = static_cast<float>(opt_.shot_noise * opt_.shot_noise);
    const float to_lut = 4095.f / 255.f;
    cv::Mat img(radiance.size(), CV_8U);
    for (int y = 0; y < radiance.rows; ++y)
    {
        uint64_t state = seed_ ^ (frame_index * 0x9E3779B97F4A7C15ull) ^ (static_cast<uint64_t>(cam) << 62) ^
                         (static_cast<uint64_t>(y) * 0xD1B54A32D192ED03ull);
        const float* r = radiance.ptr<float>(y);
        const float* vig = vignette_[cam].ptr<float>(y);
        uint8_t* o = img.ptr<uint8_t>(y);
        uint64_t bits = 0;
        for (int x = 0; x < radiance.cols; ++x)
        {
            if ((x & 3) == 0) bits = splitmix64(state);
            const float noise = normal_table_[(bits >> (16 * (x & 3))) & 0xFFFF];
            float dn = r[x] * vig[x] * gain;  // linear 8-bit units
            dn += noise * std::sqrt(read2 + shot2 * std::max(dn, 0.f));
            const int idx = std::clamp(static_cast<int>(dn * to_lut + 0.5f), 0, 4095);
            o[x] = gamma_lut_[idx];
        }
    }
    return img;
}

void StereoRenderer::render(const std::vector<mrpt::poses::CPose3D>& T_world_cam0, double t_rel, uint64_t frame_index,
                            cv::Mat& left, cv::Mat& right)
{
    cv::Mat rad[2];
    std::thread right_thread([&] {
        radianceDistorted(1, T_world_cam0, t_rel, rad[1], nullptr);
        right = sensor(1, rad[1], t_rel, frame_index);
    });
    radianceDistorted(0, T_world_cam0, t_rel, rad[0], nullptr);
    left = sensor(0, rad[0], t_rel, frame_index);
    right_thread.join();
}

}  // namespace quasiloc::sim
