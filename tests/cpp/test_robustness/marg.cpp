// test_robustness: MargFilter (robustness.hpp).
#include "robustness.hpp"

TEST(FaultSequences, MargFilter) {
  random_fault_sequences<MargFilter<double>>(5, 300);
  random_fault_sequences<MargFilter<float>>(6, 300);
}

/// An update that fails after the parts took the sample (NumericalFailure, SolveFailed) left the
/// rest detector's and the accelerometer and magnetometer parts' states, and the bias the rest
/// detector set, changed (replay: seed 5, inputs 8890 and 27701, float64; found by a replay ten
/// times the default length). Every field is put back now.
TEST(MargContract, FailedUpdateKeepsTheParts) {
  replay_input<MargFilter<double>>(5, 8890);
  replay_input<MargFilter<double>>(5, 27701);
}
