// test_robustness: MargFilter (robustness.hpp).
#include "robustness.hpp"

TEST(FaultSequences, MargFilter) {
  random_fault_sequences<MargFilter<double>>(5, 300);
  random_fault_sequences<MargFilter<float>>(6, 300);
}
