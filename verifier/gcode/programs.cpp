// The G-code reader's Fanuc-style subprograms, as LinuxCNC 2.9 runs them (the differences are listed in
// docs/verifier.md): "M98 P1000 L3" runs the program that starts at the line "O1000" (alone on its line)
// three times, each run ended by M99. The subprogram shares the caller's #1 ... #30 (an O-word call gets
// its own) and has its own named parameters; L0 skips the call, no L runs it once. M99 in the main program
// ends it (LinuxCNC's controller would start it over, endlessly: simulated once, with a warning). M98 and
// M99 open their lines: elsewhere in a block LinuxCNC refuses them, and the rest of an M98 line (but P and
// L) is ignored there, as here with a warning.
#include <cctype>
#include <cmath>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

// 98 or 99 when the code line (strip_line's output) opens with M98 or M99 after an optional N number
// (where LinuxCNC reads them as a call or a return), 0 otherwise; `rest` is where the code goes on.
int opening_m_code(const std::string& code, size_t& rest) {
  size_t i = 0;
  if (!code.empty() && code[0] == 'N')
    for (i = 1; i < code.size() && std::isdigit(static_cast<unsigned char>(code[i])); ++i) {
    }
  if (code.compare(i, 3, "M98") != 0 && code.compare(i, 3, "M99") != 0) return 0;
  rest = i + 3;
  if (rest < code.size() && (std::isdigit(static_cast<unsigned char>(code[rest])) || code[rest] == '.')) return 0;
  return code[i + 2] == '8' ? 98 : 99;
}

// A whole count from an M98 word, as rs274 reads one: within 1e-4 of a whole number.
long whole(const Word& w, const std::string& file, int line) {
  const double r = std::round(w.value);
  if (std::abs(w.value - r) > 1e-4) throw InputError(file, line, w.text, "not a whole number");
  return static_cast<long>(r);
}

}  // namespace

// A line opening with M98, or with M99 inside a called program: the call or the return, into `next`. False
// for any other line (M99 in the main program is a stop code of its block).
bool Reader::fanuc_line(const std::string& code, size_t at, size_t& next) {
  size_t rest = 0;
  const int m = opening_m_code(code, rest);
  if (m == 0 || (m == 99 && calls_.empty())) return false;
  const int number = static_cast<int>(at) + 1;
  line_ = number;
  if (m == 98) m98(code, number, next);
  else m99(code.substr(rest), number, next);
  return true;
}

void Reader::m98(const std::string& code, int number, size_t& next) {
  const ParsedLine parsed = parse_line(code, file_, number, *this);
  const Word* p = nullptr;
  const Word* l = nullptr;
  bool call_seen = false, ignored = !parsed.settings.empty();
  for (const Word& w : parsed.words) {
    if (w.letter == 'P' || w.letter == 'L') {
      const Word*& slot = w.letter == 'P' ? p : l;
      if (slot) throw InputError(file_, number, w.text, std::string(1, w.letter) + " given twice on an M98 line");
      slot = &w;
    } else if (w.letter == 'M' && w.value == 98 && !call_seen) {
      call_seen = true;
    } else if (w.letter != 'N') {
      ignored = true;
    }
  }
  if (!p) throw InputError(file_, number, "M98", "M98 without P, the number of the program to call");
  const std::string label = std::to_string(whole(*p, file_, number));
  const long passes = l ? whole(*l, file_, number) : 1;
  if (passes < 0) throw InputError(file_, number, l->text, "a negative repeat count");
  if (passes == 0) return;  // L0: no run, and rs274 does not look for the program
  const auto it = programs_.find(label);
  if (it == programs_.end()) {
    if (subs_.count(label))
      throw InputError(file_, number, p->text, "O" + label + " is an O-word subroutine (O" + label + " SUB): O" + label + " CALL calls it, not M98");
    throw InputError(file_, number, p->text,
                     "no program O" + label + " in this file (M98 runs the lines from \"O" + label + "\" to M99)");
  }
  if (ignored) warn(number, "M98", " line: words other than P and L, and parameter settings, are ignored (as LinuxCNC does)");
  Frame f{next, {}, loops_.size()};
  f.fanuc = true;
  f.start = it->second;
  f.passes_left = passes - 1;
  enter_call(f, number, "M98");
  next = f.start + 1;
}

// `after`: the code after the M99.
void Reader::m99(const std::string& after, int number, size_t& next) {
  Frame& f = calls_.back();
  if (!f.fanuc)
    throw InputError(file_, number, "M99", "M99 in an O-word subroutine: it ends with ENDSUB or RETURN (M99 ends a program M98 ran)");
  if (!after.empty()) throw InputError(file_, number, "M99", "something after M99 on its line (LinuxCNC refuses it)");
  loops_.resize(f.loops);
  value_ = value_returned_ = 0.0;  // rs274 clears both on every M99 return
  if (f.passes_left > 0) {  // the next run: a fresh call, as LinuxCNC runs the M98 line again
    --f.passes_left;
    locals_.back().clear();
    next = f.start + 1;
    return;
  }
  next = f.return_to;
  calls_.pop_back();
  locals_.pop_back();
}

}  // namespace tf::gcode
