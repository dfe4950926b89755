#!/usr/bin/env python3
"""Floating-point operations one filter step needs, counted from the structure of its math.

Not the products the code executes (bench/cpp/flop_counter.hpp counts those, dense or not): here
every product is counted over its structural nonzeros only. A term multiplied by an entry that is
exactly 1 costs no multiplication, a row of a transition that is a unit row (the state carried
over) costs nothing, a symmetric result is formed on its upper triangle only, and a diagonal block
costs one operation per entry.

Counting rules (the same as the counting scalar's, so the two columns compare): +, -, *, / and
sqrt one flop each; negation free; a fused multiply-add two; a libm call (sin, cos, atan2, asin,
exp, tan) one flop, and the calls are also listed per step in their own column because their
cost is not one FMA (bench/cpp/fma_peak.cpp measures it).

Each filter is one function that adds its terms to a Count, term by term, with the step as
quatnav_bench_filters runs it (bench/cpp/bench_filters.cpp). Usage:

    python3 bench/flops_needed.py            # the table
    python3 bench/flops_needed.py --terms    # every term of every filter
    python3 bench/flops_needed.py --json     # {case: {"flops": ..., "libm": ...}}
"""
from __future__ import annotations

import argparse
import json
import sys

import numpy as np

# --------------------------------------------------------------------------------------------
# Counting helpers
# --------------------------------------------------------------------------------------------


class Count:
    """Flops and libm calls of one step, kept term by term."""

    def __init__(self, name: str):
        self.name = name
        self.terms: list[tuple[str, int, int]] = []

    def add(self, what: str, flops: int, libm: int = 0) -> None:
        # A libm call is one flop in the total (the counting scalar's rule) and listed apart.
        self.terms.append((what, int(flops) + int(libm), int(libm)))

    def include(self, prefix: str, other: "Count", times: float = 1) -> None:
        for what, f, l in other.terms:
            self.terms.append((f"{prefix}{what}", round(f * times), round(l * times)))

    @property
    def flops(self) -> int:
        return sum(f for _, f, _ in self.terms)

    @property
    def libm(self) -> int:
        return sum(l for _, _, l in self.terms)


def dot(k: int, ones: int = 0) -> int:
    """Dot product of k nonzero terms of which `ones` multiply by exactly 1."""
    return 0 if k == 0 else (k - ones) + (k - 1)


# Small vector and quaternion operations, each from its formula.
DOT3 = dot(3)                     # 5
NORM3 = DOT3 + 1                  # squared norm, sqrt: 6
UNIT3 = NORM3 + 1 + 3             # norm, 1/n, 3 products: 10
CROSS = 6 + 3                     # 6 products, 3 differences
QMUL = 16 + 12                    # Hamilton product
QNORMALIZE = dot(4) + 1 + 1 + 4   # squared norm, sqrt, 1/n, 4 products: 13
ROTATE = 2 * CROSS + 3 + 3 + 3    # v + w t + u x t, t = 2 u x v: 27
QUAT_TO_ROTMAT = 4 + 10 + 12      # 2q, 10 pair products, 12 sums/differences: 26
# cos and sin(x)/x of the half angle from x^2 (quat::cos_sinc): for a step's angle (below 0.25 rad
# in double, 0.5 in float) two Taylor polynomials of 5 Horner steps (double; 3 in float), no libm.
COS_SINC = 2 * 5 * 2              # 20 (double)
ROTVEC_TO_QUAT = DOT3 + 1 + COS_SINC + 1 + 3  # |v|^2, x^2 = |v|^2 / 4, cos_sinc, sinc / 2, 3 products: 30
ROTVEC_TO_QUAT_LIBM = 0
QUAT_TO_ROTVEC = dot(3) + 1 + 1 + 3   # |v|, angle / |v|, 3 products (+ atan2): 10
# A low-pass step: its weight, then x + w (v - x). The parts (attitude/parts/*.hpp, detail::lowpass)
# weigh by dt / (tau + dt): an addition and a division, no libm call; MargFilter's own low-passes
# and GpsInsFilter's rest detector by 1 - exp(-dt / tau): a division, exp, a subtraction.
LOWPASS3 = 1 + 1 + 3 + 3 + 3      # weight (2), v - x, w (v - x), x + ...: 11 (+ exp where the weight has one)
LOWPASS1 = 1 + 1 + 3              # scalar: 5 (+ exp where the weight has one)


def mat_dense(m: int, k: int, n: int) -> int:
    return m * n * dot(k)


def pattern_product(A_nz: np.ndarray, B_nz: np.ndarray, A_one=None, B_one=None, upper_only=False) -> int:
    """Flops of C = A B over the structural nonzeros (A_one / B_one: entries that are exactly 1)."""
    A_one = np.zeros_like(A_nz) if A_one is None else A_one
    B_one = np.zeros_like(B_nz) if B_one is None else B_one
    total = 0
    for i in range(A_nz.shape[0]):
        for j in range(B_nz.shape[1]):
            if upper_only and j < i:
                continue
            common = A_nz[i, :] & B_nz[:, j]
            k = int(common.sum())
            ones = int((common & (A_one[i, :] | B_one[:, j])).sum())
            total += dot(k, ones)
    return total


def unit_rows(nz: np.ndarray, one: np.ndarray) -> np.ndarray:
    """Rows that are e_i exactly (the state carried over): one nonzero, a 1 on the diagonal."""
    n = nz.shape[0]
    return np.array([nz[i].sum() == 1 and nz[i, i] and one[i, i] for i in range(n)])


def covariance_predict(phi_nz: np.ndarray, phi_one: np.ndarray, q_upper_nnz: int) -> int:
    """P+ = Phi P Phi^T + Q, P dense symmetric, P+ on its upper triangle.

    M = Phi P for the rows of Phi that are not unit rows (a unit row of M is a row of P); then
    P+_ij = M_i . Phi_j for i <= j both non-unit rows (one of them a unit row: an entry of M or
    of P, free); Q added on its nonzeros.
    """
    n = phi_nz.shape[0]
    unit = unit_rows(phi_nz, phi_one)
    flops = 0
    for i in range(n):
        if not unit[i]:
            flops += n * dot(int(phi_nz[i].sum()), int((phi_nz[i] & phi_one[i]).sum()))
    for i in range(n):
        for j in range(i, n):
            if not unit[i] and not unit[j]:
                flops += dot(int(phi_nz[j].sum()), int((phi_nz[j] & phi_one[j]).sum()))
    return flops + q_upper_nnz


def ldlt_test(n: int) -> int:
    """LDL^T pivots of an n x n symmetric matrix (the covariance floor's test): with t_k = L_jk d_k,
    d_j = a_jj - L_j . t (j products, j sums), L_ij = (a_ij - L_i . t) / d_j."""
    flops = 0
    for j in range(n):
        flops += j                      # t_k = L_jk d_k
        flops += 2 * j                  # d_j = a_jj - sum L_jk t_k
        flops += (n - 1 - j) * (2 * j + 1)  # L_ij = (a_ij - dot) / d_j (the 1/d_j product)
        flops += 1                      # 1 / d_j
    return flops


def scalar_row(n: int, k: int, unit_h: bool = False) -> Count:
    """One scalar measurement row with k nonzeros in an n-state filter, Joseph form for any gain:
    a = P h, s = h.a + r, k = a / s, dx += k e, b = a - s k, P+ = P - a k^T - k b^T (upper)."""
    c = Count("row")
    c.add("a = P h (k-sparse h)", 0 if unit_h else n * dot(k))
    c.add("s = h.a + r", (1 if unit_h else dot(k)) + (0 if unit_h else 1))
    c.add("e = y - h.dx (sequential rows)", dot(k, k if unit_h else 0) + 1)
    c.add("gain k = a / s", 1 + n)
    c.add("dx += k e", 2 * n)
    c.add("nis += e^2 / s", 3)
    c.add("b = a - s k", 2 * n)
    c.add("P+ = P - a k^T - k b^T, upper triangle", 4 * n * (n + 1) // 2)
    return c


def joint_update(n: int, h_nz: np.ndarray, h_one: np.ndarray, r_full: bool) -> Count:
    """An M-row update with a full R (joint, as GpsInsFilter's aids): A = P H^T, S = H A + R,
    Cholesky of S, K = A S^-1, dx = K y, Joseph P+ = P + K W^T + W K^T with W = K S / 2 - A
    (equal to the Joseph form (I - KH) P (I - KH)^T + K R K^T for any K), upper triangle."""
    m = h_nz.shape[0]
    c = Count("joint")
    # A = P H^T: columns of P where H is a unit row are free.
    a = 0
    for r in range(m):
        k = int(h_nz[r].sum())
        ones = int((h_nz[r] & h_one[r]).sum())
        a += 0 if (k == 1 and ones == 1) else n * dot(k, ones)
    c.add("A = P H^T", a)
    # S_ij = H_i . A_j over H_i's nonzeros (a unit row of H: an entry of A, free), + R.
    c.add("S = H A + R (upper)", sum(dot(int(h_nz[i].sum()), int((h_nz[i] & h_one[i]).sum()))
                                     for i in range(m) for j in range(i, m)) + (m * (m + 1) // 2 if r_full else m))
    c.add("Cholesky of S (M x M)", sum(2 * j + (m - 1 - j) * (2 * j + 1) + 1 for j in range(m)) + m)  # with m sqrt
    c.add("K = A S^-1 (two triangular solves per row)", n * 2 * m * m)
    c.add("innovation y, dx = K y", n * dot(m))
    c.add("nis = |L^-1 y|^2", m * m + dot(m))
    c.add("W = K S / 2 - A", n * m * dot(m) + n * m + n * m)
    c.add("P+ = P + K W^T + W K^T, upper triangle", (n * (n + 1) // 2) * (4 * m))
    return c


def block(nz: np.ndarray, r0: int, c0: int, pattern: np.ndarray) -> None:
    nz[r0:r0 + pattern.shape[0], c0:c0 + pattern.shape[1]] |= pattern


DENSE3 = np.ones((3, 3), dtype=bool)
DIAG3 = np.eye(3, dtype=bool)
SKEW3 = ~np.eye(3, dtype=bool)


# --------------------------------------------------------------------------------------------
# The robustness parts (attitude/parts/*.hpp), default parameters, per step
# --------------------------------------------------------------------------------------------


def parts_rest() -> Count:
    c = Count("rest")
    c.add("predict: gyro low-pass", LOWPASS3)
    c.add("update: acc low-pass", LOWPASS3)
    c.add("update: three |difference| tests", 3 * (3 + NORM3))
    c.add("update: rest time", 1)
    return c


def parts_acc(rotation_from_rate: bool) -> Count:
    """The accelerometer part: low-pass in the gyro-carried frame, norm test, adaptive noise."""
    c = Count("acc part")
    if rotation_from_rate:
        c.add("predict: dq from the rate", 3 + ROTVEC_TO_QUAT, libm=ROTVEC_TO_QUAT_LIBM)
    c.add("predict: q_i dq, normalized", QMUL + QNORMALIZE)
    c.add("screen: rotate acc into the carried frame", ROTATE)
    c.add("screen: low-pass", LOWPASS3)
    c.add("screen: rotate back", ROTATE)
    c.add("screen: |acc| - g, sigma_add", NORM3 + 1 + 2)
    return c


def parts_mag() -> Count:
    """The magnetometer part: reference dip, norm and dip tests, the reference's low-pass."""
    c = Count("mag part")
    c.add("screen: field in the nav frame", ROTATE)
    c.add("screen: norm test |m| / ref - 1", 2)
    # cos and sin of d - d_ref from the unit vectors: sqrt(1 - z^2), two 2-term dots; cos(tol) is a
    # constant of the parameters (the code evaluates its polynomial at every sample: 11 more)
    c.add("screen: dip test cos(d - d_ref) < cos(tol)", 3 + 6 + 1)
    c.add("screen: settle time", 1)
    c.add("finish: field after the update, cos and sin of d - d_ref", ROTATE + 9)
    c.add("finish: dip low-pass: gain x atan2, cos_sinc, turn the reference, normalize",
          2 + 1 + 1 + COS_SINC + 1 + 6 + 7, libm=1)
    c.add("finish: norm low-pass", LOWPASS1)
    return c


# --------------------------------------------------------------------------------------------
# Attitude filters
# --------------------------------------------------------------------------------------------


def eskf_reset(n: int = 6) -> Count:
    """Injection of dtheta: q <- q exp(dtheta), b += db, and the covariance reset
    P_aa <- G P_aa G^T, P_ab <- G P_ab with G = I - [dtheta/2 x] (unit diagonal, skew)."""
    c = Count("inject")
    c.add("q exp(dtheta), normalized", ROTVEC_TO_QUAT + QMUL + QNORMALIZE, libm=ROTVEC_TO_QUAT_LIBM)
    c.add("bias += db", 3)
    c.add("dtheta / 2", 3)
    g_nz = np.zeros((n, n), dtype=bool)
    g_one = np.zeros((n, n), dtype=bool)
    block(g_nz, 0, 0, DENSE3)
    block(g_one, 0, 0, DIAG3)
    for i in range(3, n):
        g_nz[i, i] = g_one[i, i] = True
    c.add("G P G^T (G = I - skew)", covariance_predict(g_nz, g_one, 0))
    return c


def quaternion_eskf() -> Count:
    """QuaternionEKF (C++ QuaternionEKF, 6 error states), predict + acc + mag (heading)."""
    n = 6
    c = Count("QuaternionEKF (6 error states)")
    # --- predict
    c.add("predict: w = gyr - b, w dt", 6)
    c.add("predict: dq = exp(w dt)", ROTVEC_TO_QUAT, libm=ROTVEC_TO_QUAT_LIBM)
    c.add("predict: q dq, normalized", QMUL + QNORMALIZE)
    c.add("predict: F = C(dq)^T", QUAT_TO_ROTMAT)
    phi_nz = np.zeros((n, n), dtype=bool)
    phi_one = np.zeros((n, n), dtype=bool)
    block(phi_nz, 0, 0, DENSE3)     # F
    block(phi_nz, 0, 3, DIAG3)      # -dt I
    block(phi_nz, 3, 3, DIAG3)      # I
    block(phi_one, 3, 3, DIAG3)
    c.add("predict: Q densities dt sigma^2 (2)", 4)
    c.add("predict: P = Phi P Phi^T + Q, Phi = [F -dt I; 0 I]", covariance_predict(phi_nz, phi_one, 6))
    c.add("predict: floor test, LDL^T of P - floor I", n + ldlt_test(n))
    # --- accelerometer: 3 rows, H = [[h x] 0]: 2 nonzeros per row
    c.add("acc: unit vector", UNIT3)
    c.add("acc: h = C_bn [0 0 -1] (third row of C: 3 entries)", 9)
    c.add("acc: y = u - h, r = sigma^2", 3 + 2)
    c.include("acc row: ", scalar_row(n, 2), times=3)
    c.include("acc: ", eskf_reset(n))
    # --- magnetometer: heading row
    c.add("mag: unit vector", UNIT3)
    c.add("mag heading: C_nb, m_n = C m, |m_n,h|^2", QUAT_TO_ROTMAT + 15 + 3)
    c.add("mag heading: atan2", 0, libm=1)
    c.add("mag heading: dpsi/dm_n, J = -dpsi [m_n x]", 2 + 6)
    c.add("mag heading: v_tilt = C_0 J_0 + C_1 J_1", 9)
    c.add("mag heading: R = s^2/h2 + v^T A v", 2 + 15 + DOT3 + 1)
    c.add("mag heading: innovation, wrap", 2)
    r = scalar_row(n, 3)
    c.include("mag row: ", r)
    c.add("mag heading: gain projected on u", DOT3 + 3)
    c.include("mag: ", eskf_reset(n))
    # --- parts (default parameters)
    c.include("parts: ", parts_rest())
    c.include("parts: ", parts_acc(rotation_from_rate=False))
    c.include("parts: ", parts_mag())
    return c


def quaternion_ekf7_paper() -> Count:
    """QuaternionEKF(paper=True) = C++ QuaternionEKF with paper() parameters: 7 states
    [q, b], predict + 3 acc rows + 3 mag rows, normalization with its covariance projection,
    the covariance floor's test after the predict and each update (cov_floor stays on)."""
    n = 7
    c = Count("QuaternionEKF paper() (7 states)")
    c.add("predict: w = gyr - b", 3)
    c.add("predict: rv = w dt, dq = exp(rv)", 3 + ROTVEC_TO_QUAT, libm=ROTVEC_TO_QUAT_LIBM)
    c.add("predict: q+ = q dq; F = right(dq) (entries of dq, free)", QMUL)
    c.add("predict: d exp/d rv (4x3: 12 entries, about 3 flops each)", 36)
    c.add("predict: B = -dt left(q) J (4x4 by 4x3, dt folded into J)", mat_dense(4, 4, 3) + 12)
    phi_nz = np.zeros((n, n), dtype=bool)
    phi_one = np.zeros((n, n), dtype=bool)
    phi_nz[0:4, 0:4] = True          # F dense
    phi_nz[0:4, 4:7] = True          # B dense (4x3)
    block(phi_nz, 4, 4, DIAG3)
    block(phi_one, 4, 4, DIAG3)
    c.add("predict: Q_qq = c Xi Xi^T (4x4 upper, rank 3)", 1 + 3 + 10 * dot(3) + 12 + 10)
    c.add("predict: P = Phi P Phi^T + Q, Phi = [F B; 0 I]", covariance_predict(phi_nz, phi_one, 10 + 3))
    c.add("predict: normalize q", QNORMALIZE)
    c.add("floor test x3: T P T^T (6x6 upper from 7x7, T = [2 Xi^T 0; 0 I])", 3 * (
        pattern_product(np.ones((3, 4), dtype=bool), np.ones((4, 4), dtype=bool)) +   # Xi^T P_qq
        pattern_product(np.ones((3, 4), dtype=bool), np.ones((4, 3), dtype=bool), upper_only=True) +
        mat_dense(3, 4, 3) + 3 * 3 + 6))                                                # Xi^T P_qb, scaling
    c.add("floor test x3: LDL^T", 3 * (6 + ldlt_test(6)))
    for name, rows in (("acc", 3), ("mag", 3)):
        c.add(f"{name}: unit vector", UNIT3)
        c.add(f"{name}: h(q) and H (3x4: 12 entries, about 2 flops each)", 9 + 24)
        c.add(f"{name}: y = z - h, r", 3 + 2)
        c.include(f"{name} row: ", scalar_row(n, 4), times=rows)
        c.add(f"{name}: q += dq_q, b += dq_b", 7)
        # normalization: J = (I - qq^T)/|q| on the q rows: P_qq <- J P_qq J^T, P_qb <- J P_qb,
        # by its rank-one structure: u = P q (4 x 7 columns), then P - q u^T - u q^T + (q.u) q q^T.
        c.add(f"{name}: normalize q", QNORMALIZE)
        c.add(f"{name}: projection by the rank-one J", 7 * dot(4) + dot(4) + 10 * 6 + 12 * 3 + 10 + 12)
    return c


def euler_ekf() -> Count:
    """EulerEKF default: 6 states [roll, pitch, yaw, b], predict + acc (joint 3 rows) + mag (3
    rows), with the robustness parts; kalman_correct (joint rows) as the code, counted here as
    sequential scalar rows (R diagonal), the structure's minimum."""
    n = 6
    c = Count("EulerEKF")
    c.add("predict: sin/cos roll, cos/tan pitch", 0, libm=4)
    c.add("predict: E (7 nonzeros), w - b, e += dt E w", 6 + 3 + 7 + 3 + 3 + 3)
    c.add("predict: G = I + dt dE/de w (columns roll, pitch)", 6 * 3 + 4)
    phi_nz = np.zeros((n, n), dtype=bool)
    phi_one = np.zeros((n, n), dtype=bool)
    phi_nz[0:3, 0:2] = True          # G: columns roll, pitch
    phi_nz[0:3, 2] = [False, False, True]
    phi_one[2, 2] = True             # yaw column of G is e_3
    e_pat = np.array([[1, 1, 1], [0, 1, 1], [0, 1, 1]], dtype=bool)
    block(phi_nz, 0, 3, e_pat)       # B = -dt E
    block(phi_nz, 3, 3, DIAG3)
    block(phi_one, 3, 3, DIAG3)
    c.add("predict: B = -dt E", 7)
    c.add("predict: Q = c E E^T (upper) + diag", 1 + 6 * dot(3) + 6 + 3)
    c.add("predict: P = Phi P Phi^T + Q", covariance_predict(phi_nz, phi_one, 6 + 3))
    c.add("predict: floor test LDL^T", n + ldlt_test(n))
    c.add("acc: unit vector; h = C_bn(e) [0 0 -1] and its 5 nonzero partials", UNIT3 + 4 + 6)
    c.include("acc row: ", scalar_row(n, 2), times=3)   # rows depend on roll, pitch
    c.add("acc: floor test LDL^T", n + ldlt_test(n))
    c.add("mag: unit vector; sin/cos yaw; h = C_bn(e) m_ref and dh/de (3x3)", UNIT3 + 20 + 27, libm=2)
    c.include("mag row: ", scalar_row(n, 3), times=3)
    c.add("mag: floor test LDL^T", n + ldlt_test(n))
    c.add("angles wrapped, state += dx (2 updates)", 2 * 6)
    c.include("parts: ", parts_rest())
    c.include("parts: ", parts_acc(rotation_from_rate=True))
    c.include("parts: ", parts_mag())
    return c


def marg_filter(iterations: float) -> Count:
    """MargFilter default: gyro integration; accelerometer + magnetometer by Gauss-Newton (K = 2
    vector pairs, 6 residuals, 4 unknowns), `iterations` per update (measured by the bench)."""
    c = Count("MargFilter")
    c.add("predict: w = gyr - b, w dt, exp, q dq, normalized", 6 + ROTVEC_TO_QUAT + QMUL + QNORMALIZE,
          libm=ROTVEC_TO_QUAT_LIBM)
    c.add("predict: omega_dot low-pass ((w - w_prev)/dt)", 3 + 3 + LOWPASS3, libm=1)
    c.add("predict: timers", 2)
    c.add("update: unit vectors acc, mag", 2 * UNIT3)
    it = Count("gn")
    # marg_h: (q0^2 - |v|^2) r + 2 (v.r) v - 2 q0 v x r: 3 + 1 + ... per vector pair
    it.add("residual eps = meas - h(q) (2 vectors)", 2 * (3 + DOT3 + 1 + 3 + DOT3 + 1 + 3 + CROSS + 1 + 3 + 6 + 3))
    it.add("Jacobian X (2 blocks 3x4)", 2 * (3 + 3 + 3 + 3 + 9 + 3 + 9 + 9))
    it.add("X^T X (4x4 upper, 6 terms)", 10 * dot(6))
    it.add("X^T eps", 4 * dot(6))
    it.add("Cholesky 4x4 and the two solves", sum(2 * j + (4 - 1 - j) * (2 * j + 1) + 1 for j in range(4)) + 4
           + 2 * 16)
    it.add("q += dq, |dq|", 4 + dot(4) + 1)
    c.include("gauss-newton: ", it, times=iterations)
    c.add("residuals before and after (2 x 2 vectors)", 2 * (2 * (3 + DOT3 + 1 + 3 + DOT3 + 1 + 3 + CROSS + 1 + 3 + 6
                                                                   + 3) + dot(6) + 1))
    c.add("normalize q_gn", QNORMALIZE)
    c.add("alpha = 1 - exp(-gain T), q_pred + alpha (q_gn - q_pred), normalize", 3 + 12 + QNORMALIZE, libm=1)
    c.add("bias: conj(q_pred) q_gn, 3 products", QMUL + 2 + 3 + 3)
    c.add("correction rotvec", QMUL + QUAT_TO_ROTVEC, libm=1)
    c.include("parts: ", parts_rest())
    c.include("parts: ", parts_acc(rotation_from_rate=True))
    c.include("parts: ", parts_mag())
    return c


# --------------------------------------------------------------------------------------------
# Navigation filters
# --------------------------------------------------------------------------------------------


def nav13_F_pattern():
    """F of NavFilter13 (13 x 13, x = [v, q, b_a, b_g]): I + dt (...)."""
    n = 13
    nz = np.eye(n, dtype=bool)
    one = np.eye(n, dtype=bool)
    nz[0:3, 0:3] = SKEW3 | DIAG3           # I - dt [alpha x]: diagonal stays 1
    nz[0:3, 3:7] = True                    # dt dCa/dq (3x4)
    nz[0:3, 7:10] = True                   # -dt C (3x3)
    nz[3:7, 3:7] = True                    # I + dt/2 (Omega(w) - L(w_in)): diagonal stays 1
    nz[3:7, 10:13] = True                  # -dt/2 Xi(q) (4x3)
    return nz, one


def nav13_common(c: Count) -> None:
    c.add("rotation correction f + dt/2 (w - b_g) x (f - b_a)", 3 + 3 + CROSS + 1 + 6)
    c.add("earth terms: radii, gravity, w_ie, w_en (sin/cos lat)", 40, libm=2)
    c.add("geodetic rates at the mid velocity, position", 6 + 12)


def nav13_ekf(second_order: bool) -> Count:
    c = Count("NavFilter13 " + ("second order" if second_order else "ekf"))
    nav13_common(c)
    c.add("f_d: C(q) a - alpha x v + g; 1/2 (Xi w - L(w_in) q); x + dt f", QUAT_TO_ROTMAT + 15 + CROSS + 6
          + 3 + 16 + 16 + 4 + 13)
    c.add("F blocks: dCa/dq (3x4), dt C, dt/2 (Omega - L), dt/2 Xi", 12 * 3 + 9 + 16 + 12)
    nz, one = nav13_F_pattern()
    c.add("P = F P F^T (structured), + Q (blocks)", covariance_predict(nz, one, 6 + 10 + 6))
    c.add("Q: C C^T (identity for a rotation: free), Xi Xi^T (4x4 upper)", 10 * dot(3) + 12)
    if second_order:
        c.add("second-order term: quad_rotmat(P_qq) a, sum_k J(q, e_k) P_q,ba_k, Xi sum",
              9 * dot(10) + 3 * dot(3) + 3 * (12 * 2 + 3 * dot(4)) + 3 * 12 + 7 + 7)
    c.add("normalize q and project P by the rank-one J", QNORMALIZE + 13 * dot(4) + dot(4) + 4 * 13 * 3 + 10 * 2)
    return c


def nav13_ukf() -> Count:
    n, L = 12, 25
    c = Count("NavFilter13 ukf")
    nav13_common(c)
    c.add("T P T^T (12x12 error covariance from 13x13; q rows through 2 Xi^T)",
          pattern_product(np.ones((3, 4), dtype=bool), np.ones((4, 13), dtype=bool)) +
          pattern_product(np.ones((3, 4), dtype=bool), np.ones((4, 3), dtype=bool), upper_only=True) + 12 * 3)
    c.add("Cholesky 12x12 (sigma offsets), gamma L", sum(2 * j + (n - 1 - j) * (2 * j + 1) + 1 for j in range(n))
          + n * (n + 1) // 2)
    retract = 3 + ROTVEC_TO_QUAT + QMUL + 6
    f_d = QUAT_TO_ROTMAT + 15 + CROSS + 6 + 3 + 16 + 16 + 4 + 13
    c.add("24 sigma points: retract, f_d, normalize q (the centre: f_d only)", 24 * (retract + QNORMALIZE) + 25 * f_d
          + 25 * QNORMALIZE, libm=24 * ROTVEC_TO_QUAT_LIBM)
    c.add("mean: weighted sums (9 Euclidean + 4 quaternion over 25 points), normalize", 13 * 2 * L + 25 + QNORMALIZE)
    c.add("deviations: 9 differences, rotvec of conj(qm) q_i (25 points)", L * (9 + QMUL + QUAT_TO_ROTVEC), libm=L)
    c.add("mean rotation vector, q correction, re-centred deviations", 3 * 2 * L + ROTVEC_TO_QUAT + QMUL + QNORMALIZE
          + 3 * L, libm=ROTVEC_TO_QUAT_LIBM)
    c.add("sigma covariance sum W_i D_i D_i^T (12x12 upper, 25 points)", (n * (n + 1) // 2) * dot(L) + n * L)
    c.add("T Q T^T (blocks: diagonal, Xi^T Xi Xi^T Xi = I/4 scaled)", 12 + 10)
    c.add("back to 13x13: T' Pe T'^T (q rows through Xi/2)",
          pattern_product(np.ones((4, 3), dtype=bool), np.ones((3, 12), dtype=bool)) +
          pattern_product(np.ones((4, 3), dtype=bool), np.ones((3, 4), dtype=bool), upper_only=True))
    return c


def gpsins_F_pattern():
    """F of GpsInsFilter (16 x 16: dp, dv, psi, b_a, b_g, baro offset), earth_rotation on,
    bias time constants 0 (random walks: zero rows), model.hpp gpsins_F."""
    n = 16
    nz = np.zeros((n, n), dtype=bool)
    fpp = np.array([[1, 0, 1], [1, 1, 1], [0, 0, 0]], dtype=bool)   # eq. (9)
    block(nz, 0, 0, fpp)
    block(nz, 0, 3, DIAG3)                                          # identity
    fvp = np.array([[1, 0, 1], [1, 0, 1], [1, 0, 1]], dtype=bool)   # gravity, Coriolis by position
    block(nz, 3, 0, fvp)
    block(nz, 3, 3, DENSE3)                                         # Fvv
    block(nz, 3, 6, SKEW3)                                          # -[f_n x]
    block(nz, 3, 9, DENSE3)                                         # -C
    fpsi_p = np.array([[1, 0, 1], [0, 0, 1], [1, 0, 1]], dtype=bool)
    block(nz, 6, 0, fpsi_p)
    fpsi_v = np.array([[0, 1, 0], [1, 0, 0], [0, 1, 0]], dtype=bool)
    block(nz, 6, 3, fpsi_v)
    block(nz, 6, 6, SKEW3)                                          # -[w_in x]
    block(nz, 6, 12, DENSE3)                                        # -C
    return nz


def gpsins_time_update() -> Count:
    n = 16
    c = Count("GpsInsFilter time update")
    c.add("inputs: bias-corrected w, f", 6)
    c.add("rest detector (low-passes with one weight, norms)", 2 * LOWPASS3 - 2 + 2 * (3 + NORM3) + NORM3 + 4, libm=1)
    c.add("speed test: sigma_v, |v|", 3 + 1 + NORM3 + 3)
    c.add("gravity at (lat, h)", 12, libm=1)
    # strapdown_step: coning/sculling, rotate dv, two velocity evaluations, position, attitude
    c.add("strapdown: increments, coning and sculling terms", 6 + CROSS + 3 + CROSS + 3 + 3 + 3 + 3 * CROSS + 12)
    c.add("strapdown: dv_n = rotate(q, dv)", ROTATE)
    c.add("strapdown: earth terms x2 (radii, gravity, w_ie, w_en)", 2 * 45, libm=2 * 3)
    c.add("strapdown: velocity x2 (zeta x dv, Coriolis, gravity)", 2 * (3 + CROSS + 3 + 3 + 3 + CROSS + 3 + 3 + 3 + 6))
    c.add("strapdown: mid point, radii, lat/lon/h", 6 + 4 + 4 + 12 + 10, libm=2)
    c.add("strapdown: q+ = exp(-zeta) q exp(phi), normalized", 2 * ROTVEC_TO_QUAT + 2 * QMUL + QNORMALIZE,
          libm=2 * ROTVEC_TO_QUAT_LIBM)
    # Phi = I + F dt + (F dt)^2 / 2
    F = gpsins_F_pattern()
    c.add("F: earth quantities (sin, cos, tan of lat, radii)", 30, libm=3)
    c.add("F: C, f_n = C f, entries of the nonzero blocks", QUAT_TO_ROTMAT + 15 + 12 + 10 + 20 + 12)
    c.add("F dt (nonzeros)", int(F.sum()))
    c.add("(F dt)^2 (structured)", pattern_product(F, F))
    F2 = (F.astype(int) @ F.astype(int)) > 0
    phi_nz = np.eye(n, dtype=bool) | F | F2
    c.add("Phi = I + F dt + (F dt)^2 / 2 (nonzeros of the square, diagonal)", int(F2.sum()) * 2 + int((F | F2)[np.eye(n, dtype=bool)].sum()))
    phi_one = np.eye(n, dtype=bool) & ~(F | F2)
    c.add("P = Phi P Phi^T (structured, upper)", covariance_predict(phi_nz, phi_one, 0))
    # Qd = dt/2 (Phi Qc Phi^T + Qc), Qc diagonal on states 3..14
    qc = np.zeros(n, dtype=bool)
    qc[3:15] = True
    pq = phi_nz & qc[None, :]
    c.add("Qc, dt/2 Qc", 4 * 2 + 12)
    c.add("Phi Qc (nonzeros in the 12 noise columns)", int(pq.sum()))
    qd = 0
    for i in range(n):
        for j in range(i, n):
            k = int((pq[i] & phi_nz[j]).sum())
            qd += dot(k)
    c.add("Phi Qc Phi^T (upper), dt/2, + dt/2 Qc, + to P", qd + n * (n + 1) // 2 + 12 + n * (n + 1) // 2)
    return c


def gpsins_gnss_epoch() -> Count:
    """A GNSS epoch: position (3 rows) then velocity (3 rows), joint updates with the full R,
    default lever arm 0 and age 0 (the H blocks that depend on them are zero)."""
    n = 16
    c = Count("GpsInsFilter GNSS epoch")
    for name, col in (("position", 0), ("velocity", 3)):
        h_nz = np.zeros((3, n), dtype=bool)
        h_one = np.zeros((3, n), dtype=bool)
        block(h_nz, 0, col, DIAG3)
        block(h_one, 0, col, DIAG3)
        if name == "position":
            c.add("position: geodetic difference (radii, cos lat)", 20, libm=2)
            c.add("position: R = diag + sigma_t^2 v v^T", 3 + 1 + 6 + 6)
        else:
            c.add("velocity: y = v + C (w x l) - a age - v_fix (lever 0: sums)", QUAT_TO_ROTMAT + 15 + CROSS + 9)
            c.add("velocity: a_n = C f, R = diag + sigma_t^2 a a^T", 15 + 3 + 1 + 6 + 6)
        c.include(f"{name}: ", joint_update(n, h_nz, h_one, r_full=True))
        c.add(f"{name}: inject (geodetic add, v, q exp(-psi), biases)", 15 + 3 + ROTVEC_TO_QUAT + QMUL + QNORMALIZE
              + 7, libm=ROTVEC_TO_QUAT_LIBM + 1)
        c.add(f"{name}: adaptation of q_scale (log of nis / 3)", 4, libm=1)
    return c


CASES = {
    # key: (label of the bench case, builder)
    "QuaternionEKF [error state]": quaternion_eskf,
    "QuaternionEKFPaper [ekf, paper() parameters]": quaternion_ekf7_paper,
    "EulerEKF [ekf]": euler_ekf,
    "MargFilter [gauss-newton]": None,  # needs the iterations, see main()
    "NavFilter13 [time update: ekf]": lambda: nav13_ekf(False),
    "NavFilter13 [time update: second order]": lambda: nav13_ekf(True),
    "NavFilter13 [time update: ukf]": nav13_ukf,
    "GpsInsFilter [time update]": gpsins_time_update,
    "GpsInsFilter [GNSS epoch: pos 3 + vel 3 rows]": gpsins_gnss_epoch,
    # the two bench cases: the time update with an epoch every 200th sample, and with one at every sample
    "GpsInsFilter [time update, gnss 1/200]": lambda: combined("GpsInsFilter tu + epoch/200", 1 / 200),
    "GpsInsFilter [time update + gnss pos+vel]": lambda: combined("GpsInsFilter tu + epoch", 1),
}


def combined(name: str, epochs_per_step: float) -> Count:
    c = Count(name)
    c.include("", gpsins_time_update())
    c.include("epoch: ", gpsins_gnss_epoch(), times=epochs_per_step)
    return c


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--terms", action="store_true", help="print every term")
    ap.add_argument("--json", action="store_true", help="print {case: {flops, libm}} as JSON")
    ap.add_argument("--marg-iterations", type=float, default=3.0,
                    help="MargFilter's Gauss-Newton iterations per update (quatnav_bench_filters --iterations; default 3: gn_max_iter, as measured)")
    a = ap.parse_args(argv)
    if not a.marg_iterations > 0:
        print("flops_needed.py: --marg-iterations must be > 0", file=sys.stderr)
        return 2
    out = {}
    counts = []
    for key, f in CASES.items():
        c = marg_filter(a.marg_iterations) if f is None else f()
        counts.append((key, c))
        out[key] = {"flops": c.flops, "libm": c.libm}
    if a.json:
        print(json.dumps(out, indent=1))
        return 0
    for key, c in counts:
        if a.terms:
            print(f"\n{key}")
            for what, f, l in c.terms:
                print(f"  {f:7d} {'(' + str(l) + ' libm)' if l else '':10s} {what}")
    print(f"\n{'case':48s} {'flops needed':>12s} {'libm calls':>10s}")
    for key, c in counts:
        print(f"{key:48s} {c.flops:12d} {c.libm:10d}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
