// The Rauch-Tung-Striebel backward pass (core/smoother.hpp) on a linear-Gaussian model written on
// the same machinery (a 2-D constant-velocity filter corrected by kalman_correct): equal to the
// batch least-squares solution, the same bits whatever the checkpoint interval, no heap in the
// recursion after reserve(), refused time updates kept, the record's capacity respected.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <quatnav/core/checks.hpp>
#include <quatnav/core/smoother.hpp>
#include <random>
#include <vector>

using namespace quatnav;

namespace {

using Vec4d = Vec<double, 4>;
using Mat4d = Mat<double, 4, 4>;

/// A constant-velocity filter, state [p (2), v (2)], white-acceleration noise of density q,
/// position measurements of one-sigma r: the linear-Gaussian model of the exactness test.
struct CvFilter {
  using Scalar = double;
  Vec4d x = Vec4d::Zero();
  Mat4d P = Mat4d::Identity();
  double q = 0.5, r = 0.3;
  double max_dt = 1.0;

  static Mat4d Phi(double dt) {
    Mat4d F = Mat4d::Identity();
    F(0, 2) = F(1, 3) = dt;
    return F;
  }
  static Mat4d Q(double dt, double q) {
    Mat4d Qd = Mat4d::Zero();
    for (int i = 0; i < 2; ++i) {
      Qd(i, i) = q * dt * dt * dt / 3.0;
      Qd(i, i + 2) = Qd(i + 2, i) = q * dt * dt / 2.0;
      Qd(i + 2, i + 2) = q * dt;
    }
    return Qd;
  }
  Status predict(double dt) {
    if (!(dt > 0.0) || dt > max_dt) return Status::InvalidDt;
    const Mat4d F = Phi(dt);
    x = F * x;
    P = F * P * F.transpose() + Q(dt, q);
    symmetrize(P);
    return Status::Ok;
  }
  Status update(const Vec2<double>& z) {
    Mat<double, 2, 4> H = Mat<double, 2, 4>::Zero();
    H(0, 0) = H(1, 1) = 1.0;
    const Mat<double, 2, 2> R = Mat<double, 2, 2>::Identity() * (r * r);
    Vec4d dx;
    UpdateResult<double, 2> res;
    if (kalman_correct<double, 4, 2>(P, H, R, Vec2<double>(z - x.head<2>()), dx, res) != Status::Ok) return res.status;
    x += dx;
    return Status::Ok;
  }
};

/// Its smoother model: Euclidean error state, x [-] base = x - base.
struct CvModel {
  using Scalar = double;
  static constexpr int kErr = 4;
  struct Record {
    Vec4d x;
    PackedSym<double, 4> P;
  };
  CvFilter g;
  const double* dt = nullptr;

  bool capture(const CvFilter& f, Record& r) const {
    r.x = f.x;
    r.P.pack(f.P);
    return true;
  }
  bool same(const Record& a, const Record& b) const { return a.x == b.x && a.P == b.P; }
  bool restart(const Record&, const Record&) const { return false; }
  RtsLink predict(std::size_t k, const Record& post, Record& prior) {
    g.x = post.x;
    g.P = post.P.unpack();
    if (g.predict(dt[k]) != Status::Ok) return RtsLink::Same;
    capture(g, prior);
    return RtsLink::Predict;
  }
  RtsLink transition(std::size_t k, const Record&, const Record&, Mat4d& Phi) const {
    Phi = CvFilter::Phi(dt[k]);
    return RtsLink::Predict;
  }
  Mat4d error_covariance(const Record& r) const { return r.P.unpack(); }
  Vec4d local(const Record& base, const Record& x) const { return x.x - base.x; }
  void retract(const Record& base, const Vec4d& d, const Mat4d& Ps, Record& out) const {
    out.x = base.x + d;
    out.P.pack(Ps);
  }
};

struct CvRun {
  std::vector<double> dt;                    // dt[k]: the step into sample k (dt[0] unused)
  std::vector<Vec2<double>> z;               // measurement at sample k (NaN: none)
  Vec4d x0 = Vec4d(0.0, 0.0, 1.0, -0.5);
  Mat4d P0 = Vec4d(4.0, 4.0, 1.0, 1.0).asDiagonal();
};

CvRun make_run(int n, int every, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> nd;
  std::uniform_real_distribution<double> ud(0.05, 0.2);
  CvRun run;
  Vec4d x(0.5, -0.3, 1.2, -0.4);
  for (int k = 0; k < n; ++k) {
    const double dt = ud(g);
    run.dt.push_back(dt);
    if (k > 0) x = CvFilter::Phi(dt) * x + Vec4d(0.1 * nd(g), 0.1 * nd(g), 0.3 * nd(g), 0.3 * nd(g));
    if (k % every == 0 || k == 7)
      run.z.push_back(Vec2<double>(x[0] + 0.3 * nd(g), x[1] + 0.3 * nd(g)));
    else
      run.z.push_back(Vec2<double>::Constant(std::nan("")));
  }
  return run;
}

/// The forward pass as a batch loop reporting to `obs`; forward means and covariances out.
template <class Obs>
void cv_forward(const CvRun& run, CvFilter& f, Obs& obs, std::vector<Vec4d>* xf = nullptr,
                std::vector<Mat4d>* Pf = nullptr) {
  f.x = run.x0;
  f.P = run.P0;
  for (std::size_t k = 0; k < run.dt.size(); ++k) {
    if (k > 0) {
      f.predict(run.dt[k]);
      obs.after_predict(k, f);
    }
    if (!std::isnan(run.z[k][0])) f.update(run.z[k]);
    obs.after_sample(k, f);
    if (xf) xf->push_back(f.x);
    if (Pf) Pf->push_back(f.P);
  }
}

struct Smoothed {
  std::vector<Vec4d> x;
  std::vector<Mat4d> P;
  std::size_t records = 0;
};

Smoothed cv_smooth(const CvRun& run, std::size_t segment) {
  CvModel model;
  model.dt = run.dt.data();
  model.g.q = CvFilter().q;
  RtsSmoother<CvModel> sm(model);
  const std::size_t n = run.dt.size();
  std::size_t epochs = 1;
  for (const auto& z : run.z) epochs += std::isnan(z[0]) ? 0 : 1;
  EXPECT_TRUE(sm.reserve(n, epochs, segment));
  CvFilter f;
  cv_forward(run, f, sm);
  Smoothed s;
  s.x.assign(n, Vec4d::Constant(std::nan("")));
  s.P.assign(n, Mat4d::Zero());
  Eigen::internal::set_is_malloc_allowed(false);
  const auto res = sm.smooth([&](std::size_t k, const CvModel::Record& r, const Mat4d& Ps) {
    s.x[k] = r.x;
    s.P[k] = Ps;
  });
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(res, RtsSmoother<CvModel>::Result::Ok);
  s.records = sm.records();
  return s;
}

/// The batch least-squares solution of the same model: the minimum over every state of
///   |x_0 - x0|^2_{P0^-1} + sum_k |x_k - Phi_k x_{k-1}|^2_{Q_k^-1} + sum_k |z_k - H x_k|^2_{R^-1},
/// by the normal equations; the covariance is the inverse of their matrix.
void batch_least_squares(const CvRun& run, Eigen::VectorXd& X, Eigen::MatrixXd& Cov) {
  const int n = int(run.dt.size());
  const CvFilter f;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4 * n, 4 * n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(4 * n);
  const Mat4d P0i = run.P0.inverse();
  A.block<4, 4>(0, 0) += P0i;
  b.segment<4>(0) += P0i * run.x0;
  for (int k = 1; k < n; ++k) {
    const Mat4d F = CvFilter::Phi(run.dt[k]);
    const Mat4d Qi = CvFilter::Q(run.dt[k], f.q).inverse();
    // residual x_k - F x_{k-1}: J = [-F, I]
    A.block<4, 4>(4 * k, 4 * k) += Qi;
    A.block<4, 4>(4 * (k - 1), 4 * (k - 1)) += F.transpose() * Qi * F;
    A.block<4, 4>(4 * k, 4 * (k - 1)) -= Qi * F;
    A.block<4, 4>(4 * (k - 1), 4 * k) -= F.transpose() * Qi;
  }
  for (int k = 0; k < n; ++k) {
    if (std::isnan(run.z[k][0])) continue;
    const double ri = 1.0 / (f.r * f.r);
    A(4 * k, 4 * k) += ri;
    A(4 * k + 1, 4 * k + 1) += ri;
    b[4 * k] += ri * run.z[k][0];
    b[4 * k + 1] += ri * run.z[k][1];
  }
  Eigen::LLT<Eigen::MatrixXd> llt(A);
  X = llt.solve(b);
  Cov = llt.solve(Eigen::MatrixXd::Identity(4 * n, 4 * n));
}

}  // namespace

TEST(RtsSmoother, LinearModelEqualsBatchLeastSquares) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const CvRun run = make_run(150, 10, seed);
    Eigen::VectorXd X;
    Eigen::MatrixXd Cov;
    Eigen::internal::set_is_malloc_allowed(true);
    batch_least_squares(run, X, Cov);
    const Smoothed s = cv_smooth(run, 256);
    double dx = 0, dP = 0;
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      dx = std::max(dx, (s.x[k] - X.segment<4>(4 * k)).cwiseAbs().maxCoeff());
      dP = std::max(dP, (s.P[k] - Cov.block<4, 4>(4 * k, 4 * k)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(dx, 1e-9) << "seed " << seed;
    EXPECT_LT(dP, 1e-9) << "seed " << seed;
  }
}

TEST(RtsSmoother, SameBitsWhateverTheCheckpointInterval) {
  // Sparse measurements: with segment 256 the stretches between them are recomputed; with 1
  // every sample is a record. The recomputation is the filter's own time update: same bits.
  const CvRun run = make_run(400, 37, 4);
  const Smoothed a = cv_smooth(run, 1), b = cv_smooth(run, 5), c = cv_smooth(run, 256);
  EXPECT_EQ(a.records, run.dt.size());
  EXPECT_LT(c.records, 20u);
  for (std::size_t k = 0; k < a.x.size(); ++k) {
    EXPECT_TRUE(a.x[k] == b.x[k] && a.x[k] == c.x[k]) << k;
    EXPECT_TRUE(a.P[k] == b.P[k] && a.P[k] == c.P[k]) << k;
  }
}

TEST(RtsSmoother, SmoothedCovarianceNeverAboveForward) {
  const CvRun run = make_run(300, 25, 5);
  CvFilter f;
  NoBatchObserver none;
  std::vector<Vec4d> xf;
  std::vector<Mat4d> Pf;
  cv_forward(run, f, none, &xf, &Pf);
  const Smoothed s = cv_smooth(run, 16);
  for (std::size_t k = 0; k < xf.size(); ++k) {
    // P - P^s is positive semi-definite (to rounding), so every variance is at most the forward one.
    const Eigen::SelfAdjointEigenSolver<Mat4d> es(Pf[k] - s.P[k]);
    EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * Pf[k].norm()) << k;
  }
  // The last sample is the forward estimate.
  EXPECT_TRUE(s.x.back() == xf.back());
}

TEST(RtsSmoother, RefusedTimeUpdateIsSameAndCapacityIsKept) {
  CvRun run = make_run(120, 10, 6);
  run.dt[50] = 5.0;  // above max_dt: the time update of sample 50 is refused (state kept)
  const Smoothed s = cv_smooth(run, 256);
  EXPECT_TRUE(s.x[49] == s.x[50]);
  EXPECT_TRUE(s.P[49] == s.P[50]);
  // Out of capacity: fewer records reserved than epochs seen -> refused, no smoothing.
  CvModel model;
  model.dt = run.dt.data();
  RtsSmoother<CvModel> sm(model);
  ASSERT_TRUE(sm.reserve(run.dt.size(), 0, 1000));
  CvFilter f;
  cv_forward(run, f, sm);
  EXPECT_EQ(sm.smooth([](std::size_t, const CvModel::Record&, const Mat4d&) {}),
            RtsSmoother<CvModel>::Result::OutOfCapacity);
}

TEST(RtsSmoother, PackedSymmetricRoundTrip) {
  std::mt19937 g(7);
  std::normal_distribution<double> nd;
  Mat<double, 6, 6> A;
  for (int i = 0; i < 36; ++i) A.data()[i] = nd(g);
  const Mat<double, 6, 6> P = A * A.transpose();
  PackedSym<double, 6> p;
  p.pack(P);
  EXPECT_TRUE(p.unpack() == P);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(p.diag(i), P(i, i));
}

