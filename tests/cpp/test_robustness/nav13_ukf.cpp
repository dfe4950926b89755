// test_robustness: the NavFilter13 helpers of robustness.hpp for TimeUpdate::Ukf, float64 and
// float32 (their tests are in nav13.cpp).
#include "robustness.hpp"

QUATNAV_ROBUSTNESS_NAV13(, TimeUpdate::Ukf)
