// Feed scheduling from per-block removal, and the F-word rewrite of a G-code text.
#include "tiltfield/engagement/feed_schedule.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf {

void check_feed_schedule_options(const FeedScheduleOptions& o, const std::string& limit_option) {
  if (!(o.max_mrr > 0.0) || !std::isfinite(o.max_mrr))
    throw InputError("", 0, limit_option, "must be a positive number of mm3/min");
  if (!(o.min_feed > 0.0) || !std::isfinite(o.min_feed)) throw InputError("", 0, "--min-feed", "must be a positive number of mm/min");
}

FeedSchedule schedule_feeds(const Program& program, const VerifyReport& report, const FeedScheduleOptions& o) {
  check_feed_schedule_options(o);
  if (report.per_block.size() != program.blocks.size())
    throw InputError("", 0, "--max-mrr",
                     "the verification covered " + std::to_string(report.per_block.size()) + " of " +
                         std::to_string(program.blocks.size()) + " blocks; feeds are scheduled on a complete run");
  FeedSchedule s;
  s.feed.assign(program.blocks.size(), 0.0);
  for (size_t i = 0; i < program.blocks.size(); ++i) {
    const Block& b = program.blocks[i];
    const BlockResult& r = report.per_block[i];
    if (b.motion == Motion::Rapid) continue;
    s.feed[i] = b.feed;
    const double path = r.path_mm;
    if (!(r.minutes > 0.0) || !(path > 0.0)) continue;  // a block that takes no time keeps its F
    double t = r.minutes;
    if (r.removed_mm3 < o.air_volume_mm3) {
      if (o.air_feed > 0.0) t = path / o.air_feed;
    } else {
      t = std::max(t, r.removed_mm3 / o.max_mrr);
      const double t_slowest = path / o.min_feed;
      if (t > t_slowest) {
        if (t_slowest >= r.minutes) {
          t = t_slowest;
          s.warnings.push_back("block " + std::to_string(r.block) + " (line " + std::to_string(r.line) + "): " +
                               fixed(r.removed_mm3 / t, 1) + " mm3/min at the minimum feed " + fixed(o.min_feed, 1) +
                               " mm/min, above the limit");
        } else {
          t = r.minutes;  // programmed slower than the minimum feed already: left as it is
        }
      }
    }
    // Rounded down to the precision the feed is written with, so the written feed keeps the limit.
    const int decimals = b.feed_mode == FeedMode::InverseTime ? 4 : 2;
    const double scale = std::pow(10.0, decimals);
    const double f = std::floor((b.feed_mode == FeedMode::InverseTime ? 1.0 / t : path / t) * scale) / scale;
    if (fixed(f, decimals) == fixed(b.feed, decimals)) continue;
    if (b.fixed_feed) {
      if (f < b.feed)
        s.warnings.push_back("block " + std::to_string(r.block) + " (line " + std::to_string(r.line) + "): " +
                             fixed(r.removed_mm3 / r.minutes, 1) +
                             " mm3/min, above the limit, left at its feed (a G33/G33.1 move or a subroutine file's block)");
      continue;
    }
    s.feed[i] = f;
    if (f < b.feed) ++s.slowed;
    else ++s.sped_up;
  }
  return s;
}

namespace {

// [begin, end) of the F word in `code` (a line without comments), or npos.
std::pair<size_t, size_t> find_f_word(const std::string& code, size_t from) {
  for (size_t k = from; k < code.size(); ++k) {
    if (code[k] != 'F' && code[k] != 'f') continue;
    size_t e = k + 1;
    while (e < code.size() && (code[e] == ' ' || code[e] == '\t')) ++e;
    const size_t num = e;
    // RS274/NGC ignores blanks inside a number too ("F12. 5" is F12.5): they belong to the word when more
    // of the number follows them.
    auto number_char = [&](size_t i) {
      const bool sign = (code[i] == '+' || code[i] == '-') && e == num;  // a sign only leads
      return std::isdigit(static_cast<unsigned char>(code[i])) || code[i] == '.' || sign;
    };
    for (size_t i = e; i < code.size(); ++i) {
      if (number_char(i)) e = i + 1;
      else if (code[i] != ' ' && code[i] != '\t') break;
    }
    if (e > num) return {k, e};
  }
  return {std::string::npos, std::string::npos};
}

// Rewrites one line: F words outside comments removed, " F<value>" added after the last code character.
std::string rewrite_line(const std::string& line, const std::string& f) {
  // Mask the comments so that an "F" inside one is never touched.
  std::string code = line;
  bool in_paren = false;
  for (size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (in_paren) {
      code[k] = ' ';
      if (c == ')') in_paren = false;
    } else if (c == '(') {
      code[k] = ' ';
      in_paren = true;
    } else if (c == ';') {
      for (size_t m = k; m < line.size(); ++m) code[m] = ' ';
      break;
    }
  }
  std::string out = line;
  for (size_t from = 0;;) {
    auto [b, e] = find_f_word(code, from);
    if (b == std::string::npos) break;
    if (b > 0 && code[b - 1] == ' ') --b;  // the word's separating blank goes with it
    out.erase(b, e - b);
    code.erase(b, e - b);
    from = b;
  }
  // Insert after the last code character (comments are masked as blanks in `code`).
  size_t at = code.size();
  while (at > 0 && (code[at - 1] == ' ' || code[at - 1] == '\t' || code[at - 1] == '\r')) --at;
  out.insert(at, " F" + f);
  return out;
}

}  // namespace

std::string rewrite_feeds(std::string_view text, const Program& program, const FeedSchedule& schedule) {
  auto counted = [&](size_t i) {
    const Block& b = program.blocks[i];
    return b.motion != Motion::Rapid && !b.fixed_feed && b.line > 0 && schedule.feed[i] > 0.0 && b.feed > 0.0;
  };
  // Under G93 one F on a line times all of its blocks together (a spline's chords, an arc's turns), each
  // its share of the programmed minutes: the line's F is the largest that gives every block at least
  // its scheduled time. Under G94 a line takes the smallest of its blocks' feeds.
  std::map<int, double> programmed;  // G93 lines: their programmed minutes (the sum of 1 / F)
  const size_t n = std::min(program.blocks.size(), schedule.feed.size());
  for (size_t i = 0; i < n; ++i)
    if (counted(i) && program.blocks[i].feed_mode == FeedMode::InverseTime) programmed[program.blocks[i].line] += 1.0 / program.blocks[i].feed;
  std::map<int, std::pair<double, int>> per_line;  // line -> (feed, decimals)
  for (size_t i = 0; i < n; ++i) {
    if (!counted(i)) continue;
    const Block& b = program.blocks[i];
    const bool inverse_time = b.feed_mode == FeedMode::InverseTime;
    double f = schedule.feed[i];
    if (inverse_time) f = std::floor(f / b.feed / programmed[b.line] * 1e4) / 1e4;  // share x scheduled F, rounded down
    auto [it, fresh] = per_line.try_emplace(b.line, f, inverse_time ? 4 : 2);
    if (!fresh) it->second.first = std::min(it->second.first, f);
  }
  std::string out;
  out.reserve(text.size() + 8 * per_line.size());
  int line_no = 1;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t nl = text.find('\n', pos);
    const size_t end = nl == std::string_view::npos ? text.size() : nl;
    const std::string line(text.substr(pos, end - pos));
    auto it = per_line.find(line_no);
    out += it == per_line.end() ? line : rewrite_line(line, fixed(it->second.first, it->second.second));
    if (nl == std::string_view::npos) break;
    out += '\n';
    pos = nl + 1;
    ++line_no;
  }
  return out;
}

}  // namespace tf
