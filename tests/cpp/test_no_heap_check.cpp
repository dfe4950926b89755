// The no-heap check of every C++ test (tests/cpp/support/no_heap.hpp and no_heap.cpp) fires in
// this very build: inside Eigen::internal::set_is_malloc_allowed(false) an Eigen allocation and a
// new (a std::vector) abort, with NDEBUG or without, with the sanitizers or without; fixed-size
// Eigen work does not; Eigen's other assertions are as Eigen makes them (off with NDEBUG).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

namespace {

// Where the allocations go, so that the compiler cannot drop them.
void* volatile sink = nullptr;

void eigen_dynamic_matrix_in_scope() {
  Eigen::internal::set_is_malloc_allowed(false);
  Eigen::MatrixXd m(4, 4);
  sink = m.data();
  Eigen::internal::set_is_malloc_allowed(true);
}

void vector_in_scope() {
  Eigen::internal::set_is_malloc_allowed(false);
  std::vector<double> v(16);
  sink = v.data();
  Eigen::internal::set_is_malloc_allowed(true);
}

void new_in_scope() {
  Eigen::internal::set_is_malloc_allowed(false);
  double* p = new double[8];
  sink = p;
  delete[] p;
  Eigen::internal::set_is_malloc_allowed(true);
}

}  // namespace

TEST(NoHeapCheck, EigenAllocationInsideAScopeAborts) {
  EXPECT_DEATH(eigen_dynamic_matrix_in_scope(), "inside a no-heap scope");
}

TEST(NoHeapCheck, StdContainerInsideAScopeAborts) { EXPECT_DEATH(vector_in_scope(), "inside a no-heap scope"); }

TEST(NoHeapCheck, NewInsideAScopeAborts) { EXPECT_DEATH(new_in_scope(), "inside a no-heap scope"); }

TEST(NoHeapCheck, FixedSizeWorkInsideAScopeAndTheHeapAfterIt) {
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 3; ++k) a = (a * a.transpose() + Eigen::Matrix<double, 6, 6>::Identity()).eval();
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_GT(a(0, 0), 1.0);
  Eigen::MatrixXd m(4, 4);  // allowed again
  std::vector<double> v(16);
  sink = m.data();
  sink = v.data();
  EXPECT_EQ(m.rows(), 4);
}

// Resizing a fixed-size matrix to another size is refused by an eigen_assert (and does nothing
// otherwise): that assertion aborts exactly when Eigen's assertions are on.
TEST(NoHeapCheck, EigenOtherAssertionsFollowNDEBUG) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
#ifdef NDEBUG
  m.resize(4, 4);
  EXPECT_EQ(m.rows(), 3);
#else
  EXPECT_DEATH(m.resize(4, 4), "resiz");
#endif
}
