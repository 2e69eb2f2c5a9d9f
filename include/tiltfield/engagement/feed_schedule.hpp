// tiltfield engagement: feed scheduling from the verifier's material removal (what Vericut OptiPath sells).
// In: a verification report at the programmed feeds. Out: a feed for every block, so that no cutting
// block's material removal rate exceeds a limit. Units: mm^3/min, mm/min, 1/min (G93).
//
// Per feed block with removed volume V (mm^3) and programmed time t (min): the new time is
// max(t, V / max_mrr), so the feed never rises above the programmed one while cutting; it is capped by
// the minimum feed (a block that still exceeds the limit there is named in the warnings). Feed blocks
// that remove nothing (air moves) run at the air feed. Rapids keep their G0. The feed words follow the
// block's mode: mm/min under G94, 1/min (1 / block time) under G93. A block whose feed no F on its line
// sets (Block::fixed_feed: G33/G33.1, a subroutine file's block) keeps it, named in the warnings when it
// is above the limit.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "tiltfield/core/program.hpp"
#include "tiltfield/core/report.hpp"

namespace tf {

struct FeedScheduleOptions {
  double max_mrr = 0.0;          // mm^3/min, the limit; must be > 0
  double min_feed = 10.0;        // mm/min, the slowest feed the schedule writes
  double air_feed = 0.0;         // mm/min for feed blocks that cut nothing; 0: keep the programmed feed
  double air_volume_mm3 = 1e-4;  // blocks removing less than this are air moves
};

struct FeedSchedule {
  std::vector<double> feed;  // per program block: the new F (G94 mm/min or G93 1/min); rapids: 0
  int slowed = 0, sped_up = 0;
  std::vector<std::string> warnings;  // blocks above the limit even at the minimum feed
};

// Throws InputError naming `limit_option` (the command's name for max_mrr), "--min-feed" or "--air-feed"
// when an option is out of range (feeds: at most 1e6 mm/min); commands call it before their simulation.
void check_feed_schedule_options(const FeedScheduleOptions& options, const std::string& limit_option = "--max-mrr");

// The schedule for `program` from its verification `report` (one BlockResult per block, in order).
// Throws InputError ("--max-mrr", ...) for a limit that is not positive, and when the report does not
// cover every block (a verification stopped at a collision).
FeedSchedule schedule_feeds(const Program& program, const VerifyReport& report, const FeedScheduleOptions& options);

// The program's G-code text with the F word of every feed block replaced by the schedule's (inserted
// where the block had none, before a trailing comment); every other character is kept. Blocks sharing a
// line take the smallest of their feeds (G93, where one F times a spline's chords or an arc's turns
// together: the largest F that gives each of them at least its scheduled time).
std::string rewrite_feeds(std::string_view text, const Program& program, const FeedSchedule& schedule);

}  // namespace tf
