// The G-code reader's subroutine files: a call of O<name> (or O100) that the program does not define runs
// the subroutine of the file <name>.ngc (100.ngc; the name in lower case, as LinuxCNC stores it) from the first of
// GcodeOptions::subroutine_dirs that has one, as LinuxCNC looks in its PROGRAM_PREFIX and SUBROUTINE_PATH.
// The file's lines from "O<name> SUB" to its ENDSUB are appended to the program's lines the first time it
// is called (what else the file holds is not run, as in LinuxCNC), so that the call, the loops and the
// returns work as for a subroutine of the program itself; errors and warnings name the file and its line,
// and the blocks it makes carry the line of the program's call.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::gcode {

bool Reader::load_subroutine_file(const std::string& label, int number) {
  // O<name>: name.ngc; a numbered O100: 100.ngc (LinuxCNC looks for both).
  std::string name = label.front() == '<' ? label.substr(1, label.size() - 2) : label;
  if (name.empty()) return false;
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::filesystem::path path;
  for (const std::filesystem::path& dir : options_.subroutine_dirs) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(dir / (name + ".ngc"), ec)) {
      path = dir / (name + ".ngc");
      break;
    }
  }
  if (path.empty()) return false;
  const std::string file = path.string();
  file_texts_.push_back(read_text_file(path, "subroutine file"));
  const std::vector<std::string_view> lines = split_lines(file_texts_.back());
  // Its SUB and ENDSUB lines.
  size_t sub = lines.size(), endsub = lines.size();
  for (size_t i = 0; i < lines.size() && endsub == lines.size(); ++i) {
    const std::optional<OWord> o = o_word(strip_line(lines[i], file, static_cast<int>(i) + 1));
    if (!o || o->label != label) continue;
    if (o->keyword == "SUB" && sub == lines.size()) sub = i;
    else if (o->keyword == "ENDSUB" && sub < lines.size()) endsub = i;
  }
  if (endsub == lines.size())  // at the call (the caller maps a subroutine file's line to its own)
    throw InputError(file_, number, "O" + label, "the subroutine file " + file + " holds no O" + label + " SUB ... ENDSUB");
  const size_t begin = lines_.size();
  lines_.insert(lines_.end(), lines.begin() + static_cast<std::ptrdiff_t>(sub), lines.begin() + static_cast<std::ptrdiff_t>(endsub) + 1);
  sources_.push_back({begin, lines_.size(), file, static_cast<int>(sub) + 1});
  scan_o_words(begin, lines_.size());
  return true;
}

std::pair<std::string, int> Reader::source_of(int number) const {
  const size_t at = static_cast<size_t>(std::max(number, 1)) - 1;
  if (at < main_lines_) return {file_, number};
  for (const Source& s : sources_)
    if (at >= s.begin && at < s.end) return {s.file, s.first_line + static_cast<int>(at - s.begin)};
  return {file_, number};
}

InputError Reader::in_source(const InputError& e) const {
  if (e.file() != file_ || e.line() <= static_cast<int>(main_lines_)) return e;
  const auto [file, line] = source_of(e.line());
  return InputError(file, line, e.field(), e.reason());
}

std::string Reader::line_name(int number) const {
  if (number <= static_cast<int>(main_lines_)) return "line " + std::to_string(number);
  const auto [file, line] = source_of(number);
  return file + ":" + std::to_string(line);
}

size_t Reader::source_end(size_t at) const {
  if (at < main_lines_) return main_lines_;
  for (const Source& s : sources_)
    if (at >= s.begin && at < s.end) return s.end;
  return lines_.size();
}

// A block made by a line of a subroutine file carries the line of the program's call that led there: the
// innermost call made from the program's own lines (a frame's return_to is the line after its call).
int Reader::block_line(int number) const {
  if (number <= static_cast<int>(main_lines_)) return number;
  for (auto f = calls_.rbegin(); f != calls_.rend(); ++f)
    if (f->return_to <= main_lines_) return static_cast<int>(f->return_to);
  return number;
}

}  // namespace tf::gcode
