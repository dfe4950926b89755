// Random test matrices: standard-normal coefficients drawn from one generator and one
// distribution (so consecutive matrices continue one sequence), in storage order.
#pragma once

#include <random>

namespace quatnav_test {

struct Randn {
  explicit Randn(unsigned seed) : g(seed) {}
  double operator()() { return n(g); }
  /// A fixed-size matrix type M with independent N(0, 1) coefficients, column by column.
  template <class M> M matrix() {
    M m;
    for (int i = 0; i < m.size(); ++i) m.data()[i] = n(g);
    return m;
  }
  /// A A^T + ridge I for a random square A: a symmetric positive definite N x N matrix.
  template <class M> M spd(double ridge) {
    const M a = matrix<M>();
    return a * a.transpose() + ridge * M::Identity();
  }
  std::mt19937 g;
  std::normal_distribution<double> n;
};

}  // namespace quatnav_test
