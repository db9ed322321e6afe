// The one round schedule: batch runs spend exactly their budget over the rounds, open-ended
// runs a fixed amount per round up to their cap.
#include "methods/schedule.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(RoundSchedule, BatchSpendsExactlyTheBudgetInEqualShares) {
  const RoundSchedule s(RunShape::batch(16), 100, 4, 8);
  EXPECT_EQ(s.initialBudget(), 400u);
  EXPECT_EQ(s.totalBudget(), 1600u);
  uint64_t spent = s.initialBudget();
  int round = 0;
  while (!s.finished(spent)) {
    const uint64_t b = s.roundBudget(spent, round++);
    EXPECT_GT(b, 0u);
    EXPECT_LE(b, 150u);  // ceil(1200 / 8)
    spent += b;
  }
  EXPECT_EQ(spent, 1600u);
  EXPECT_EQ(round, 8);
  // Rounds past the last spend what is left at once.
  EXPECT_EQ(s.roundBudget(1500, 20), 100u);
}

TEST(RoundSchedule, OpenEndedRunsAddRoundSppUpToTheCap) {
  const RoundSchedule open(RunShape::progressive(2), 10, 4, 8);
  EXPECT_EQ(open.roundBudget(40, 0), 20u);
  EXPECT_EQ(open.roundBudget(1000000, 500), 20u);
  EXPECT_FALSE(open.finished(1000000));
  const RoundSchedule capped(RunShape::progressive(3, 0, 10), 10, 4, 8);
  EXPECT_EQ(capped.roundBudget(40, 0), 30u);
  EXPECT_EQ(capped.roundBudget(90, 2), 10u);
  EXPECT_FALSE(capped.finished(90));
  EXPECT_TRUE(capped.finished(100));
}

// The adaptive methods' rounds: open-ended, at least an eighth of what is spent, still
// capped; a batch run is unchanged.
TEST(RoundSchedule, GrowingRoundsAddAnEighthOfWhatIsSpent) {
  const RoundSchedule open(RunShape::progressive(2), 10, 4, 8);
  EXPECT_EQ(open.growingRoundBudget(40, 0), 20u);      // roundSpp x pixels is more
  EXPECT_EQ(open.growingRoundBudget(8000, 9), 1000u);  // an eighth of 8000
  const RoundSchedule capped(RunShape::progressive(2, 0, 100), 10, 4, 8);
  EXPECT_EQ(capped.growingRoundBudget(960, 9), 40u);  // 1000 - 960 left
  const RoundSchedule batch(RunShape::batch(16), 10, 4, 8);
  EXPECT_EQ(batch.growingRoundBudget(800, 3), batch.roundBudget(800, 3));
}

}  // namespace
}  // namespace penumbra
