// The progress ETA: the mean of the iterations' own times times the iterations left.

#include <gtest/gtest.h>

#include "rbaa/opt/iteration_eta.hpp"

namespace rbaa {
namespace {

ProgressRow row(int iteration, double seconds) {
  ProgressRow r;
  r.iteration = iteration;
  r.seconds = seconds;
  return r;
}

// Whatever ran before the loop (the best uniform start's candidate runs) is no iteration's time:
// after the first iteration the estimate is its time times the iterations left.
TEST(IterationEta, IsTheMeanIterationTimeTimesTheIterationsLeft) {
  IterationEta eta;
  EXPECT_EQ(eta.seconds_left(), 0.0);
  eta.add(row(0, 80.0), 50);
  EXPECT_DOUBLE_EQ(eta.seconds_left(), 80.0 * 49);
  eta.add(row(1, 90.0), 50);
  EXPECT_DOUBLE_EQ(eta.seconds_left(), 85.0 * 48);
  eta.add(row(49, 85.0), 50);
  EXPECT_EQ(eta.seconds_left(), 0.0);
}

// A resumed run counts from its first iteration in this run; the polish loop after the main loop
// starts its own mean.
TEST(IterationEta, AResumedRunAndTheNextLoopCountTheirOwnIterations) {
  IterationEta eta;
  eta.add(row(20, 60.0), 50);
  EXPECT_DOUBLE_EQ(eta.seconds_left(), 60.0 * 29);
  eta.add(row(49, 80.0), 50);
  EXPECT_EQ(eta.seconds_left(), 0.0);
  eta.add(row(0, 10.0), 10);
  EXPECT_DOUBLE_EQ(eta.seconds_left(), 10.0 * 9);
  eta.add(row(1, 20.0), 10);
  EXPECT_DOUBLE_EQ(eta.seconds_left(), 15.0 * 8);
}

}  // namespace
}  // namespace rbaa
