// Feed scheduling from per-block removal, and the F-word rewrite of a G-code text.
#include "tiltfield/engagement/feed_schedule.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf {
namespace {

// How an F word is written: G93 in 1/min with 4 decimals; G94 in mm/min with 2, or under G20 in inch/min
// with 4 (0.0001 in/min is 0.00254 mm/min). `unit`: mm/min (or 1/min) per written unit.
struct WrittenFeed {
  int decimals;
  double scale;  // 10^decimals
  double unit;
};
WrittenFeed written_feed(bool inverse_time, bool inch) {
  if (inverse_time) return {4, 1e4, 1.0};
  return inch ? WrittenFeed{4, 1e4, 25.4} : WrittenFeed{2, 1e2, 1.0};
}
WrittenFeed written_feed(const Block& b) { return written_feed(b.feed_mode == FeedMode::InverseTime, b.inch); }

}  // namespace

void check_feed_schedule_options(const FeedScheduleOptions& o, const std::string& limit_option) {
  if (!(o.max_mrr > 0.0) || !std::isfinite(o.max_mrr))
    throw InputError("", 0, limit_option, "must be a positive number of mm3/min");
  // Beyond any machine's feed, as the machine file's max_feed: a feed of 1e300 had been written as a
  // 300-digit F that neither LinuxCNC nor the reader takes (black-box testing).
  constexpr double kMaxFeed = 1e6;
  if (!(o.min_feed > 0.0 && o.min_feed <= kMaxFeed))
    throw InputError("", 0, "--min-feed", "must be a positive number of mm/min, at most 1000000");
  if (o.air_feed != 0.0 && !(o.air_feed > 0.0 && o.air_feed <= kMaxFeed))
    throw InputError("", 0, "--air-feed", "must be a positive number of mm/min, at most 1000000");
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
    // A block the limits leave alone keeps its F: recomputed from its path and time a 500 had come back
    // as 499.99999... and been written 499.99 (black-box testing).
    if (t == r.minutes) continue;
    // Rounded down to the precision the feed is written with, in the program's units, so the written
    // feed keeps the limit (less a billionth for the division's rounding: an air feed of 3000 stays 3000).
    const WrittenFeed w = written_feed(b);
    const double exact = (b.feed_mode == FeedMode::InverseTime ? 1.0 / t : path / t) / w.unit * w.scale;
    double f = std::floor(exact * (1.0 + 1e-9)) / w.scale * w.unit;
    // The minimum feed is written at least (10 mm/min rounded down in inches would read 9.99998).
    if (b.feed_mode != FeedMode::InverseTime && f < o.min_feed && path / t >= o.min_feed * (1 - 1e-12))
      f = std::ceil(o.min_feed / w.unit * w.scale) / w.scale * w.unit;
    if (fixed(f / w.unit, w.decimals) == fixed(b.feed / w.unit, w.decimals)) continue;
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
  const auto fixed_blocks = std::count_if(program.blocks.begin(), program.blocks.end(),
                                          [](const Block& b) { return b.fixed_feed && b.motion != Motion::Rapid; });
  if (fixed_blocks > 0)
    s.warnings.push_back(std::to_string(fixed_blocks) + " feed blocks (G33/G33.1, or subroutine files') are not rescheduled; a " +
                         "subroutine file's block without its own F runs at the F in force, which the rewritten lines before its call set");
  // A line run under both G93 and G94, or both G20 and G21 (a subroutine's), takes no one F: it keeps its own.
  std::map<int, int> modes;  // line -> bit 1 G94, bit 2 G93, bit 4 G94 under G20
  for (const Block& b : program.blocks)
    if (b.motion != Motion::Rapid && b.line > 0)
      modes[b.line] |= b.feed_mode == FeedMode::InverseTime ? 2 : b.inch ? 4 : 1;
  for (const auto& [line, m] : modes)
    if (m == 3 || m == 6 || m == 7)
      s.warnings.push_back("line " + std::to_string(line) + " runs under both G93 and G94: its F is left as it is");
    else if (m == 5)
      s.warnings.push_back("line " + std::to_string(line) + " runs under both G20 and G21: its F is left as it is");
  return s;
}

namespace {

constexpr size_t npos = std::string::npos;

bool blank(char c) { return c == ' ' || c == '\t'; }
size_t skip_blanks(const std::string& code, size_t k) {
  while (k < code.size() && blank(code[k])) ++k;
  return k;
}
// After the ']' that closes the '[' at k, or npos.
size_t bracket_end(const std::string& code, size_t k) {
  int depth = 0;
  for (; k < code.size(); ++k) {
    if (code[k] == '[') ++depth;
    else if (code[k] == ']' && --depth == 0) return k + 1;
  }
  return npos;
}
// After the number at k (RS274/NGC ignores blanks inside a number: "F12. 5" is F12.5, so they belong to it
// when more of the number follows), or k when there is none.
size_t number_end(const std::string& code, size_t k) {
  size_t e = k;
  for (size_t i = k; i < code.size(); ++i) {
    const bool sign = (code[i] == '+' || code[i] == '-') && e == k;  // a sign only leads
    if (std::isdigit(static_cast<unsigned char>(code[i])) || code[i] == '.' || sign) e = i + 1;
    else if (!blank(code[i])) break;
  }
  return e;
}
// After the real value at k: a number, a parameter (#1, ##2, #<name>, #[...]), an expression [...] or a
// unary function NAME[...] (ATAN[...]/[...]); k when there is none. A feed written as a parameter had
// kept its word beside the new one ("F#1 F455.19", which LinuxCNC refuses, black-box testing).
size_t value_end(const std::string& code, size_t k) {
  k = skip_blanks(code, k);
  if (k >= code.size()) return k;
  if (code[k] == '[') return std::min(bracket_end(code, k), code.size());
  if (code[k] == '#') {
    size_t m = k;
    while (m < code.size() && (code[m] == '#' || blank(code[m]))) ++m;
    if (m < code.size() && code[m] == '<') {
      const size_t close = code.find('>', m);
      return close == npos ? code.size() : close + 1;
    }
    return value_end(code, m);  // #1, #[...], #ABS[...]: the parameter's number is itself a value
  }
  if (std::isalpha(static_cast<unsigned char>(code[k]))) {
    size_t m = k;
    while (m < code.size() && std::isalpha(static_cast<unsigned char>(code[m]))) ++m;
    m = skip_blanks(code, m);
    if (m >= code.size() || code[m] != '[') return k;
    size_t e = std::min(bracket_end(code, m), code.size());
    const size_t slash = skip_blanks(code, e);  // ATAN[y]/[x]
    if (slash < code.size() && code[slash] == '/') {
      const size_t open = skip_blanks(code, slash + 1);
      if (open < code.size() && code[open] == '[') e = std::min(bracket_end(code, open), code.size());
    }
    return e;
  }
  return number_end(code, k);
}

// [begin, end) of the F word in `code` (a line without comments, names of parameters masked), or npos.
std::pair<size_t, size_t> find_f_word(const std::string& code, size_t from) {
  for (size_t k = from; k < code.size(); ++k) {
    if (code[k] != 'F' && code[k] != 'f') continue;
    // FIX[...] and FUP[...] are functions, not words.
    const size_t next = skip_blanks(code, k + 1);
    if (next < code.size() && std::isalpha(static_cast<unsigned char>(code[next]))) {
      size_t m = next;
      while (m < code.size() && std::isalpha(static_cast<unsigned char>(code[m]))) ++m;
      const size_t open = skip_blanks(code, m);
      if (open < code.size() && code[open] == '[' && m - next == 2) {
        const char a = static_cast<char>(std::toupper(static_cast<unsigned char>(code[next])));
        const char b = static_cast<char>(std::toupper(static_cast<unsigned char>(code[next + 1])));
        if ((a == 'I' && b == 'X') || (a == 'U' && b == 'P')) {
          k = m - 1;
          continue;
        }
      }
    }
    const size_t e = value_end(code, k + 1);
    if (e > skip_blanks(code, k + 1)) return {k, e};
  }
  return {npos, npos};
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
    } else if (c == '<') {  // a parameter's name: its letters are no words
      for (++k; k < line.size() && line[k] != '>'; ++k) code[k] = '_';
      if (k == line.size()) break;
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

namespace {
// `v` with at most `places` decimals, trailing zeros (and a bare point) dropped.
std::string trimmed(double v, int places) {
  std::string s = fixed(v, places);
  if (s.find('.') == std::string::npos) return s;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}
}  // namespace

std::string rewrite_feeds(std::string_view text, const Program& program, const FeedSchedule& schedule) {
  // Per line, over every run of it (loops, calls): G94, the smallest of its blocks' feeds; G93, where one F
  // times a line's blocks together (an arc's P turns), the largest F that gives each at least its scheduled
  // time: its scheduled F times its share of the line's minutes. Every feed line gets its F written (F is
  // modal: a line left without one would run at the F of the line before it), but a line that runs under
  // both G93 and G94 (a subroutine's), which is left as it is (schedule_feeds warns).
  struct Line {
    double feed = 0.0;
    bool inverse_time = false, inch = false, mixed = false;
    bool kept = true;  // every block of the line keeps its programmed F
  };
  std::map<int, Line> per_line;
  for (size_t i = 0; i < program.blocks.size() && i < schedule.feed.size(); ++i) {
    const Block& b = program.blocks[i];
    if (b.motion == Motion::Rapid || b.fixed_feed || b.line <= 0 || !(schedule.feed[i] > 0.0)) continue;
    const bool inverse_time = b.feed_mode == FeedMode::InverseTime;
    const double f = inverse_time ? schedule.feed[i] * b.time_share : schedule.feed[i];
    const bool inch = b.inch && !inverse_time;
    auto [it, fresh] = per_line.try_emplace(b.line, Line{f, inverse_time, inch});
    Line& l = it->second;
    if (!fresh) l.feed = std::min(l.feed, f);
    l.mixed |= l.inverse_time != inverse_time || l.inch != inch;
    l.kept &= schedule.feed[i] == b.feed;
  }
  std::string out;
  out.reserve(text.size() + 8 * per_line.size());
  int line_no = 1;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t nl = text.find('\n', pos);
    const size_t end = nl == std::string_view::npos ? text.size() : nl;
    const std::string line(text.substr(pos, end - pos));
    const auto it = per_line.find(line_no);
    if (it == per_line.end() || it->second.mixed) {
      out += line;
    } else {  // rounded down to what is written (+1e-6 of a digit: a share's own rounding costs none)
      const Line& l = it->second;
      const WrittenFeed w = written_feed(l.inverse_time, l.inch);
      // A line the schedule left alone keeps its F's digits (F123.456 had been cut to F123.45 under a limit
      // no block reached; black-box testing): up to 6 places, trailing zeros dropped.
      out += rewrite_line(line, l.kept ? trimmed(l.feed / w.unit, 6)
                                       : fixed(std::floor(l.feed / w.unit * w.scale + 1e-6) / w.scale, w.decimals));
    }
    if (nl == std::string_view::npos) break;
    out += '\n';
    pos = nl + 1;
    ++line_no;
  }
  return out;
}

}  // namespace tf
