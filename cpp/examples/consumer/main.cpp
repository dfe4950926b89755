// Runs a QuaternionEKF for one second of a level, still sensor and prints the attitude.
#include <cstdio>
#include <quatnav/quatnav.hpp>

int main() {
  quatnav::QuaternionEKF<double> f;
  const Eigen::Vector3d acc(0.0, 0.0, -9.81), mag(0.4, 0.0, 0.9), gyr(0.0, 0.0, 0.0);
  if (f.initialize(acc, mag) != quatnav::Status::Ok) return 1;
  for (int k = 0; k < 100; ++k) {
    if (f.predict(gyr, 0.01) != quatnav::Status::Ok) return 1;
    if (!f.update_acc(acc).accepted() || !f.update_mag(mag).accepted()) return 1;
  }
  const Eigen::Vector3d rpy = quatnav::quat::to_euler(f.quat());
  std::printf("quatnav consumer: roll %.3f pitch %.3f yaw %.3f rad\n", rpy[0], rpy[1], rpy[2]);
  return rpy.norm() < 1e-6 ? 0 : 1;
}
