// The shared machinery of core/: the [F B; 0 I] covariance prediction, the quaternion block,
// the commit path, the geodetic add/difference and the Earth terms.
#include <gtest/gtest.h>

#include <quatnav/quatnav.hpp>


using namespace quatnav;

namespace {
template <int N> Mat<double, N, N> spd(unsigned seed) {
  std::srand(seed);
  const Mat<double, N, N> A = Mat<double, N, N>::Random();
  Mat<double, N, N> P = A * A.transpose() + 0.1 * Mat<double, N, N>::Identity();
  symmetrize(P);
  return P;
}
}  // namespace

TEST(CoreMachinery, PredictCovarianceFbIsPhiPPhiTPlusQ) {
  const Mat<double, 7, 7> P = spd<7>(1);
  std::srand(2);
  const Mat4<double> F = Mat4<double>::Random();
  const Mat43<double> B = Mat43<double>::Random();
  const Mat4<double> Qaa = spd<4>(3);
  Mat<double, 7, 7> Phi = Mat<double, 7, 7>::Identity();
  Phi.topLeftCorner<4, 4>() = F;
  Phi.topRightCorner<4, 3>() = B;
  Mat<double, 7, 7> Q = Mat<double, 7, 7>::Zero();
  Q.topLeftCorner<4, 4>() = Qaa;
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(0.25);
  Mat<double, 7, 7> Pn;
  predict_covariance_fb<double, 4, 3>(P, F, B, Qaa, 0.25, Pn);
  const Mat<double, 7, 7> ref = Phi * P * Phi.transpose() + Q;
  EXPECT_LT((Pn - ref).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff());
  const bool mirrored = Pn.topRightCorner<4, 3>() == Pn.bottomLeftCorner<3, 4>().transpose();
  EXPECT_TRUE(mirrored);  // exact mirror
}

TEST(CoreMachinery, QuatBlockMapsAndNormalizes) {
  using QB = QuatBlock<double, 13, 3>;
  const Quat<double> q = quat::normalized(Quat<double>(0.7, -0.2, 0.5, 0.3));
  const Mat<double, 12, 13> T = QB::to_error(q);
  const Mat<double, 13, 12> Tb = QB::from_error(q);
  EXPECT_LT((T * Tb - Mat<double, 12, 12>::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  // Normalization: unit q, no variance along q, and the error covariance unchanged by T' T.
  Vec<double, 13> x = Vec<double, 13>::Zero();
  Mat<double, 13, 13> P = spd<13>(4);
  Quat<double> qs = 1.3 * q;
  QB::normalize(qs, P);
  EXPECT_NEAR(qs.norm(), 1.0, 1e-15);
  EXPECT_LT((P.block<4, 4>(3, 3) * qs).norm(), 1e-14);
  const Mat<double, 12, 12> Pe = QB::error_covariance(qs, P);
  EXPECT_LT((QB::from_error_covariance(qs, Pe) - P).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((QB::attitude_covariance(qs, P) - Pe.block<3, 3>(3, 3)).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((QB::attitude_variance(qs, P) - Pe.block<3, 3>(3, 3).diagonal()).cwiseAbs().maxCoeff(), 1e-14);
  // Retraction: q exp(dtheta) and plain sums elsewhere.
  x.segment<4>(3) = qs;
  Vec<double, 12> dx = Vec<double, 12>::LinSpaced(12, -0.1, 0.1);
  const Vec<double, 13> y = QB::retract(x, dx);
  EXPECT_EQ(Vec3<double>(y.head<3>()), Vec3<double>(dx.head<3>()));
  EXPECT_LT((quat::to_rotvec(quat::mul(quat::conj(qs), Quat<double>(y.segment<4>(3)))) - dx.segment<3>(3)).norm(), 1e-15);
  const bool tail_sum = y.tail<6>() == dx.tail<6>();
  EXPECT_TRUE(tail_sum);
  // The two forms of the normalization and the floor agree to rounding (state [q, b]).
  using QE = QuatBlock<double, 7, 0>;
  Mat<double, 7, 7> P7 = spd<7>(5), P7b = P7;
  Quat<double> q1 = 0.8 * q, q2 = q1;
  QE::normalize(q1, P7);
  QE::normalize_symmetric(q2, P7b);
  EXPECT_LT((P7 - P7b).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(P7b, P7b.transpose());  // exactly symmetric without a symmetrization
  EXPECT_TRUE(QE::floor_error_covariance(q1, P7, 1.0));
  EXPECT_TRUE(QE::floor_symmetric_error_covariance(q2, P7b, 1.0));
  EXPECT_LT((P7 - P7b).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT(QE::attitude_covariance(q1, P7).diagonal().minCoeff(), 1.0 - 1e-9);
}

TEST(CoreMachinery, CommitPathRefusesWithTheStateUntouched) {
  UpdateResult<double, 1> res;
  Mat<double, 2, 2> P = Mat<double, 2, 2>::Identity();
  int state = 1, injected = 0;
  res.status = Status::Rejected;  // a refused correction: nothing runs
  EXPECT_EQ(inject_and_commit(
                res, P, [&] { return ++injected; }, Always{}, Always{}, [&](int v, const Mat<double, 2, 2>&) { state = v; }),
            Status::Rejected);
  EXPECT_EQ(injected, 0);
  res.status = Status::Ok;  // a candidate that fails its check
  EXPECT_EQ(inject_and_commit(
                res, P, [&] { return 7; }, [](int v, const Mat<double, 2, 2>&) { return v < 5; }, Always{},
                [&](int v, const Mat<double, 2, 2>&) { state = v; }),
            Status::NumericalFailure);
  EXPECT_EQ(state, 1);
  res.status = Status::Ok;  // conditioning refuses
  EXPECT_EQ(inject_and_commit(
                res, P, [&] { return 3; }, Always{}, [](int&, Mat<double, 2, 2>&) { return false; },
                [&](int v, const Mat<double, 2, 2>&) { state = v; }),
            Status::NumericalFailure);
  EXPECT_EQ(state, 1);
  res.status = Status::Ok;  // accepted: conditioned, then committed
  EXPECT_EQ(inject_and_commit(
                res, P, [&] { return 3; }, Always{},
                [](int& v, Mat<double, 2, 2>& Pc) {
                  v *= 2;
                  Pc *= 2.0;
                  return true;
                },
                [&](int v, const Mat<double, 2, 2>&) { state = v; }),
            Status::Ok);
  EXPECT_EQ(state, 6);
  EXPECT_EQ(P(0, 0), 2.0);
}

TEST(CoreMachinery, GeodeticAddAndDifferenceRoundTrip) {
  const double lat0 = 0.9, lon0 = 3.14159, h0 = 250.0;
  double lat = lat0, lon = lon0, h = h0;
  const Vec3<double> d(120.0, 85.0, -12.0);
  earth::geodetic_add(lat, lon, h, d);  // crosses the antimeridian (lon > pi)
  const Vec3<double> back = earth::geodetic_diff<double>(lat, quat::wrap_pi(lon), h, lat0, lon0, h0);
  EXPECT_LT((back - d).norm(), 1e-6);
  EXPECT_EQ(earth::ned_to_geodetic<double>(d, lat0, lon0, h0), Vec3<double>(lat, lon, h));
}

TEST(CoreMachinery, EarthTermsInEitherPrecision) {
  const earth::Terms<double> e = earth::terms<double>(0.7, 100.0, Vec3<double>(10.0, -5.0, 1.0), true);
  EXPECT_EQ(e.g_n(), earth::gravity_n<double>(0.7, 100.0));
  EXPECT_EQ(e.omega_ie_n, earth::earth_rate_n<double>(0.7));
  EXPECT_EQ(e.omega_en_n, earth::transport_rate_n<double>(0.7, 100.0, Vec3<double>(10.0, -5.0, 1.0)));
  const earth::Terms<float> f = earth::terms<float>(0.7f, 100.0f, Vec3<float>(10.0f, -5.0f, 1.0f), false);
  EXPECT_EQ(f.omega_ie_n, Vec3<float>::Zero());
  EXPECT_EQ(f.omega_en_n, Vec3<float>::Zero());
  EXPECT_NEAR(f.g, e.g, 1e-5);
}
