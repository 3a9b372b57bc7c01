// The method's claims (PAPER_NOTES.md): weak directions of each factor, no translational null direction for
// point + line + plane, sigma = 0 for candidates that agree, q ranks factors by the weak directions they fill,
// and the weak-mode analysis does not depend on the unit of length.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <quasiloc/estimation/reweighting.h>
#include <quasiloc/estimation/visual_factors.h>

#include "test_helpers.h"

using namespace quasiloc::estimation;
using quasiloc::estimation::test::makePose;
using quasiloc::estimation::test::pinholeCamera;

namespace
{
// Body = camera (T_body_cam = I), so tangent directions are camera-frame directions. The camera sits at the
// map origin looking along +z (T_map_body = I) unless a test moves it.
const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

template <class Factor>
Matrix6d information(const Factor& f, const Eigen::Isometry3d& T = kIdentity)
{
    Eigen::VectorXd r;
    Eigen::Matrix<double, -1, 6> J;
    f.linearize(T, r, &J);
    return J.transpose() * J;
}
Matrix6d pointInformation(const CameraGeometry& cam, const Eigen::Vector3d& P, const Eigen::Isometry3d& T = kIdentity)
{
    const PointReprojectionFactor f(cam, Eigen::Vector2d::Zero(), P, 1.0);
    Eigen::Vector2d r;
    Matrix26d J;
    f.linearize(T, r, &J);
    return J.transpose() * J;
}
Vector6d rot(const Eigen::Vector3d& v) { return (Vector6d() << v.normalized(), Eigen::Vector3d::Zero()).finished(); }
Vector6d trans(const Eigen::Vector3d& v) { return (Vector6d() << Eigen::Vector3d::Zero(), v.normalized()).finished(); }
double along(const Matrix6d& H, const Vector6d& v) { return v.dot(H * v) / H.trace(); }

std::vector<Eigen::Vector3d> sampleSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int n)
{
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i) pts.push_back(a + (b - a) * (i / double(n - 1)));
    return pts;
}
Eigen::Vector3d imageLine(const CameraGeometry& cam, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
    Eigen::Vector2d ua, ub;
    cam.model.project(a, ua);
    cam.model.project(b, ub);
    return Eigen::Vector3d(ua.x(), ua.y(), 1).cross(Eigen::Vector3d(ub.x(), ub.y(), 1));
}
}  // namespace

TEST(WeakDirections, PointIsBlindAlongItsViewingRay)
{
    const CameraGeometry cam = pinholeCamera();
    const Eigen::Vector3d P(0.8, -0.5, 4.0);
    const Matrix6d H = pointInformation(cam, P);
    EXPECT_LT(along(H, trans(P)), 1e-12);
    EXPECT_GT(along(H, trans(P.cross(Eigen::Vector3d::UnitY()))), 1e-3);  // across the ray: informative
}

TEST(WeakDirections, LineIsBlindInItsInterpretationPlaneAndAboutItsNormal)
{
    const CameraGeometry cam = pinholeCamera();
    const Eigen::Vector3d A(-1.0, 0.4, 3.5), B(1.2, -0.2, 5.0);
    const Eigen::Vector3d m_L = A.cross(B).normalized();  // normal of the interpretation plane
    const PointToLineFactor f(cam, imageLine(cam, A, B), sampleSegment(A, B, 8), 1.0);
    const Matrix6d H = information(f);
    const Eigen::Vector3d in_plane1 = (B - A).normalized(), in_plane2 = m_L.cross(in_plane1);
    EXPECT_LT(along(H, trans(in_plane1)), 1e-12);
    EXPECT_LT(along(H, trans(in_plane2)), 1e-12);
    EXPECT_LT(along(H, rot(m_L)), 1e-12);
    EXPECT_GT(along(H, trans(m_L)), 1e-3);  // translation out of the plane is seen
}

TEST(WeakDirections, PlaneIsBlindToInPlaneTranslationAndRotationAboutNormal)
{
    const CameraGeometry cam = pinholeCamera();
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, -1.0).normalized();
    const double d = 4.0;  // n^T P + d = 0
    std::vector<Eigen::Vector3d> pts;
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    for (int i = 0; i < 10; ++i) pts.push_back(-d * n + (i % 4 - 1.5) * e1 + (i / 4 - 1.0) * e2);
    const PointToPlaneFactor f(cam, pts, n, d, 0.02);
    const Matrix6d H = information(f);
    EXPECT_LT(along(H, trans(e1)), 1e-12);
    EXPECT_LT(along(H, trans(e2)), 1e-12);
    EXPECT_LT(along(H, rot(n)), 1e-12);
    EXPECT_GT(along(H, trans(n)), 1e-3);
}

TEST(WeakDirections, PointOnLineOnPlaneHasNoTranslationalNullDirection)
{
    const CameraGeometry cam = pinholeCamera();
    // A point on a line lying in a wall that does not contain the camera centre.
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.1, -1.0).normalized();
    const double d = 5.0;
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const Eigen::Vector3d P = -d * n, A = P - e1, B = P + e1;
    std::vector<Eigen::Vector3d> wall;
    for (int i = 0; i < 12; ++i) wall.push_back(P + (i % 4 - 1.5) * 0.5 * e1 + (i / 4 - 1.0) * 0.5 * e2);
    const Matrix6d Hp = pointInformation(cam, P);
    const Matrix6d Hl = information(PointToLineFactor(cam, imageLine(cam, A, B), sampleSegment(A, B, 6), 1.0));
    const Matrix6d Hs = information(PointToPlaneFactor(cam, wall, n, d, 0.02));
    auto minEig3 = [](const Eigen::Matrix3d& M) {
        return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(M).eigenvalues()[0];
    };
    auto minTranslationalEig = [&](const Matrix6d& H) {
        // Translational information left after the rotations are free: Schur complement on the rotation block.
        const Eigen::Matrix3d S = H.bottomRightCorner<3, 3>() -
                                  H.bottomLeftCorner<3, 3>() *
                                      (H.topLeftCorner<3, 3>() + 1e-12 * Eigen::Matrix3d::Identity()).inverse() *
                                      H.topRightCorner<3, 3>();
        return minEig3(S);
    };
    // Each alone has a translational null direction (even with rotation fixed) ...
    for (const Matrix6d* H : {&Hp, &Hl, &Hs}) EXPECT_LT(minEig3(H->bottomRightCorner<3, 3>()), 1e-9 * H->trace());
    // ... the three together have none, even with the rotation free.
    const Matrix6d H = Hp + Hl + Hs;
    const double trace_t = H.bottomRightCorner<3, 3>().trace();
    EXPECT_GT(minEig3(H.bottomRightCorner<3, 3>()), 1e-4 * trace_t);
    EXPECT_GT(minTranslationalEig(H), 1e-6 * trace_t);
}

TEST(Reweighting, SigmaIsZeroWhenCandidatesAgreeWhateverTheirProbabilities)
{
    Matrix6d H0 = Matrix6d::Identity();
    H0.diagonal() << 400, 300, 200, 0.5, 20, 9;
    const ObservabilityAnalysis an = analyzeObservability(H0, 3.0, 100.0);
    // Two different matrices with the same diagonal in the eigenbasis of H~_0 give the same g_ick.
    Matrix6d Ht = Matrix6d::Identity() * 2;
    Ht(0, 3) = Ht(3, 0) = 0.7;  // off-diagonal in the U basis: changes H, not g
    Matrix6d Dinv = Matrix6d::Identity();
    Dinv.bottomRightCorner<3, 3>() /= an.L;
    const Matrix6d H_a = Dinv * an.U * (Matrix6d::Identity() * 2) * an.U.transpose() * Dinv;
    const Matrix6d H_b = Dinv * an.U * Ht * an.U.transpose() * Dinv;
    for (double p : {0.5, 0.9, 0.01})
    {
        StructuralCandidates f;
        f.H = {H_a, H_b, H_a};
        f.probability = {p, (1 - p) / 2, (1 - p) / 2};
        Vector6d mu, sigma;
        double trace;
        candidateStatistics(an, f, false, mu, sigma, trace);
        EXPECT_EQ(sigma.maxCoeff(), 0.0) << "p = " << p;
        EXPECT_NEAR(mu.minCoeff(), 2.0, 1e-9);
        EXPECT_DOUBLE_EQ(factorScore(an, f, 5.0, 1e-9, false), factorScore(an, f, 0.0, 1e-9, false));
    }
    // Candidates that disagree have sigma > 0 and a lower score with kappa > 0.
    StructuralCandidates g;
    g.H = {H_a, 3 * H_a};
    g.probability = {0.5, 0.5};
    Vector6d mu, sigma;
    double trace;
    candidateStatistics(an, g, false, mu, sigma, trace);
    EXPECT_GT(sigma.minCoeff(), 0.9);
    EXPECT_LT(factorScore(an, g, 1.0, 1e-9, false), factorScore(an, g, 0.0, 1e-9, false));
}

TEST(Reweighting, ScoreRanksFactorsByTheWeakDirectionsTheyFill)
{
    // H_0 with one strong, one mid, one weakest direction in the scaled coordinates (rotation x strong,
    // translation y mid, translation z weakest).
    const double L = 2.0, tau = 100.0;
    Matrix6d H0 = Matrix6d::Zero();
    H0.diagonal() << 1e6, 1e6, 1e6, 1e6 / (L * L), 900 / (L * L), 1 / (L * L);
    auto factorAlong = [&](const Vector6d& scaled_dir) {
        Vector6d v = scaled_dir;
        v.tail<3>() /= L;  // H~ = D H D = e e^T  <=>  H = D^-1 e e^T D^-1
        StructuralCandidates f;
        f.H = {v * v.transpose()};
        f.probability = {1.0};
        return f;
    };
    const ObservabilityAnalysis an = analyzeObservability(H0, L, tau);
    EXPECT_NEAR(an.lambda[0], 1.0, 1e-6);
    EXPECT_NEAR(an.a[0], 0.99, 1e-6);
    EXPECT_EQ(an.a[5], 0.0);
    const double q_strong = factorScore(an, factorAlong(Vector6d::Unit(0)), 1, 1e-9, false);
    const double q_mid = factorScore(an, factorAlong(Vector6d::Unit(4)), 1, 1e-9, false);
    const double q_weak = factorScore(an, factorAlong(Vector6d::Unit(5)), 1, 1e-9, false);
    EXPECT_LT(q_strong, 1e-9);
    EXPECT_GT(q_weak, q_mid);
    EXPECT_GT(q_mid, 0.5 * q_strong);
    EXPECT_NEAR(q_weak, 0.99, 1e-6);
    EXPECT_NEAR(q_mid, 0.7, 1e-6);

    ReweightingOptions opt;
    opt.tau = tau;
    opt.beta = 2.0;
    ReweightingResult res;
    computeWeights(opt, H0, L, {factorAlong(Vector6d::Unit(0)), factorAlong(Vector6d::Unit(5))}, res);
    EXPECT_NEAR(res.weight[0], 1.0, 1e-9);
    EXPECT_NEAR(res.weight[1], 1.0 + 2.0 * 0.99, 1e-6);
    opt.mode = ReweightingMode::Uniform;
    computeWeights(opt, H0, L, {factorAlong(Vector6d::Unit(5))}, res);
    EXPECT_EQ(res.weight[0], 1.0);
}

TEST(Reweighting, ObservabilityModeUsesOnlyTheNominalCandidate)
{
    Matrix6d H0 = Matrix6d::Identity();
    H0(5, 5) = 1e-4;
    StructuralCandidates f;
    Vector6d weak = Vector6d::Unit(5), strong = Vector6d::Unit(0);
    f.H = {strong * strong.transpose(), weak * weak.transpose()};
    f.probability = {0.3, 0.7};
    f.nominal = 1;
    ReweightingOptions opt;
    opt.mode = ReweightingMode::Observability;
    ReweightingResult res;
    computeWeights(opt, H0, 1.0, {f}, res);
    EXPECT_NEAR(res.q[0], 1.0 - 0.01 / opt.tau, 1e-9);  // nominal alone, p = 1, no sigma penalty
    opt.mode = ReweightingMode::Full;
    computeWeights(opt, H0, 1.0, {f}, res);
    EXPECT_LT(res.q[0], 0.7);  // the mixture is less sure about the weak direction
}

TEST(Reweighting, WeakModeAnalysisDoesNotDependOnTheUnitOfLength)
{
    // A corridor-like scene: map points far ahead, a wall on the left, a line along the corridor and one across.
    auto analyse = [](double s, ObservabilityAnalysis& an, std::vector<double>& q) {
        const CameraGeometry cam = pinholeCamera();
        const Eigen::Isometry3d T = makePose(Eigen::Vector3d(0.02, -0.03, 0.01), Eigen::Vector3d(0.1, 0.05, -0.2) * s);
        Matrix6d H0 = Matrix6d::Zero();
        std::vector<double> depths;
        for (int i = 0; i < 6; ++i)
        {
            const Eigen::Vector3d P = Eigen::Vector3d(0.3 * (i % 3) - 0.3, 0.2 * (i / 3) - 0.1, 9.0 + i) * s;
            H0 += pointInformation(cam, P, T);
            depths.push_back((T.inverse() * P).z());
        }
        const double L = medianDepth(depths);
        std::vector<Eigen::Vector3d> wall;
        for (int i = 0; i < 10; ++i) wall.push_back(T.inverse() * (Eigen::Vector3d(-1.5, 0.3 * (i % 3), 2.0 + i) * s));
        const PointToPlaneFactor plane(cam, wall, Eigen::Vector3d::UnitX(), 1.5 * s, 0.02 * s);
        const Eigen::Vector3d A1 = Eigen::Vector3d(1.0, 0.5, 2) * s, B1 = Eigen::Vector3d(1.0, 0.5, 8) * s;
        const Eigen::Vector3d A2 = Eigen::Vector3d(-1, -0.5, 5) * s, B2 = Eigen::Vector3d(1, -0.5, 5) * s;
        auto line = [&](const Eigen::Vector3d& A, const Eigen::Vector3d& B) {
            return information(
                PointToLineFactor(cam, imageLine(cam, T.inverse() * A, T.inverse() * B), sampleSegment(A, B, 6), 1.0),
                T);
        };
        std::vector<StructuralCandidates> factors(3);
        factors[0].H = {information(plane, T)};
        factors[0].probability = {1.0};
        factors[1].H = {line(A1, B1), line(A2, B2)};  // two candidates that disagree
        factors[1].probability = {0.6, 0.4};
        factors[2].H = {line(A2, B2)};
        factors[2].probability = {1.0};
        ReweightingOptions opt;
        opt.tau = 50.0;
        ReweightingResult res;
        computeWeights(opt, H0, L, factors, res);
        an = res.analysis;
        q = res.q;
    };
    ObservabilityAnalysis an1, an2;
    std::vector<double> q1, q2;
    analyse(1.0, an1, q1);
    analyse(1000.0, an2, q2);  // metres -> millimetres
    EXPECT_NEAR(an2.L / an1.L, 1000.0, 1e-9);
    for (int k = 0; k < 6; ++k)
    {
        EXPECT_NEAR(an2.lambda[k] / std::max(an1.lambda[k], 1e-300), 1.0, 1e-6) << k;
        EXPECT_NEAR(std::abs(an1.U.col(k).dot(an2.U.col(k))), 1.0, 1e-6) << k;
        EXPECT_NEAR(an1.a[k], an2.a[k], 1e-9) << k;
    }
    EXPECT_GT(an1.a.maxCoeff(), 0.1);  // the test is meaningful: there are weak directions
    for (size_t i = 0; i < q1.size(); ++i)
    {
        EXPECT_GT(q1[i], 1e-4) << i;
        EXPECT_NEAR(q2[i] / q1[i], 1.0, 1e-6) << i;
    }
}
