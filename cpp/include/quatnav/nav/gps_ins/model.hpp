// quatnav: GpsInsFilter's error-state model (nav/gps_ins.hpp): the continuous error dynamics F,
// the process noise density, the injection of a correction into the nominal state, and the check
// of a candidate state. The equations and the paper's slips are in the comment of gps_ins.hpp.
#pragma once

#include <cmath>

#include "../../core/checks.hpp"
#include "../../core/covariance.hpp"
#include "../../core/earth.hpp"
#include "../../core/quaternion.hpp"
#include "../../core/types.hpp"
#include "../strapdown.hpp"
#include "params.hpp"

namespace quatnav {

/// The error state: [dp (N, E, D, m), dv (m/s), psi (rad), db_a (m/s^2), db_g (rad/s),
/// d_baro_offset (m)] and, with the scale-factor states, [ds_a, ds_g] (1); the index of the first
/// component of each block.
namespace gpsins {
constexpr int kN = 16;
constexpr int kNScale = 22;
constexpr int kPos = 0, kVel = 3, kAtt = 6, kBa = 9, kBg = 12, kBo = 15, kSa = 16, kSg = 19;
/// The number of error states without (16) and with (22) the scale-factor states.
template <bool SF> constexpr int kStates = SF ? kNScale : kN;
}  // namespace gpsins

namespace detail {

template <class S> using Mat16 = Mat<S, gpsins::kN, gpsins::kN>;
template <class S, bool SF> using MatN = Mat<S, gpsins::kStates<SF>, gpsins::kStates<SF>>;
template <class S, bool SF> using VecN = Vec<S, gpsins::kStates<SF>>;

/// Largest |latitude| (rad) the filter navigates at: the Earth model divides by cos(lat) (about
/// 10 m from the pole). A state, fix or correction beyond it is refused.
constexpr double kGpsInsMaxAbsLat = 1.5707;

/// The nominal navigation state and the biases as the filter keeps them: finite, |q| = 1 to
/// rounding (a quaternion whose norm overflowed normalizes to zero, which this refuses) and the
/// latitude off the poles. Checked on every candidate state before it is committed.
/// The scale factors: finite and within (-0.5, 0.5) (the correction divides by 1 + s); exactly
/// zero without the scale-factor states.
template <class S, bool SF> bool gpsins_nav_ok(const GpsInsState<S, SF>& s) {
  // (Eigen's maxCoeff may skip a NaN: compared element by element, a NaN fails.)
  const bool scale_ok = SF ? ((s.acc_scale.array().abs() < S(0.5)).all() && (s.gyro_scale.array().abs() < S(0.5)).all())
                           : ((s.acc_scale.array() == S(0)).all() && (s.gyro_scale.array() == S(0)).all());
  return s.nav.q_nb.allFinite() && s.nav.v_n.allFinite() && std::isfinite(s.nav.lat) && std::isfinite(s.nav.lon) &&
         std::isfinite(s.nav.h) && std::abs(s.nav.lat) < kGpsInsMaxAbsLat && s.acc_bias.allFinite() &&
         s.gyro_bias.allFinite() && std::isfinite(s.baro_offset) && std::abs(s.nav.q_nb.norm() - S(1)) <= S(1e-3) &&
         scale_ok;
}

/// A state as the filter keeps it, and as set_state() takes it back: every floating-point field
/// finite (detail::fields_finite: the low-passes, the motion window, the times too), the nominal
/// state as gpsins_nav_ok, P exactly symmetric with a non-negative diagonal, q_scale >= 1 and the
/// enums in range. Checked by set_state() and at the end of every time update; an update checks
/// its candidate with gpsins_nav_ok and its covariance with acceptable_covariance.
template <class S, bool SF> bool gpsins_state_ok(const GpsInsState<S, SF>& s) {
  return fields_finite(s) && gpsins_nav_ok(s) && acceptable_covariance<S, gpsins::kStates<SF>>(s.P) &&
         s.q_scale >= S(1) && int(s.phase) <= 2 && int(s.align_method) <= 4 && int(s.heading_source) <= 5;
}

/// The IMU corrected by the bias (and scale-factor) estimates, in the body axes: the rate or
/// specific force m_b = (1 + s) * m + b (per axis) gives m = (m_b - b) / (1 + s).
template <class S, bool SF> Vec3<S> gpsins_correct(const Vec3<S>& m_b, const Vec3<S>& b, const Vec3<S>& s) {
  if constexpr (SF)
    return (m_b - b).cwiseQuotient(Vec3<S>::Ones() + s);
  else
    return m_b - b;
}

/// The nonzero 3 x 3 blocks of the continuous error dynamics F (16 x 16) at a nominal state, for
/// the bias-corrected specific force f_b (m/s^2), named by block row and column (p position, v
/// velocity, a attitude psi, ba / bg the accelerometer / gyro bias). The other blocks are zero
/// but F_pv = I, F_ba,ba = ba I and F_bg,bg = bg I (-1 / tau, 0 for a random walk); the altimeter
/// offset is a random walk: its row is zero. Equations: see the file comment of gps_ins.hpp.
template <class S> struct GpsInsFBlocks {
  Mat3<S> pp, vp, vv, va, vba, ap, av, aa, abg;
  S ba = S(0), bg = S(0);
  /// With the scale-factor states: F_v,sa and F_psi,sg (else unset).
  Mat3<S> vsa, asg;
};

/// The columns of the scale-factor states. With m = (m_b - b) / (1 + s) per axis (gpsins_correct),
/// (1 + s_e) m_e - (1 + s_t) m_t = -(b_e - b_t), so to first order the error of the corrected input
/// is dm = -D (db + diag(m) ds) with D = diag(1 / (1 + s)): F_v,ba = -C D, F_v,sa = -C D diag(f),
/// F_psi,bg = -C D_g, F_psi,sg = -C D_g diag(w) (f, w the corrected specific force and rate).
/// The scale factors are random walks (their F rows are zero).
template <class S>
void gpsins_F_scale(GpsInsFBlocks<S>& F, const Vec3<S>& f_b, const Vec3<S>& w_b, const Vec3<S>& s_a,
                    const Vec3<S>& s_g) {
  const Vec3<S> da = (Vec3<S>::Ones() + s_a).cwiseInverse();
  const Vec3<S> dg = (Vec3<S>::Ones() + s_g).cwiseInverse();
  F.vba = F.vba * da.asDiagonal();
  F.abg = F.abg * dg.asDiagonal();
  F.vsa = F.vba * f_b.asDiagonal();
  F.asg = F.abg * w_b.asDiagonal();
}

template <class S>
GpsInsFBlocks<S> gpsins_F_blocks(const StrapdownState<S>& nav, const Vec3<S>& f_b, const GpsInsParams<S>& p) {
  using std::cos;
  using std::sin;
  using std::tan;
  GpsInsFBlocks<S> F;
  const double L = nav.lat, h = nav.h;
  const earth::Radii<double> r = earth::radii<double>(L);
  const double Rm = r.R_M + h, Rn = r.R_N + h;
  const Vec3<double> v = nav.v_n.template cast<double>();
  const double tL = tan(L), sL = sin(L), cL = cos(L);
  const Mat3<S> C = quat::to_rotmat(nav.q_nb);
  const Vec3<S> f_n = C * f_b;

  // eq. (9): position error (m) from the exact linearization of the geodetic rates.
  Mat3<double> Fpp = Mat3<double>::Zero();
  Fpp(0, 0) = -v[2] / Rm;
  Fpp(0, 2) = v[0] / Rm;
  Fpp(1, 0) = v[1] * tL / Rm;
  Fpp(1, 1) = -v[2] / Rn - v[0] * tL / Rm;
  Fpp(1, 2) = v[1] / Rn;
  F.pp = Fpp.template cast<S>();

  // Gravity error: dg_D = dg/dh dh + dg/dL dL with dh = -dp_D, dL = dp_N / Rm.
  const double s2 = sL * sL;
  const double dg_dh = earth::kG2 + earth::kG3 * s2;
  const double dg_dL = (earth::kG1 + earth::kG3 * h) * 2.0 * sL * cL;
  Mat3<double> Fvp = Mat3<double>::Zero();
  Fvp(2, 2) = -dg_dh;
  Fvp(2, 0) = dg_dL / Rm;

  Mat3<double> Fvv = Mat3<double>::Zero();
  Mat3<double> Fpsi_p = Mat3<double>::Zero();
  Mat3<double> Fpsi_v = Mat3<double>::Zero();
  Vec3<double> w_in = Vec3<double>::Zero();
  if (p.earth_rotation) {
    const Vec3<double> w_ie = earth::earth_rate_n<double>(L);
    const Vec3<double> w_en = earth::transport_rate_n<double>(L, h, v);
    w_in = w_ie + w_en;
    // d w_en / d v
    Mat3<double> Wv = Mat3<double>::Zero();
    Wv(0, 1) = 1.0 / Rn;
    Wv(1, 0) = -1.0 / Rm;
    Wv(2, 1) = -tL / Rn;
    // d w_ie / d p and d w_en / d p (columns N and D; radii taken constant in latitude)
    Mat3<double> Wie_p = Mat3<double>::Zero();
    Wie_p(0, 0) = -earth::kOmegaIe * sL / Rm;
    Wie_p(2, 0) = -earth::kOmegaIe * cL / Rm;
    Mat3<double> Wen_p = Mat3<double>::Zero();
    Wen_p(2, 0) = -v[1] / (Rn * cL * cL * Rm);
    Wen_p(0, 2) = v[1] / (Rn * Rn);
    Wen_p(1, 2) = -v[0] / (Rm * Rm);
    Wen_p(2, 2) = -v[1] * tL / (Rn * Rn);
    const Mat3<double> Vx = quat::skew<double>(v);
    // eq. (8): Coriolis and transport terms.
    Fvv = -quat::skew<double>(2.0 * w_ie + w_en) + Vx * Wv;
    Fvp += Vx * (2.0 * Wie_p + Wen_p);
    // eq. (10) (corrected): -[w_in x] psi - dw_in.
    Fpsi_v = -Wv;
    Fpsi_p = -(Wie_p + Wen_p);
  }
  F.vp = Fvp.template cast<S>();
  F.vv = Fvv.template cast<S>();
  F.va = -quat::skew<S>(f_n);
  F.vba = -C;
  F.ap = Fpsi_p.template cast<S>();
  F.av = Fpsi_v.template cast<S>();
  F.aa = -quat::skew<S>(w_in.template cast<S>());
  F.abg = -C;
  if (p.acc_bias_tau > S(0)) F.ba = S(-1) / p.acc_bias_tau;
  if (p.gyro_bias_tau > S(0)) F.bg = S(-1) / p.gyro_bias_tau;
  return F;
}

/// Continuous-time error dynamics matrix F (16 x 16) at a nominal state, for the bias-corrected
/// specific force f_b (m/s^2): the blocks of gpsins_F_blocks in place.
template <class S, bool SF = false>
MatN<S, SF> gpsins_F_dense(const GpsInsFBlocks<S>& B) {
  MatN<S, SF> F = MatN<S, SF>::Zero();
  F.template block<3, 3>(gpsins::kPos, gpsins::kPos) = B.pp;
  F.template block<3, 3>(gpsins::kPos, gpsins::kVel).setIdentity();
  F.template block<3, 3>(gpsins::kVel, gpsins::kPos) = B.vp;
  F.template block<3, 3>(gpsins::kVel, gpsins::kVel) = B.vv;
  F.template block<3, 3>(gpsins::kVel, gpsins::kAtt) = B.va;
  F.template block<3, 3>(gpsins::kVel, gpsins::kBa) = B.vba;
  F.template block<3, 3>(gpsins::kAtt, gpsins::kPos) = B.ap;
  F.template block<3, 3>(gpsins::kAtt, gpsins::kVel) = B.av;
  F.template block<3, 3>(gpsins::kAtt, gpsins::kAtt) = B.aa;
  F.template block<3, 3>(gpsins::kAtt, gpsins::kBg) = B.abg;
  F.template block<3, 3>(gpsins::kBa, gpsins::kBa).diagonal().setConstant(B.ba);
  F.template block<3, 3>(gpsins::kBg, gpsins::kBg).diagonal().setConstant(B.bg);
  if constexpr (SF) {
    F.template block<3, 3>(gpsins::kVel, gpsins::kSa) = B.vsa;
    F.template block<3, 3>(gpsins::kAtt, gpsins::kSg) = B.asg;
  }
  return F;
}

template <class S>
Mat16<S> gpsins_F(const StrapdownState<S>& nav, const Vec3<S>& f_b, const GpsInsParams<S>& p) {
  return gpsins_F_dense<S, false>(gpsins_F_blocks<S>(nav, f_b, p));
}

/// F (22 x 22) with the scale-factor states, for the corrected specific force f_b and rate w_b and
/// the scale-factor estimates s_a, s_g (gpsins_F_scale).
template <class S>
MatN<S, true> gpsins_F_scaled(const StrapdownState<S>& nav, const Vec3<S>& f_b, const Vec3<S>& w_b,
                              const Vec3<S>& s_a, const Vec3<S>& s_g, const GpsInsParams<S>& p) {
  GpsInsFBlocks<S> B = gpsins_F_blocks<S>(nav, f_b, p);
  gpsins_F_scale<S>(B, f_b, w_b, s_a, s_g);
  return gpsins_F_dense<S, true>(B);
}

/// The discrete error-state transition over one IMU interval dt, with F at the nominal state
/// before the step, Phi = I + F dt + (F dt)^2 / 2, by its blocks: with the navigation states
/// n = [p, v, psi] (0-8) and the bias and offset states b (9-15),
///   Phi = [ N  Ba  [0; Bg]  0 ]
///         [ 0  da I   0     0 ]
///         [ 0   0   dg I    0 ]
///         [ 0   0     0     1 ]
/// (the position rows of the gyro bias columns are zero: F_pp, F_pv reach the gyro bias only in
/// F^3). Each block of (F dt)^2 is the sum of the products of its nonzero blocks: 19 products of
/// 3 x 3 matrices (513 multiply-adds) instead of the 16 x 16 product (4,096).
/// With the scale-factor states, their columns Sa (rows p, v, psi) and Sg (rows v, psi) follow the
/// same pattern as the bias columns (the scale factors are random walks: their diagonal is 1).
template <class S, bool SF = false> struct GpsInsPhi {
  Mat<S, 9, 9> N;
  Mat<S, 9, 3> Ba;
  Mat<S, 6, 3> Bg;
  S da = S(1), dg = S(1);
  Mat<S, 9, 3> Sa;  ///< scale-factor states only
  Mat<S, 6, 3> Sg;  ///< scale-factor states only

  /// The dense matrix.
  MatN<S, SF> dense() const {
    MatN<S, SF> Phi = MatN<S, SF>::Identity();
    Phi.template topLeftCorner<9, 9>() = N;
    Phi.template block<9, 3>(0, gpsins::kBa) = Ba;
    Phi.template block<6, 3>(gpsins::kVel, gpsins::kBg) = Bg;
    Phi.template block<3, 3>(gpsins::kBa, gpsins::kBa).diagonal().setConstant(da);
    Phi.template block<3, 3>(gpsins::kBg, gpsins::kBg).diagonal().setConstant(dg);
    if constexpr (SF) {
      Phi.template block<9, 3>(0, gpsins::kSa) = Sa;
      Phi.template block<6, 3>(gpsins::kVel, gpsins::kSg) = Sg;
    }
    return Phi;
  }
};

template <class S, bool SF = false> GpsInsPhi<S, SF> gpsins_Phi_of(const GpsInsFBlocks<S>& F, S dt) {
  // A = F dt, block by block (A_pv = dt I).
  const Mat3<S> pp = F.pp * dt, vp = F.vp * dt, vv = F.vv * dt, va = F.va * dt, vba = F.vba * dt;
  const Mat3<S> ap = F.ap * dt, av = F.av * dt, aa = F.aa * dt, abg = F.abg * dt;
  const S ba = F.ba * dt, bg = F.bg * dt;
  const Mat3<S> I = Mat3<S>::Identity();
  const S h = S(0.5);
  GpsInsPhi<S, SF> Phi;
  // Row p: A_pp, A_pv.
  Phi.N.template block<3, 3>(0, 0) = I + pp + h * (pp * pp + dt * vp);
  Phi.N.template block<3, 3>(0, 3) = dt * I + h * (dt * pp + dt * vv);
  Phi.N.template block<3, 3>(0, 6) = h * (dt * va);
  Phi.Ba.template block<3, 3>(0, 0) = h * (dt * vba);
  // Row v: A_vp, A_vv, A_va, A_vba.
  Phi.N.template block<3, 3>(3, 0) = vp + h * (vp * pp + vv * vp + va * ap);
  Phi.N.template block<3, 3>(3, 3) = I + vv + h * (dt * vp + vv * vv + va * av);
  Phi.N.template block<3, 3>(3, 6) = va + h * (vv * va + va * aa);
  Phi.Ba.template block<3, 3>(3, 0) = vba + h * (vv * vba + ba * vba);
  Phi.Bg.template block<3, 3>(0, 0) = h * (va * abg);
  // Row psi: A_ap, A_av, A_aa, A_abg.
  Phi.N.template block<3, 3>(6, 0) = ap + h * (ap * pp + av * vp + aa * ap);
  Phi.N.template block<3, 3>(6, 3) = av + h * (dt * ap + av * vv + aa * av);
  Phi.N.template block<3, 3>(6, 6) = I + aa + h * (av * va + aa * aa);
  Phi.Ba.template block<3, 3>(6, 0) = h * (av * vba);
  Phi.Bg.template block<3, 3>(3, 0) = abg + h * (aa * abg + bg * abg);
  // The biases: (1 + a + a^2 / 2) I.
  Phi.da = S(1) + ba + h * (ba * ba);
  Phi.dg = S(1) + bg + h * (bg * bg);
  if constexpr (SF) {
    // The scale-factor columns: as the bias columns with A_sa,sa = A_sg,sg = 0.
    const Mat3<S> vsa = F.vsa * dt, asg = F.asg * dt;
    Phi.Sa.template block<3, 3>(0, 0) = h * (dt * vsa);
    Phi.Sa.template block<3, 3>(3, 0) = vsa + h * (vv * vsa);
    Phi.Sa.template block<3, 3>(6, 0) = h * (av * vsa);
    Phi.Sg.template block<3, 3>(0, 0) = h * (va * asg);
    Phi.Sg.template block<3, 3>(3, 0) = asg + h * (aa * asg);
  }
  return Phi;
}

template <class S>
GpsInsPhi<S> gpsins_Phi_blocks(const StrapdownState<S>& nav, const Vec3<S>& f_b, S dt, const GpsInsParams<S>& p) {
  return gpsins_Phi_of<S, false>(gpsins_F_blocks<S>(nav, f_b, p), dt);
}

/// Phi by blocks at a state of either size: f_b, w_b the corrected specific force and rate (w_b
/// and the scale factors enter only with the scale-factor states).
template <class S, bool SF>
GpsInsPhi<S, SF> gpsins_Phi_state(const GpsInsState<S, SF>& s, const Vec3<S>& f_b, const Vec3<S>& w_b, S dt,
                                  const GpsInsParams<S>& p) {
  GpsInsFBlocks<S> F = gpsins_F_blocks<S>(s.nav, f_b, p);
  if constexpr (SF) gpsins_F_scale<S>(F, f_b, w_b, s.acc_scale, s.gyro_scale);
  return gpsins_Phi_of<S, SF>(F, dt);
}

/// The discrete error-state transition over one IMU interval dt, with F at the nominal state
/// before the step: Phi = I + F dt + (F dt)^2 / 2 (the time update's and the smoother's), dense.
template <class S>
Mat16<S> gpsins_Phi(const StrapdownState<S>& nav, const Vec3<S>& f_b, S dt, const GpsInsParams<S>& p) {
  return gpsins_Phi_blocks<S>(nav, f_b, dt, p).dense();
}

/// The covariance time update P <- Phi P Phi^T + Qd with Qd = (Phi Qc Phi^T + Qc) dt / 2
/// (trapezoidal; qc: the diagonal of Qc), evaluated as Phi (P + Qc dt / 2) Phi^T + Qc dt / 2 with
/// only the nonzero blocks of Phi (GpsInsPhi). With T = the navigation rows of Phi P':
///   T      = N P'_n + Ba P'_ba + [0; Bg] P'_bg                         (9 x 16)
///   P_nn   = T_n N^T + T_ba Ba^T + T_bg [0; Bg]^T,  P_nb = T_b diag(da, dg, 1),  P_bn = P_nb^T,
///   P_bb   = diag(da, dg, 1) P'_bb diag(da, dg, 1).
/// 3,150 multiply-adds (T 2,016, P_nn 1,134; and 152 products by da, dg) instead of the 12,288
/// of the dense Phi P Phi^T and Phi Qc Phi^T (three 16 x 16 products). The result is symmetric
/// but for the rounding of P_nn (the caller symmetrizes). P must be symmetric (P_bn is taken as
/// P_nb^T).
/// With the scale-factor states the navigation rows gain Sa P'_sa + [0; Sg] P'_sg in T and
/// T_sa Sa^T + T_sg [0; Sg]^T in P_nn; their own block of diag(...) has 1 for each scale factor.
/// qc_att: a full 3 x 3 term added to Qc's attitude block (gpsins_Qc_rate); null (the default,
/// gyro_rate_noise = 0) adds nothing and costs nothing.
template <class S, bool SF>
MatN<S, SF> gpsins_propagate(const GpsInsPhi<S, SF>& Phi, const MatN<S, SF>& P, const VecN<S, SF>& qc, S dt,
                             const Mat3<S>* qc_att = nullptr) {
  constexpr int N = gpsins::kStates<SF>, NB = N - 9;
  const VecN<S, SF> q2 = (S(0.5) * dt) * qc;
  Mat3<S> qa2;
  if (qc_att) qa2 = (S(0.5) * dt) * *qc_att;
  MatN<S, SF> P1 = P;
  P1.diagonal() += q2;
  if (qc_att) P1.template block<3, 3>(6, 6) += qa2;
  Mat<S, 9, N> T = fixed_mul(Phi.N, P1.template topRows<9>());
  T += fixed_mul(Phi.Ba, P1.template middleRows<3>(gpsins::kBa));
  T.template bottomRows<6>() += fixed_mul(Phi.Bg, P1.template middleRows<3>(gpsins::kBg));
  if constexpr (SF) {
    T += fixed_mul(Phi.Sa, P1.template middleRows<3>(gpsins::kSa));
    T.template bottomRows<6>() += fixed_mul(Phi.Sg, P1.template middleRows<3>(gpsins::kSg));
  }
  MatN<S, SF> Pn;
  Mat<S, 9, 9> Pnn = fixed_mul(T.template leftCols<9>(), Phi.N.transpose());
  Pnn += fixed_mul(T.template middleCols<3>(gpsins::kBa), Phi.Ba.transpose());
  Pnn.template rightCols<6>() += fixed_mul(T.template middleCols<3>(gpsins::kBg), Phi.Bg.transpose());
  if constexpr (SF) {
    Pnn += fixed_mul(T.template middleCols<3>(gpsins::kSa), Phi.Sa.transpose());
    Pnn.template rightCols<6>() += fixed_mul(T.template middleCols<3>(gpsins::kSg), Phi.Sg.transpose());
    Pn.template block<9, 6>(0, gpsins::kSa) = T.template middleCols<6>(gpsins::kSa);
  }
  Pn.template topLeftCorner<9, 9>() = Pnn;
  Pn.template block<9, 3>(0, gpsins::kBa) = Phi.da * T.template middleCols<3>(gpsins::kBa);
  Pn.template block<9, 3>(0, gpsins::kBg) = Phi.dg * T.template middleCols<3>(gpsins::kBg);
  Pn.template block<9, 1>(0, gpsins::kBo) = T.col(gpsins::kBo);
  Pn.template bottomLeftCorner<NB, 9>() = Pn.template topRightCorner<9, NB>().transpose();
  Vec<S, NB> d = Vec<S, NB>::Ones();
  d.template head<7>() << Phi.da, Phi.da, Phi.da, Phi.dg, Phi.dg, Phi.dg, S(1);
  Pn.template bottomRightCorner<NB, NB>() =
      d.asDiagonal() * P1.template bottomRightCorner<NB, NB>() * d.asDiagonal();
  Pn.diagonal() += q2;
  if (qc_att) Pn.template block<3, 3>(6, 6) += qa2;
  return Pn;
}

/// Continuous process noise spectral density Qc (diagonal, 16 x 16); the IMU terms scaled by the
/// adaptation's q_scale.
template <class S, bool SF = false> VecN<S, SF> gpsins_Qc_diag(const GpsInsParams<S>& p, S q_scale) {
  VecN<S, SF> q = VecN<S, SF>::Zero();
  q.template segment<3>(3).setConstant(q_scale * p.acc_noise * p.acc_noise);
  q.template segment<3>(6).setConstant(q_scale * p.gyro_noise * p.gyro_noise);
  q.template segment<3>(9).setConstant(q_scale * p.acc_bias_noise * p.acc_bias_noise);
  q.template segment<3>(12).setConstant(q_scale * p.gyro_bias_noise * p.gyro_bias_noise);
  q[gpsins::kBo] = p.baro_offset_noise * p.baro_offset_noise;
  if constexpr (SF) {
    q.template segment<3>(gpsins::kSa).setConstant(q_scale * p.acc_scale_noise * p.acc_scale_noise);
    q.template segment<3>(gpsins::kSg).setConstant(q_scale * p.gyro_scale_noise * p.gyro_scale_noise);
  }
  return q;
}

/// The attitude's rate-proportional process noise (k = gyro_rate_noise, 1/sqrt(Hz), the name and
/// unit of the attitude filters'): Qc_att = k^2 |w|^2 I (rad^2/s, NED) at the corrected rate w =
/// w_m - b; with the scale-factor states k^2 C_nb diag(|w|^2 - w_i^2) C_nb^T (below).
/// Derivation. The gyro reads (I + E) w + b + n: E holds the scale-factor errors on its diagonal
/// and the misalignment (non-orthogonality) errors off it, nine entries taken independent, each
/// of one-sigma sigma_E; the model has no state for E (16 states), so the rate error E w turns
/// the attitude unseen: dpsi_n/dt = -C_nb E w. Its covariance, E[(E w)(E w)^T]_ij =
/// sum_kl E[E_ik E_jl] w_k w_l = sigma_E^2 |w|^2 delta_ij, is isotropic: the same in NED. Over a
/// turn about a fixed axis u (fixed in the body and in NED) by theta = |w| T:
///  * along u the error u^T E u |w| is constant and grows with the angle: variance
///    sigma_E^2 theta^2;
///  * across u it is constant in the body, turns with it in NED and integrates to a chord,
///    2 sin(theta / 2) / |w| times it: variance 4 sigma_E^2 sin^2(theta / 2) per axis, within
///    20 % of sigma_E^2 theta^2 up to 90 deg, at most 4 sigma_E^2 beyond.
/// E is constant; white noise of density q gives q T over the turn, sigma_E^2 |w|^2 T^2 wants q =
/// sigma_E^2 T |w|^2: the rate error taken as correlated over one turn and white beyond (turns
/// go either way: for turns in random directions the variance of their sum is the sum of theirs),
/// k = sigma_E sqrt(T_turn), T_turn = (int |w| dt)^2 / int |w|^2 dt for a turn whose rate ramps,
/// the same on every axis: exact along the axis, and across it for turns up to about 90 deg,
/// conservative for longer ones (a 270 deg loop: 22 sigma_E^2 where E gives 2). For the simulated
/// car (0.1 % scale, 1 mrad misalignment: sigma_E = 1e-3) and its 19 s on-ramp loop, k = 4.4e-3
/// sqrt(s). Off by default: on the car, NaveGo and the real walk it moved the figures by their
/// noise, some for the worse (docs/GPSINS_DATA.md, 2026-12-06).
/// With the scale-factor states (SF) the diagonal of E is estimated and the misalignment remains:
/// E[(E' w)(E' w)^T] = sigma_E^2 diag(|w|^2 - w_i^2) in the body (E' = E off its diagonal),
/// rotated into NED by C_nb. Scaled by the adaptation's q_scale like the IMU densities; zero when
/// k = 0 or w = 0.
template <class S, bool SF>
Mat3<S> gpsins_Qc_rate(const GpsInsParams<S>& p, S q_scale, const Quat<S>& q_nb, const Vec3<S>& w_b) {
  const S w2 = w_b.squaredNorm();
  if (!(p.gyro_rate_noise > S(0) && w2 > S(0))) return Mat3<S>::Zero();
  const S k2 = q_scale * p.gyro_rate_noise * p.gyro_rate_noise;
  if constexpr (SF) {
    const Mat3<S> C = quat::to_rotmat(q_nb);
    const Vec3<S> d = (Vec3<S>::Constant(w2) - w_b.cwiseAbs2()) * k2;
    return C * d.asDiagonal() * C.transpose();
  } else {
    return (k2 * w2) * Mat3<S>::Identity();
  }
}

/// P's time update with the filter's Qc at the corrected rate w_b and the attitude after the step;
/// the rate-proportional attitude term is neither computed nor added while gyro_rate_noise is 0.
template <class S, bool SF>
MatN<S, SF> gpsins_propagate_P(const GpsInsPhi<S, SF>& Phi, const MatN<S, SF>& P, const GpsInsParams<S>& p,
                               S q_scale, const Quat<S>& q_nb, const Vec3<S>& w_b, S dt) {
  const VecN<S, SF> qc = gpsins_Qc_diag<S, SF>(p, q_scale);
  if (!(p.gyro_rate_noise > S(0))) return gpsins_propagate<S, SF>(Phi, P, qc, dt);
  const Mat3<S> qa = gpsins_Qc_rate<S, SF>(p, q_scale, q_nb, w_b);
  return gpsins_propagate<S, SF>(Phi, P, qc, dt, &qa);
}

/// Inject an error estimate into a copy of the state (the feedback of paper Fig. 2).
template <class S, bool SF> void gpsins_inject(GpsInsState<S, SF>& s, const VecN<S, SF>& dx) {
  const Vec3<double> dp = dx.template segment<3>(0).template cast<double>();
  earth::geodetic_add(s.nav.lat, s.nav.lon, s.nav.h, Vec3<double>(-dp));
  s.nav.v_n -= dx.template segment<3>(3);
  Quat<S> q = quat::mul(quat::from_rotvec(Vec3<S>(-dx.template segment<3>(6))), s.nav.q_nb);
  s.nav.q_nb = q / q.norm();
  s.acc_bias -= dx.template segment<3>(9);
  s.gyro_bias -= dx.template segment<3>(12);
  s.baro_offset -= double(dx[gpsins::kBo]);
  if constexpr (SF) {
    s.acc_scale -= dx.template segment<3>(gpsins::kSa);
    s.gyro_scale -= dx.template segment<3>(gpsins::kSg);
  }
}

}  // namespace detail

}  // namespace quatnav
