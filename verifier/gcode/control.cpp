// The G-code reader's program flow: LinuxCNC's O-words. Subroutines (O100 SUB ... O100 ENDSUB, or
// O<name>) are called with up to 30 bracketed arguments in #1 ... #30 (the rest 0, the caller's restored on
// return); their named parameters belong to the call (names beginning with "_" are global); RETURN or
// ENDSUB [value] leaves the value in #<_value>. IF / ELSEIF / ELSE / ENDIF, WHILE / ENDWHILE, DO / WHILE,
// REPEAT / ENDREPEAT, BREAK and CONTINUE: a label pairs the lines of one construct, as in LinuxCNC.
// Subroutines are found in the program's own file, then O<name> in the file <name>.ngc of the
// subroutine directories (subroutine_files.cpp), as LinuxCNC looks in PROGRAM_PREFIX and SUBROUTINE_PATH.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

constexpr size_t kArguments = 30;

}  // namespace

void Reader::run(const std::vector<std::string_view>& lines) {
  lines_ = lines;
  main_lines_ = lines.size();
  try {
    scan_o_words(0, main_lines_);
    long run_lines = 0;
    for (size_t next = 0; next < lines_.size() && !st_.ended;) {
      const size_t at = next++;
      const int number = static_cast<int>(at) + 1;
      // The program's own lines, and as many again from its loops and calls.
      if (++run_lines > options_.max_lines_run + static_cast<long>(main_lines_))
        throw InputError(file_, number, "", "more than " + std::to_string(options_.max_lines_run) +
                                               " lines run beyond the program's own (GcodeOptions::max_lines_run): a loop that does not end?");
      const std::optional<std::string> code = code_of(lines_[at], number);
      if (code && !code->empty()) {
        if (o_lines_[at]) {
          line_ = number;
          const OLine o = *o_lines_[at];  // a copy: a call may read a subroutine file, which grows o_lines_
          control(o, at, next);
          // rs274 reads the lines a condition, a loop's end or a definition skips (a line too long there
          // stops it), but not those a call or a return jumps over.
          const std::string& k = o.word.keyword;
          if (next > at + 1 && k != "CALL" && k != "RETURN" && k != "ENDSUB")
            for (size_t i = at + 1; i < next; ++i) check_length(lines_[i], static_cast<int>(i) + 1);
        } else if (!fanuc_line(*code, at, next)) {
          execute(*code, number);
        }
      }
      if (next == at + 1 && next == source_end(at)) break;  // the end of the program's file (or a subroutine file's)
    }
    // A program M98 ran that reaches the end of the file without M99 or a program end: the caller's rest
    // would go unread (rs274: "File ended with no percent sign or program end").
    for (const Frame& f : calls_)
      if (f.fanuc && !st_.ended)
        throw InputError(file_, static_cast<int>(f.return_to), "M98",
                         "the program it runs (line " + std::to_string(f.start + 1) + ") reaches the end of the file without M99");
  } catch (const InputError& e) {
    throw in_source(e);
  }
}

// Every O-word line, each subroutine's SUB and ENDSUB lines (a program may call a subroutine defined
// further down) and each Fanuc-style program's "O1000" line (the first, as rs274 finds it). A line that
// cannot be read is left to the run, which reports it if it gets there, unless the scan finds an error
// further down: then that line's is the error.
void Reader::scan_o_words(size_t begin, size_t end) {
  o_lines_.resize(lines_.size());
  std::optional<std::pair<std::string, size_t>> open;  // the subroutine being defined: label, line
  int percent = 0;
  // A line that cannot be read comes before a scan error further down: rs274 stops at it first.
  std::optional<InputError> unreadable;
  auto fail = [&](int number, const std::string& field, const std::string& what) {
    if (unreadable) throw *unreadable;
    throw InputError(file_, number, field, what);
  };
  for (size_t i = begin; i < end && percent < 2; ++i) {
    std::string_view view = lines_[i];
    while (!view.empty() && std::isspace(static_cast<unsigned char>(view.front()))) view.remove_prefix(1);
    if (!view.empty() && view.front() == '/') {
      if (options_.block_delete) continue;
      view.remove_prefix(1);
    }
    if (!view.empty() && view.front() == '%') {
      ++percent;
      continue;
    }
    std::string code;
    try {
      code = strip_line(view, file_, static_cast<int>(i) + 1);
    } catch (const InputError& e) {
      if (!unreadable) unreadable = e;
      continue;
    }
    const std::optional<OWord> o = o_word(code);
    if (!o) {
      if (const std::optional<std::string> n = program_number(code)) {
        if (open)  // rs274: a nested definition
          fail(static_cast<int>(i) + 1, "O" + *n, "a program number inside subroutine O" + open->first);
        programs_.emplace(*n, i);
      }
      continue;
    }
    const int number = static_cast<int>(i) + 1;
    if (o->keyword == "SUB") {
      if (open) fail(number, o->name(), "a subroutine defined inside another (O" + open->first + ")");
      if (subs_.count(o->label)) fail(number, o->name(), "subroutine defined twice");
      open = {o->label, i};
    } else if (o->keyword == "ENDSUB") {
      if (!open || open->first != o->label) fail(number, o->name(), "ENDSUB without its SUB");
      subs_[o->label] = {open->second, i};
      open.reset();
    }
    o_lines_[i] = OLine{*o, code};
  }
  if (open) fail(static_cast<int>(open->second) + 1, "O" + open->first, "subroutine without its ENDSUB");
}

void Reader::control(const OLine& o, size_t at, size_t& next) {
  const int number = static_cast<int>(at) + 1;
  const std::string& k = o.word.keyword;
  if (k == "SUB") {
    next = subs_.at(o.word.label).end + 1;  // a definition is not run where it stands
  } else if (k == "CALL") {
    call(o, number, next);
  } else if (k == "ENDSUB" || k == "RETURN") {
    return_from(o, number, next);
  } else if (k == "IF") {
    if (condition(o, number)) return;
    // On to the first branch whose condition holds, the ELSE, or the ENDIF.
    for (size_t j = at;;) {
      j = find_o_word(j, o.word, {"ELSEIF", "ELSE", "ENDIF"});
      const OLine& branch = *o_lines_[j];
      if (branch.word.keyword != "ELSEIF" || condition(branch, static_cast<int>(j) + 1)) {
        next = j + 1;
        return;
      }
    }
  } else if (k == "ELSEIF" || k == "ELSE") {
    next = find_o_word(at, o.word, {"ENDIF"}) + 1;  // an earlier branch ran
  } else if (k == "DO") {
    loops_.push_back({o.word.label, LoopKind::Do, at + 1, 0});
  } else if (k == "WHILE") {
    const size_t base = calls_.empty() ? 0 : calls_.back().loops;
    if (loops_.size() > base && loops_.back().kind == LoopKind::Do && loops_.back().label == o.word.label) {
      if (condition(o, number)) next = loops_.back().head;  // the end of a DO loop
      else loops_.pop_back();
    } else if (condition(o, number)) {
      loops_.push_back({o.word.label, LoopKind::While, at, 0});
    } else {
      next = find_o_word(at, o.word, {"ENDWHILE"}) + 1;
    }
  } else if (k == "REPEAT") {
    const std::vector<double> v = o_word_values(o.code, o.word, file_, number, *this);
    if (v.size() != 1) throw InputError(file_, number, o.word.name(), "REPEAT takes one count: REPEAT [n]");
    const long n = std::lrint(v[0]);  // to the nearest whole count, halves to even (rs274: 2.5 is 2, 2.7 is 3)
    if (n <= 0) next = find_o_word(at, o.word, {"ENDREPEAT"}) + 1;
    else loops_.push_back({o.word.label, LoopKind::Repeat, at + 1, n});
  } else if (k == "ENDWHILE" || k == "ENDREPEAT") {
    loop_end(o, number, next);
  } else if (k == "BREAK" || k == "CONTINUE") {
    break_or_continue(o, at, next);
  }
  // ENDIF: nothing to do.
}

void Reader::call(const OLine& o, int number, size_t& next) {
  if (!subs_.count(o.word.label)) {
    if (programs_.count(o.word.label))
      throw InputError(file_, number, o.word.name(), "a Fanuc-style program (" + o.word.name() + " ... M99): M98 P" + o.word.label + " calls it");
    if (!load_subroutine_file(o.word.label, number)) {
      std::string what = "subroutine not defined in this file nor found as a file in";
      for (const std::filesystem::path& dir : options_.subroutine_dirs) what.append(" ").append((dir / "").string());
      if (options_.subroutine_dirs.empty()) what.append(" no subroutine directory (none given)");
      throw InputError(file_, number, o.word.name(), what);
    }
  }
  const auto it = subs_.find(o.word.label);
  const std::vector<double> args = o_word_values(o.code, o.word, file_, number, *this);  // in the caller's scope
  if (args.size() > kArguments) throw InputError(file_, number, o.word.name(), "more than 30 arguments");
  Frame f{next, {}, loops_.size()};
  std::copy_n(numbered_.begin(), f.saved.size(), f.saved.begin());
  enter_call(f, number, o.word.name());
  for (size_t k = 1; k <= kArguments; ++k) numbered_[k] = k <= args.size() ? args[k - 1] : 0.0;
  next = it->second.begin + 1;
}

// A new call level (an O-word call or M98): its frame and its own named parameters.
void Reader::enter_call(const Frame& f, int number, const std::string& field) {
  if (calls_.size() >= kMaxCallDepth)
    throw InputError(file_, number, field, "subroutine calls nested more than 9 deep (LinuxCNC's limit; a recursion that does not end?)");
  calls_.push_back(f);
  locals_.emplace_back();
}

void Reader::return_from(const OLine& o, int number, size_t& next) {
  if (calls_.empty()) throw InputError(file_, number, o.word.name(), o.word.keyword + " outside a subroutine call");
  if (calls_.back().fanuc)
    throw InputError(file_, number, o.word.name(), o.word.keyword + " in a program M98 ran: it ends with M99");
  const std::vector<double> v = o_word_values(o.code, o.word, file_, number, *this);
  if (v.size() > 1) throw InputError(file_, number, o.word.name(), "a subroutine returns one value");
  value_returned_ = v.empty() ? 0.0 : 1.0;
  value_ = v.empty() ? 0.0 : v[0];  // rs274 clears it on a return without a value
  const Frame f = calls_.back();
  calls_.pop_back();
  locals_.pop_back();
  std::copy_n(f.saved.begin(), f.saved.size(), numbered_.begin());
  loops_.resize(f.loops);
  next = f.return_to;
}

void Reader::loop_end(const OLine& o, int number, size_t& next) {
  const size_t base = calls_.empty() ? 0 : calls_.back().loops;
  const LoopKind kind = o.word.keyword == "ENDWHILE" ? LoopKind::While : LoopKind::Repeat;
  if (loops_.size() <= base || loops_.back().label != o.word.label || loops_.back().kind != kind)
    throw InputError(file_, number, o.word.name(), o.word.keyword + " without its " +
                                                       (kind == LoopKind::While ? "WHILE" : "REPEAT"));
  Loop& l = loops_.back();
  if (kind == LoopKind::While) {
    next = l.head;  // the WHILE, which tests again
    loops_.pop_back();
  } else if (--l.remaining > 0) {
    next = l.head;
  } else {
    loops_.pop_back();
  }
}

// BREAK leaves the loop of its label (and any inside it); CONTINUE goes on to its next pass.
void Reader::break_or_continue(const OLine& o, size_t at, size_t& next) {
  const size_t base = calls_.empty() ? 0 : calls_.back().loops;
  size_t i = loops_.size();
  while (i > base && loops_[i - 1].label != o.word.label) --i;
  if (i == base)
    throw InputError(file_, static_cast<int>(at) + 1, o.word.name(), o.word.keyword + " outside a loop of this label");
  loops_.resize(i);
  const bool leave = o.word.keyword == "BREAK";
  const LoopKind kind = loops_.back().kind;
  if (kind == LoopKind::Repeat)  // rs274 refuses them there too
    throw InputError(file_, static_cast<int>(at) + 1, o.word.name(), o.word.keyword + " in a REPEAT loop (only WHILE and DO)");
  if (kind == LoopKind::While) {
    next = leave ? find_o_word(at, o.word, {"ENDWHILE"}) + 1 : loops_.back().head;
    loops_.pop_back();  // CONTINUE: the WHILE opens it again if its condition holds
    return;
  }
  if (leave) {
    loops_.pop_back();
    next = find_o_word(at, o.word, {"WHILE"}) + 1;
    return;
  }
  // CONTINUE in a DO loop goes on at the next line of its label, which rs274 then runs: DO's WHILE tests
  // its condition, but a BREAK of the loop on the way (inside an IF not taken) leaves it. LinuxCNC's
  // machines run that way; the reader had followed the text (black-box testing against rs274).
  next = find_o_word(at, o.word, {"WHILE", "BREAK", "CONTINUE"});
}

bool Reader::condition(const OLine& o, int number) {
  line_ = number;
  const std::vector<double> v = o_word_values(o.code, o.word, file_, number, *this);
  if (v.size() != 1)
    throw InputError(file_, number, o.word.name(), o.word.keyword + " takes one condition: " + o.word.keyword + " [...]");
  return v[0] != 0.0;
}

// The first line after `from` with o's label and one of the keywords.
size_t Reader::find_o_word(size_t from, const OWord& o, std::initializer_list<std::string_view> keywords) const {
  for (size_t j = from + 1; j < source_end(from); ++j)
    if (o_lines_[j] && o_lines_[j]->word.label == o.label &&
        std::find(keywords.begin(), keywords.end(), o_lines_[j]->word.keyword) != keywords.end())
      return j;
  throw InputError(file_, static_cast<int>(from) + 1, o.name(),
                   o.keyword + " without its " + std::string(*(keywords.end() - 1)));
}

}  // namespace tf::gcode
