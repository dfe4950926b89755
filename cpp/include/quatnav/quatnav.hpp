// quatnav: every public header.
#pragma once

#include "types.hpp"
#include "quaternion.hpp"
#include "kalman.hpp"
#include "covariance.hpp"
#include "attitude.hpp"
#include "quaternion_ekf.hpp"
#include "euler_ekf.hpp"
#include "marg_filter.hpp"
#include "batch.hpp"
#include "earth.hpp"
#include "strapdown.hpp"
#include "unscented.hpp"
#include "nav_filter13.hpp"
