// quatnav: every public header.
//
//   core/      math and machinery that knows no filter (includes nothing outside core/)
//   attitude/  QuaternionEKF (and its paper form), EulerEKF, MargFilter, their shared initialization, batch loop and
//              smoothers, and parts/, the robustness they compose (rest detection, accelerometer,
//              magnetometer, clipped gyro)
//   nav/       strapdown, NavFilter13, GpsInsFilter, their batch loops and smoothers
// attitude/ and nav/ include core/ only, never each other (tests/python/test_layout.py).
#pragma once

#include "core/types.hpp"
#include "core/fields.hpp"
#include "core/checks.hpp"
#include "core/quaternion.hpp"
#include "core/quat_block.hpp"
#include "core/commit.hpp"
#include "core/kalman.hpp"
#include "core/covariance.hpp"
#include "core/unscented.hpp"
#include "core/earth.hpp"
#include "core/smoother.hpp"

#include "attitude/attitude.hpp"
#include "attitude/parts/rest.hpp"
#include "attitude/parts/acc_filter.hpp"
#include "attitude/parts/mag_disturbance.hpp"
#include "attitude/parts/gyro_clip.hpp"
#include "attitude/quaternion_ekf_params.hpp"
#include "attitude/quaternion_ekf_paper.hpp"
#include "attitude/quaternion_ekf.hpp"
#include "attitude/euler_ekf.hpp"
#include "attitude/marg_filter.hpp"
#include "attitude/batch.hpp"
#include "attitude/smoother.hpp"

#include "nav/strapdown.hpp"
#include "nav/nav_filter13.hpp"
#include "nav/gps_ins.hpp"
#include "nav/gps_ins/smoother.hpp"
#include "nav/nav13_smoother.hpp"
