#include <algorithm>
#include <cmath>
#include <quasiloc/estimation/reweighting.h>
#include <quasiloc/estimation/synthetic_scene.h>

namespace quasiloc::estimation
{
std::string toString(SceneLayout l)
{
    switch (l)
    {
        case SceneLayout::Room: return "room";
        case SceneLayout::Corridor: return "corridor";
        case SceneLayout::SingleWall: return "single wall";
    }
    return "?";
}

namespace
{
/** A planar rectangle o + a U + b V, a, b in [0, 1], in the true camera frame. */
struct Rect
{
    Eigen::Vector3d o, U, V;
    Eigen::Vector3d normal() const { return U.cross(V).normalized(); }
    double d() const { return -normal().dot(o); }
};

struct Layout
{
    std::vector<Rect> rects;
    int num_points = 0;
    double min_point_depth = 0.3;
    double along_v_share = 0.5;  ///< share of lines running along V (the corridor's long axis)
};

Layout makeLayout(const SceneOptions& o)
{
    Layout L;
    using V3 = Eigen::Vector3d;
    switch (o.layout)
    {
        case SceneLayout::Room:
            L.rects = {{V3(-2.5, -1.5, 0.5), V3(0, 3, 0), V3(0, 0, 7.5)},
                       {V3(2.5, -1.5, 0.5), V3(0, 3, 0), V3(0, 0, 7.5)},
                       {V3(-2.5, 1.5, 0.5), V3(5, 0, 0), V3(0, 0, 7.5)},
                       {V3(-2.5, -1.5, 0.5), V3(5, 0, 0), V3(0, 0, 7.5)},
                       {V3(-2.5, -1.5, 8.0), V3(5, 0, 0), V3(0, 3, 0)}};
            L.num_points = o.num_points;
            break;
        case SceneLayout::Corridor:
            L.rects = {{V3(-1.2, -1.2, 1), V3(0, 2.4, 0), V3(0, 0, 29)},
                       {V3(1.2, -1.2, 1), V3(0, 2.4, 0), V3(0, 0, 29)},
                       {V3(-1.2, 1.2, 1), V3(2.4, 0, 0), V3(0, 0, 29)},
                       {V3(-1.2, -1.2, 1), V3(2.4, 0, 0), V3(0, 0, 29)}};
            L.num_points = std::max(4, o.num_points / 5);
            L.min_point_depth = 15.0;
            L.along_v_share = 0.75;
            break;
        case SceneLayout::SingleWall:
            L.rects = {{V3(-3, -2, 4), V3(6, 0, 0), V3(0, 4, 0)}};
            L.num_points = std::max(4, o.num_points / 8);
            break;
    }
    return L;
}

class Generator
{
   public:
    Generator(const SceneOptions& o, std::mt19937& rng) : o_(o), rng_(rng), layout_(makeLayout(o)) {}
    double U(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
    double N(double s) { return s > 0 ? std::normal_distribution<double>(0, s)(rng_) : 0.0; }
    Eigen::Vector3d N3(double s) { return Eigen::Vector3d(N(s), N(s), N(s)); }
    int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }

    bool visible(const CameraGeometry& cam, const Eigen::Vector3d& p_cam, double min_depth = 0.3) const
    {
        Eigen::Vector2d px;
        return p_cam.z() > min_depth && cam.model.project(p_cam, px) && cam.model.isInImage(px, 5);
    }
    /** A visible point of rect r (rejection sampling; false if none found). */
    bool samplePoint(const CameraGeometry& cam, int r, double min_depth, Eigen::Vector3d& p)
    {
        const Rect& R = layout_.rects[r];
        for (int tries = 0; tries < 200; ++tries)
        {
            p = R.o + U(0, 1) * R.U + U(0, 1) * R.V;
            if (visible(cam, p, min_depth)) return true;
        }
        return false;
    }
    /** A visible segment on rect r, along U or V, 0.6-2.5 m long. */
    bool sampleSegment(const CameraGeometry& cam, int r, Eigen::Vector3d& A, Eigen::Vector3d& B)
    {
        const Rect& R = layout_.rects[r];
        for (int tries = 0; tries < 200; ++tries)
        {
            if (!samplePoint(cam, r, 0.5, A)) return false;
            Eigen::Vector3d dir = (U(0, 1) < layout_.along_v_share) ? R.V.normalized() : R.U.normalized();
            if (o_.layout == SceneLayout::SingleWall)
            {
                const double a = U(0, M_PI);
                dir = std::cos(a) * R.U.normalized() + std::sin(a) * R.V.normalized();
            }
            B = A + U(0.6, 2.5) * dir;
            if (visible(cam, B, 0.5) && visible(cam, 0.5 * (A + B), 0.5)) return true;
        }
        return false;
    }
    std::vector<Eigen::Vector3d> support(const Eigen::Vector3d& A, const Eigen::Vector3d& B, const Eigen::Isometry3d& T)
    {
        std::vector<Eigen::Vector3d> s;
        for (int m = 0; m < o_.support_points; ++m)
            s.push_back(T * (A + (B - A) * (m + 0.5) / o_.support_points + N3(o_.lidar_noise_m)));
        return s;
    }
    /** Probabilities: the true candidate (index 0) scores higher unless `wrong_nominal`. */
    std::vector<double> probabilities(int n, bool wrong_nominal)
    {
        std::vector<double> s(n);
        s[0] = U(0.5, 1.0);
        for (int c = 1; c < n; ++c) s[c] = U(0.1, 0.45);
        if (wrong_nominal && n > 1) std::swap(s[0], s[1 + pick(n - 1)]);
        double sum = 0;
        for (double v : s) sum += v;
        for (double& v : s) v /= sum;
        return s;
    }

    const SceneOptions& o_;
    std::mt19937& rng_;
    Layout layout_;
};

Eigen::Isometry3d randomPose(Generator& g)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSO3(Eigen::Vector3d(g.N(1.0), g.N(1.0), g.N(1.0)));
    T.translation() = Eigen::Vector3d(g.U(-5, 5), g.U(-5, 5), g.U(-2, 2));
    return T;
}
}  // namespace

SyntheticFrame makeSyntheticFrame(const SceneOptions& o, std::mt19937& rng)
{
    Generator g(o, rng);
    SyntheticFrame f;
    f.stereo.left.model = core::CameraModel::pinhole(640, 480, 400, 400, 320, 240);
    f.stereo.right = f.stereo.left.model;
    f.stereo.T_left_right.translation() = Eigen::Vector3d(0.11, 0, 0);
    const CameraGeometry& cam = f.stereo.left;
    const Eigen::Isometry3d T = randomPose(g);  // T_map_cam = T_map_body (body = left camera)
    f.T_map_body_true = T;
    const int nr = static_cast<int>(g.layout_.rects.size());

    for (int i = 0; i < g.layout_.num_points; ++i)
    {
        Eigen::Vector3d p;
        if (!g.samplePoint(cam, g.pick(nr), g.layout_.min_point_depth, p)) continue;
        PointMatch m;
        cam.model.project(p, m.px);
        const double sp = o.pixel_noise * o.point_noise_factor;
        m.px += Eigen::Vector2d(g.N(sp), g.N(sp));
        if (g.U(0, 1) < o.point_outlier_rate) m.px = Eigen::Vector2d(g.U(0, 640), g.U(0, 480));
        m.p_map = T * (p + g.N3(o.lidar_noise_m));
        m.sigma_px = std::max(o.pixel_noise, 0.5);
        f.points.push_back(m);
    }

    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
    std::vector<int> segment_rect;
    for (int i = 0; i < o.num_lines; ++i)
    {
        const int r = g.pick(nr);
        Eigen::Vector3d A, B;
        if (!g.sampleSegment(cam, r, A, B)) continue;
        segments.emplace_back(A, B);
        segment_rect.push_back(r);
    }
    for (size_t i = 0; i < segments.size(); ++i)
    {
        const auto& [A, B] = segments[i];
        LineFactorInput lf;
        Eigen::Vector2d ua, ub;
        cam.model.project(A, ua);
        cam.model.project(B, ub);
        ua += Eigen::Vector2d(g.N(o.pixel_noise), g.N(o.pixel_noise));
        ub += Eigen::Vector2d(g.N(o.pixel_noise), g.N(o.pixel_noise));
        lf.line_px = Eigen::Vector3d(ua.x(), ua.y(), 1).cross(Eigen::Vector3d(ub.x(), ub.y(), 1));
        lf.sigma_px = std::max(o.pixel_noise, 0.5);
        const bool wrong = g.U(0, 1) < o.wrong_nominal_rate;
        f.wrong_nominal_lines += wrong && o.candidates > 1;
        const std::vector<double> p = g.probabilities(o.candidates, wrong);
        lf.candidates.push_back({g.support(A, B, T), p[0]});
        const Eigen::Vector3d n = g.layout_.rects[segment_rect[i]].normal();
        for (int c = 1; c < o.candidates; ++c)
        {
            Eigen::Vector3d A2 = A, B2 = B;
            if (segments.size() > 1 && g.U(0, 1) < 0.5)  // another edge of the scene
                std::tie(A2, B2) = segments[(i + 1 + g.pick(static_cast<int>(segments.size()) - 1)) % segments.size()];
            else  // a parallel neighbour in the same surface
            {
                const Eigen::Vector3d side = n.cross(B - A).normalized();
                const double s = (g.U(0, 1) < 0.5 ? -1 : 1) * g.U(0.15, 0.5);
                A2 += s * side;
                B2 += s * side;
            }
            lf.candidates.push_back({g.support(A2, B2, T), p[c]});
        }
        f.lines.push_back(std::move(lf));
    }

    for (int i = 0; i < o.num_planes; ++i)
    {
        const int r = g.pick(nr);
        const Rect& R = g.layout_.rects[r];
        Eigen::Vector3d centre;
        if (!g.samplePoint(cam, r, 0.5, centre)) continue;
        PlaneFactorInput pf;
        std::vector<double> depths;
        for (int tries = 0; tries < 50 * o.plane_points && static_cast<int>(pf.points_cam.size()) < o.plane_points;
             ++tries)
        {
            const Eigen::Vector3d p = centre + g.U(-1, 1) * R.U.normalized() + g.U(-1, 1) * R.V.normalized();
            const Eigen::Vector3d rel = p - R.o;
            if (rel.dot(R.U) < 0 || rel.dot(R.U) > R.U.squaredNorm() || rel.dot(R.V) < 0 ||
                rel.dot(R.V) > R.V.squaredNorm() || !g.visible(cam, p, 0.5))
                continue;
            pf.points_cam.push_back(p * (1.0 + g.N(o.stereo_noise_rel)));
            depths.push_back(p.z());
        }
        if (pf.points_cam.size() < 3) continue;
        pf.sigma_m = std::max(1e-3, o.stereo_noise_rel * medianDepth(depths));
        const bool wrong = g.U(0, 1) < o.wrong_nominal_rate;
        f.wrong_nominal_planes += wrong && o.candidates > 1;
        const std::vector<double> p = g.probabilities(o.candidates, wrong);
        auto toMap = [&](const Eigen::Vector3d& n_cam, double d_cam, double prob) {
            const Eigen::Vector3d n_map = T.linear() * n_cam;  // n^T P_cam + d = 0 -> n_map^T P_map + d' = 0
            return PlaneCandidate{n_map, d_cam - n_map.dot(T.translation()), prob};
        };
        pf.candidates.push_back(toMap(R.normal(), R.d(), p[0]));
        for (int c = 1; c < o.candidates; ++c)
        {
            if (nr > 1 && g.U(0, 1) < 0.5)
            {
                const Rect& W = g.layout_.rects[(r + 1 + g.pick(nr - 1)) % nr];
                pf.candidates.push_back(toMap(W.normal(), W.d(), p[c]));
            }
            else
                pf.candidates.push_back(toMap(R.normal(), R.d() + (g.U(0, 1) < 0.5 ? -1 : 1) * g.U(0.1, 0.3), p[c]));
        }
        f.planes.push_back(std::move(pf));
    }

    f.guess.T_map_body =
        boxPlus(T, (Vector6d() << g.N3(o.init_sigma_deg * M_PI / 180), g.N3(o.init_sigma_m)).finished());
    f.prior.mean = f.guess;
    f.prior.information.setZero();
    const double k2 = o.prior_overconfidence * o.prior_overconfidence;
    f.prior.information.diagonal().head<3>().setConstant(k2 * std::pow(o.init_sigma_deg * M_PI / 180, -2));
    f.prior.information.diagonal().segment<3>(3).setConstant(k2 * std::pow(o.init_sigma_m, -2));
    return f;
}

}  // namespace quasiloc::estimation
