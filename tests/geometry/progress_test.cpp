#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/geometry/progress.h"

using namespace relume;

// A job's Cancel is set on its root Progress; a stage that waits on a child process (COLMAP)
// asks its own sub-stage whether to stop, two levels down.
TEST(Progress, CancellingTheRootReachesEverySubStage) {
  std::vector<double> seen;
  Progress root([&](double f, const std::string&) { seen.push_back(f); });
  Progress stage(root, 0.0, 0.5);
  Progress step(stage, 0.5, 1.0);
  EXPECT_FALSE(step.cancelled());
  step.report(0.5, "half");
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_DOUBLE_EQ(seen[0], 0.375);  // 0.5 of [0.5, 1] of [0, 0.5]
  root.cancel();
  EXPECT_TRUE(stage.cancelled());
  EXPECT_TRUE(step.cancelled());
  EXPECT_THROW(step.poll(), Cancelled);
  EXPECT_THROW(step.report(0.9, "more"), Cancelled);
}

TEST(Progress, CancellingASubStageLeavesItsParentRunning) {
  Progress root;
  Progress stage(root, 0.0, 1.0);
  stage.cancel();
  EXPECT_TRUE(stage.cancelled());
  EXPECT_FALSE(root.cancelled());
  EXPECT_NO_THROW(root.poll());
}
